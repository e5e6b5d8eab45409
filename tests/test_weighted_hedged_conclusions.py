"""A weight on a rule whose conclusion is hedged by seldom or fuzzylite's extremely (no power):
fuzzylite 6 and pyfuzzylite 8 hedge the weighted activation, h(w a) (pyfuzzylite rule.py:
Rule.activate_with takes weight * antecedent, Consequent.modify then applies the
conclusion's hedges), which the model keeps as a CondOp.WEIGHT step inside the hedge (it was
refused).  Numbers by hand and the tools' own (measured with the fuzzylite 6 CLI and
pyfuzzylite 8.0.6 on the FLL text below)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fll, write_fll, write_fz
from fuzzyc.formats.tool_semantics import Chain
from fuzzyc.language.parser import parse
from fuzzyc.semantics.model import CondOp

FLL = """Engine: w
InputVariable: x
  range: 0.000 1.000
  term: a Triangle 0.000 0.000 1.000
OutputVariable: y
  range: 0.000 5.000
  aggregation: none
  defuzzifier: WeightedSum TakagiSugeno
  default: nan
  term: b Constant 3.000
RuleBlock: rules
  conjunction: Minimum
  disjunction: Maximum
  implication: AlgebraicProduct
  rule: if x is a then y is {hedge} b with 0.5
"""

FCL = """FUNCTION_BLOCK w
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY x
  RANGE := (0.000 .. 1.000);
  TERM a := Triangle 0.000 0.000 1.000;
END_FUZZIFY
DEFUZZIFY y
  RANGE := (0.000 .. 5.000);
  TERM b := 3.000;
  METHOD : COGS;
  DEFAULT := nan;
END_DEFUZZIFY
RULEBLOCK rules
  AND : MIN;
  ACT : PROD;
  RULE 1 : if x is a then y is {hedge} b with 0.5;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def seldom(v: float) -> float:          # fuzzylite's Seldom
    return math.sqrt(0.5 * v) if v <= 0.5 else 1 - math.sqrt(0.5 * (1 - v))


def s_curve(v: float) -> float:         # fuzzylite's Extremely
    return 2 * v * v if v <= 0.5 else 1 - 2 * (1 - v) ** 2


# x = 0.2: a = 1 - 0.2 = 0.8, weighted 0.4; the rule's value 3 times its activation
# (WeightedSum; COGS of one rule is the value itself, so FCL checks the activation's rule
# through the fuzzylite semantics' weighted average = 3 and the FLL sum carries the number)
CASES = {"seldom": 3 * seldom(0.4),          # sqrt(0.2) * 3 = 1.3416407865 (not 0.5 seldom(0.8):
                                             # 0.5 * (1 - sqrt(0.1)) * 3 = 1.0257)
         "extremely": 3 * s_curve(0.4)}       # 2 * 0.16 * 3 = 0.96 (not 0.5 * 0.92 * 3 = 1.38)


def test_the_hand_numbers_are_the_tools():
    # measured: `fuzzylite -i w.fll -d x.fld -o y.fld -of fld` gives 1.342; pyfuzzylite 8.0.6's
    # FllImporter engine gives 1.34164079 at x = 0.2
    assert CASES["seldom"] == pytest.approx(1.34164079, abs=1e-8)
    assert CASES["extremely"] == pytest.approx(0.96, abs=1e-15)


@pytest.mark.parametrize("hedge", sorted(CASES))
@pytest.mark.parametrize("semantics", ["exact", "fuzzylite", "pyfuzzylite"])
def test_fll_weighs_the_activation_before_the_hedge(hedge, semantics):
    model = read_fll(FLL.format(hedge=hedge), "w.fll")
    rb = model.rulebase
    assert rb.weights.tolist() == [1.0]              # the weight is in the program
    assert CondOp.WEIGHT in rb.conditions[0][:, 0]
    y = Chain(model).evaluate(np.array([[0.2]]), semantics)
    assert y[0, 0] == pytest.approx(CASES[hedge], rel=1e-14)


@pytest.mark.parametrize("hedge", sorted(CASES))
def test_fcl_reads_it_so_too(hedge):
    model = read_fcl(FCL.format(hedge=hedge), "w.fcl")
    assert CondOp.WEIGHT in model.rulebase.conditions[0][:, 0]
    # COGS: a weighted average of one rule gives its value; the activation is the hand one
    from fuzzyc.engine.inference import activations
    act = activations(model.rulebase, np.array([[0.2]]))
    assert act[0, 0] == pytest.approx(CASES[hedge] / 3, rel=1e-14)


def test_power_hedges_keep_the_weight_as_w_to_the_p():
    """very(w a) = w^2 very(a): the rule stays a weight (0.5^2) on its hedged clause."""
    rb = read_fll(FLL.format(hedge="very"), "w.fll").rulebase
    assert rb.weights.tolist() == [0.25]
    assert not rb.conditions


def test_fll_refuses_to_write_it_by_rule_and_fz_says_it():
    model = read_fll(FLL.format(hedge="seldom"), "w.fll")
    with pytest.raises(FuzzycError, match="rule 1 weighs its activation before a hedge"):
        write_fll(model, [])
    text = write_fz(model)
    assert "rule if seldom (0.5 * (x is a)) then y is b" in text
    back = parse(text, "w.fz")
    np.testing.assert_array_equal(back.rulebase.conditions[0], model.rulebase.conditions[0])
    x = np.array([[0.2]])
    assert Chain(back).evaluate(x)[0, 0] == Chain(model).evaluate(x)[0, 0]


def test_fuzzylite6_fires_on_the_weighted_activation_before_the_hedge():
    """fuzzylite 6's Rule::trigger tests the weighted activation against its 1e-6, then
    Consequent::modify hedges it: x = 0.999, a = 0.001, w a = 0.0005 fires; extremely(0.0005)
    = 2 * 0.0005^2 = 5e-7, below 1e-6, is what the rule adds: y = 3 * 5e-7 = 1.5e-6 (the CLI,
    `-decimals 12`: 0.000001500000; the hedged value tested instead gave no rule fired, NaN)."""
    model = read_fll(FLL.format(hedge="extremely"), "w.fll")
    for semantics in ("fuzzylite", "pyfuzzylite", "exact"):
        y = Chain(model).evaluate(np.array([[0.999]]), semantics)[0, 0]
        assert y == pytest.approx(3 * 2 * 0.0005 ** 2, rel=1e-12), semantics
