"""Discrete terms (fuzzylite's Discrete, MATLAB's discretemf, an FCL point list): linear between
the points, the end values held beyond them.  Hand-computed values, in every format and .fz."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.backends.c.header import check_supported
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fis, read_fll, write_fcl, write_fis, write_fll, write_fz
from fuzzyc.engine.membership import memberships
from fuzzyc.semantics.model import TermKind
from fuzzyc.language.parser import parse

# input x: p = (0, 0) (1, 1) (3, 0.5); output y on [0, 4]: d = (0, 1) (2, 1) (4, 0)
DISCRETE_FLL = """Engine: discrete
InputVariable: x
  range: -1 4
  term: p Discrete 0 0 1 1 3 0.5
OutputVariable: y
  range: 0 4
  aggregation: Maximum
  defuzzifier: Centroid
  term: d Discrete 0 1 2 1 4 0
RuleBlock:
  implication: Minimum
  rule: if x is p then y is d
"""
DISCRETE_FCL = """FUNCTION_BLOCK discrete
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY x
  RANGE := (-1 .. 4);
  TERM p := (0, 0) (1, 1) (3, 0.5);
END_FUZZIFY
DEFUZZIFY y
  RANGE := (0 .. 4);
  TERM d := (0, 1) (2, 1) (4, 0);
  METHOD : COG;
  ACCU : MAX;
END_DEFUZZIFY
RULEBLOCK rules
  ACT : MIN;
  RULE 1 : IF x IS p THEN y IS d;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""
DISCRETE_FIS = """[System]
Name='discrete'
Type='mamdani'
NumInputs=1
NumOutputs=1
NumRules=1
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='max'
DefuzzMethod='centroid'

[Input1]
Name='x'
Range=[-1 4]
NumMFs=1
MF1='p':'discretemf',[0 0 1 1 3 0.5]

[Output1]
Name='y'
Range=[0 4]
NumMFs=1
MF1='d':'discretemf',[0 1 2 1 4 0]

[Rules]
1, 1 (1) : 1
"""
MODELS = [read_fll(DISCRETE_FLL, "d.fll"), read_fcl(DISCRETE_FCL, "d.fcl"),
          read_fis(DISCRETE_FIS, "d.fis")]


@pytest.mark.parametrize("model", MODELS, ids=["fll", "fcl", "fis"])
def test_discrete_membership_interpolates_and_holds_the_ends(model):
    x = model.rulebase.inputs[0]
    assert x.kinds[0] == TermKind.DISCRETE
    # -1: before the first point, its y 0; 0.5: halfway up to 1; 2: 1 + (0.5 - 1) * (2 - 1) / 2
    # = 0.75; 4: past the last point, its y 0.5; NaN: 0 (as every term)
    np.testing.assert_allclose(memberships(x, np.array([-1, 0.5, 2, 4, np.nan]))[:, 0],
                               [0, 0.5, 0.75, 0.5, 0], rtol=0, atol=1e-15)


@pytest.mark.parametrize("model", MODELS, ids=["fll", "fcl", "fis"])
def test_discrete_output_centroid(model):
    # x = 1: p = 1, so M = d: 1 on [0, 2], (4 - u) / 2 on [2, 4].  Area 2 + 1 = 3, moment
    # int_0^2 u du + int_2^4 u (4 - u) / 2 du = 2 + (1/2)(2u^2 - u^3/3)|_2^4 = 2 + 8/3 = 14/3:
    # centroid 14/9.  x = 2: p = 0.75 clips d: M = 0.75 on [0, 2.5], (4 - u) / 2 after; area
    # 1.875 + 0.5625 = 2.4375, moment 0.75 * 2.5^2 / 2 + (1/2)(2u^2 - u^3/3)|_2.5^4 = 2.34375 +
    # (1/2)(32/3 - 175/24) = 2.34375 + 1.6875 = 4.03125: 4.03125 / 2.4375 = 1.6538461...
    y = evaluate(model.rulebase, np.array([[1.0], [2.0]]))[:, 0]
    np.testing.assert_allclose(y, [14 / 9, 4.03125 / 2.4375], rtol=0, atol=1e-9)


@pytest.mark.parametrize("write, read", [(write_fll, read_fll), (write_fcl, read_fcl),
                                         (write_fis, read_fis), (write_fz, parse)],
                         ids=["fll", "fcl", "fis", "fz"])
def test_discrete_terms_are_written_and_read_back(write, read):
    model = MODELS[0]
    back = read(write(model, []), "back")
    np.testing.assert_array_equal(back.rulebase.inputs[0].points[0], [[0, 0], [1, 1], [3, 0.5]])
    # FCL reads the 0/1 point list d back as the trapezoid it is, whose centroid is exact where
    # a discrete output's is integrated on the engine's grid (within 1e-6 here)
    x = np.linspace(0.1, 4, 23)[:, None]      # where the rule fires (FIS's default differs)
    np.testing.assert_allclose(evaluate(back.rulebase, x), evaluate(model.rulebase, x),
                               rtol=0, atol=1e-6)


@pytest.mark.parametrize("text, message", [
    ("term: p Discrete 0 0 1", "pairs of finite numbers"),
    ("term: p Discrete 1 0 0 1", "x values must ascend"),
    ("term: p Discrete 0 0 1 2", "y values lie in \\[0, 1\\]"),
])
def test_bad_discrete_terms_are_refused_where_written(text, message):
    with pytest.raises(FuzzycError, match=f"d.fll:4:\\d+: error: .*{message}"):
        read_fll(DISCRETE_FLL.replace("term: p Discrete 0 0 1 1 3 0.5", text), "d.fll")


def test_the_c_back_end_refuses_discrete_terms_by_name():
    with pytest.raises(FuzzycError, match="discrete"):
        check_supported(MODELS[0].rulebase)
