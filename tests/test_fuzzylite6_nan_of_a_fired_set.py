"""fuzzylite 6 takes an output's numeric default only where no rule concluding it fired
(OutputVariable::defuzzify: the default where its fuzzy output is empty); a rule that fired
into a set that is 0 throughout (here a BoundedDifference implication) leaves the fuzzy output
non-empty, and Centroid's 0/0 stays NaN.  pyfuzzylite 8 replaces every NaN by the default
(OutputVariable.defuzzify).  Found by the differential fuzzer (fuzzylite-fcl, 3 of 200 files:
"a numeric default"); the numbers are the fuzzylite 6 CLI's, measured on this file
(`fuzzylite -i e.fcl -d x.fld -o y.fld -of fld`: nan, nan, 7.000)."""
from __future__ import annotations

import numpy as np

from fuzzyc.formats import read_fcl
from fuzzyc.formats.tool_semantics import Chain

FCL = """FUNCTION_BLOCK e
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY x
  RANGE := (0.000 .. 1.000);
  TERM a := Triangle 0.000 0.500 1.000;
END_FUZZIFY
DEFUZZIFY y
  RANGE := (0.000 .. 10.000);
  TERM b := (0.000, 0.000) (5.000, 0.500) (10.000, 0.000);
  METHOD : COG;
  ACCU : MAX;
  DEFAULT := 7.000;
END_DEFUZZIFY
RULEBLOCK rules
  AND : MIN;
  ACT : BDIF;
  RULE 1 : if x is a then y is b;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""

# x = 0.125: a = 0.25 fires (above fuzzylite's 1e-6); BDIF(0.25, b) = max(0, 0.25 + b - 1) = 0
# since b <= 0.5, so the set is 0 throughout and its centroid 0/0: NaN.  x = 0.9: a = 0.2, the
# same.  x = 0: a = 0, nothing fires: the default 7.
X = np.array([[0.125], [0.9], [0.0]])


def test_fuzzylite6_keeps_the_nan_of_a_fired_empty_set():
    y = Chain(read_fcl(FCL, "e.fcl")).evaluate(X, "fuzzylite")[:, 0]
    assert np.isnan(y[0]) and np.isnan(y[1]) and y[2] == 7.0


def test_pyfuzzylite_and_exact_give_the_default():
    model = read_fcl(FCL, "e.fcl")
    assert Chain(model).evaluate(X, "pyfuzzylite")[:, 0].tolist() == [7.0, 7.0, 7.0]
    assert Chain(model).evaluate(X, "exact")[:, 0].tolist() == [7.0, 7.0, 7.0]
