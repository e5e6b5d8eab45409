"""Hedged conclusions and repeated hedges as fuzzylite computes them (fuzzylite 6 and pyfuzzylite
8 alike, and so the FLL/FCL meaning): a conclusion's hedges act on the rule's activation and the
result carries on to the later conclusions of the rule; `very very a` hedges twice.  fuzzyc
reads them as rules whose condition is hedged (the HEDGE step of a clause program).
Hand-computed values."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fll, write_fcl, write_fll
from fuzzyc.semantics.model import CondOp

# x = 0.5: a = x = 0.5, not a = 0.5.
# y: rule 1 `very hi` fires 0.5^2 = 0.25, rule 2 `lo` 0.5: y = (0.25 * 1 + 0.5 * 0) / 0.75 = 1/3.
# z: rule 1's `hi` has no hedge of its own but takes the activation y's hedge made, 0.25: 1/3
#    (0.5, were the hedge not carried).
# w: `very very a` = (0.5^2)^2 = 0.0625: w = 0.0625 / (0.0625 + 0.5) = 1/9.
HEDGED_FLL = """Engine: hedged
InputVariable: x
  range: 0 1
  term: a Ramp 0 1
OutputVariable: y
  range: 0 1
  defuzzifier: WeightedAverage
  term: lo Constant 0
  term: hi Constant 1
OutputVariable: z
  range: 0 1
  defuzzifier: WeightedAverage
  term: lo Constant 0
  term: hi Constant 1
OutputVariable: w
  range: 0 1
  defuzzifier: WeightedAverage
  term: lo Constant 0
  term: hi Constant 1
RuleBlock:
  conjunction: Minimum
  rule: if x is a then y is very hi and z is hi
  rule: if x is not a then y is lo and z is lo and w is lo
  rule: if x is very very a then w is hi
"""


def test_a_conclusions_hedge_carries_on_and_hedges_repeat():
    rb = read_fll(HEDGED_FLL, "hedged.fll").rulebase
    np.testing.assert_allclose(evaluate(rb, np.array([[0.5]])), [[1 / 3, 1 / 3, 1 / 9]],
                               rtol=0, atol=1e-15)
    # rule 1's hedge lands on its one clause (`x is very a`, a matrix row); `very very a` is
    # the clause `very a` under a HEDGE step
    assert [p[:, 0].tolist() for p in rb.conditions.values()] == [[CondOp.CLAUSE, CondOp.HEDGE]]


@pytest.mark.parametrize("write", [write_fll, write_fcl], ids=["fll", "fcl"])
def test_a_hedged_condition_is_not_exported_as_something_else(write):
    with pytest.raises(FuzzycError, match="hedges a compound condition or a hedged clause"):
        write(read_fll(HEDGED_FLL, "hedged.fll"), [])
