"""Rule blocks read from fuzzylite's files.  Chained rules (SimpleDimmerChained): a rule that
reads an output goes to a rule block after the rules concluding it.  fuzzyc reads the output's
value through its terms (as a MATLAB FIS tree does); fuzzylite reads the term's activation in
the output's fuzzy set, which `--semantics fuzzylite` reproduces.  Hybrid FCL: a RULEBLOCK
each, a METHOD per output.  Hand-computed values."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fll
from fuzzyc.formats.tool_semantics import Chain
from fuzzyc.semantics.model import Defuzzifier

# x = 0.25: low = 1 - x = 0.75, high = x = 0.25.
# y: max(min(0.75, a), min(0.25, b)) = 0.75 on [0, 0.5], 0.25 on (0.5, 1]; centroid
#   (0.75 * 0.5 * 0.25 + 0.25 * 0.5 * 0.75) / (0.75 * 0.5 + 0.25 * 0.5) = 0.1875 / 0.5 = 0.375
#   (fuzzylite's 100 midpoints split at 0.5 as well: the same 0.375).
# z exact: y = 0.375 is a (rectangle [0, 0.5]) fully, b not: z = (1 * 1) / 1 = 1.
# z fuzzylite: `y is a` is a's activation 0.75, `y is b` 0.25: z = (0.75 * 1 + 0.25 * 0) / 1.
CHAINED_FLL = """Engine: chained
InputVariable: x
  range: 0 1
  term: low Ramp 1 0
  term: high Ramp 0 1
OutputVariable: y
  range: 0 1
  aggregation: Maximum
  defuzzifier: Centroid 100
  default: nan
  term: a Rectangle 0 0.5
  term: b Rectangle 0.5 1
OutputVariable: z
  range: 0 1
  aggregation: Maximum
  defuzzifier: WeightedAverage
  default: nan
  term: c Constant 0
  term: d Constant 1
RuleBlock:
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  rule: if x is low then y is a
  rule: if x is high then y is b
  rule: if y is a then z is d
  rule: if y is b then z is c
"""

# the FCL head both tests share: y's terms are rectangles, z's singletons
FCL_HEAD = """FUNCTION_BLOCK chained
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; z : REAL; END_VAR
FUZZIFY x
  RANGE := (0 .. 1);
  TERM low := Ramp 1 0;
  TERM high := Ramp 0 1;
END_FUZZIFY
DEFUZZIFY y
  RANGE := (0 .. 1);
  TERM a := Rectangle 0 0.5;
  TERM b := Rectangle 0.5 1;
  METHOD : COG;
  ACCU : MAX;
  DEFAULT := nan;
END_DEFUZZIFY
DEFUZZIFY z
  RANGE := (0 .. 1);
  TERM c := 0;
  TERM d := 1;
"""
Y_RULES = """  AND : MIN;
  ACT : MIN;
  RULE 1 : if x is low then y is a;
  RULE 2 : if x is high then y is b;
"""
CHAINED_FCL = FCL_HEAD + """  METHOD : COG;
  ACCU : MAX;
  DEFAULT := nan;
END_DEFUZZIFY
RULEBLOCK rules
""" + Y_RULES + """  RULE 3 : if y is a then z is d;
  RULE 4 : if y is b then z is c;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""
# fuzzylite's hybrid FCL: a METHOD per DEFUZZIFY and a RULEBLOCK per output with its own AND.
# x = 0.25: y as above, 0.375; z (COGS without ACCU: the weighted average over the rules):
# (0.75 * 1 + 0.25 * 0) / 1 = 0.75.
HYBRID_FCL = FCL_HEAD + """  METHOD : COGS;
END_DEFUZZIFY
RULEBLOCK mamdani
""" + Y_RULES + """END_RULEBLOCK
RULEBLOCK sugeno
  AND : PROD;
  RULE 1 : if x is low then z is d;
  RULE 2 : if x is high then z is c;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


@pytest.mark.parametrize("model", [read_fll(CHAINED_FLL, "chained.fll"),
                                   read_fcl(CHAINED_FCL, "chained.fcl")],
                         ids=["fll", "fcl"])
def test_chained_rules_make_a_second_block_reading_the_output(model):
    assert [[v.name for v in rb.outputs] for rb in model.blocks] == [["y"], ["z"]]
    assert [v.name for v in model.blocks[1].inputs] == ["x", "y"]
    chain = Chain(model)
    np.testing.assert_allclose(chain.evaluate([[0.25]]), [[0.375, 1.0]], rtol=0, atol=1e-12)
    np.testing.assert_allclose(chain.evaluate([[0.25]], "fuzzylite"), [[0.375, 0.75]],
                               rtol=0, atol=1e-12)


def test_a_rule_reading_an_output_before_it_is_concluded_is_refused():
    text = CHAINED_FLL.replace("  rule: if x is low then y is a\n", "") + \
        "  rule: if x is low then y is a\n"
    with pytest.raises(FuzzycError, match=r"chained.fll:25:9: .*reads `y` before the rule at chained.fll:27"):
        read_fll(text, "chained.fll")


def test_hybrid_fcl_reads_a_method_per_output_and_a_block_per_ruleblock():
    model = read_fcl(HYBRID_FCL, "hybrid.fcl")
    assert [(rb.name, [v.name for v in rb.outputs]) for rb in model.blocks] == \
        [("mamdani", ["y"]), ("sugeno", ["z"])]
    assert model.blocks[1].inference_of(0).defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
    np.testing.assert_allclose(Chain(model).evaluate([[0.25]]), [[0.375, 0.75]], rtol=0,
                               atol=1e-12)


def test_two_methods_in_one_defuzzify_are_refused():
    text = HYBRID_FCL.replace("  METHOD : COGS;\n", "  METHOD : COGS;\n  METHOD : COG;\n")
    with pytest.raises(FuzzycError, match=r"hybrid.fcl:22:12: error: METHOD COG differs from "
                                          r"COGS at line 21 in the same block"):
        read_fcl(text, "hybrid.fcl")


@pytest.mark.parametrize("semantics, z", [("exact", 1.0), ("fuzzylite", 0.75),
                                          ("pyfuzzylite", 0.75)])
def test_the_controller_reads_a_chain_as_the_semantics_says(semantics, z):
    # `eval`, `simulate` and `verify --semantics fuzzylite` run the Controller: it read the
    # output's value in every semantics (z = 1 at x = 0.25) where fuzzylite reads the term
    # activations (0.75, the hand values above); on a grid it equals Chain, which the
    # conformance harness holds against the fuzzylite CLI
    from fuzzyc.api import Controller
    model = read_fll(CHAINED_FLL, "chained.fll")
    x = np.linspace(0, 1, 41)
    controller = Controller(model, batch=len(x), semantics=semantics)
    controller.step({"x": x})
    assert controller.signals["z"][10] == pytest.approx(z, abs=1e-12)     # x = 0.25
    got = np.column_stack([controller.signals["y"], controller.signals["z"]])
    np.testing.assert_allclose(got, Chain(model).evaluate(x[:, None], semantics), rtol=0,
                               atol=1e-12)
