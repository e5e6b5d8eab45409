"""Outputs evaluated in order, for what reads an output's value: fuzzylite's Function terms
(`fabs(outputFx - trueFx)`) and `lock-previous` (an output holding its last value where no
rule fires: state).

fuzzylite defuzzifies a rule block's outputs in the order they are declared; a Function term
reads every variable's current value, so an output declared before it gives this evaluation's
value (after its lock), one after it (or itself) the previous evaluation's.  fuzzyc reads the
earlier ones and refuses the others at import (a value from the past is state).

What each semantics does where the stateless engine has no word for it (`Policy`):
- exact: a non-finite function value has no value (its rules do not fire); an output holding
  its value holds the last value where one of its rules fired, its default before that;
- fuzzylite (fuzzylite 6 C++, OutputVariable::defuzzify): NaN and inf carry on through the
  weighted average; NaN where no rule fired; a locked output holds, where no rule fired, the
  last finite value it had (NaN before that);
- pyfuzzylite (8.0.6, OutputVariable.defuzzify): the same arithmetic, but a locked output
  replaces every NaN (also one a rule gave, 0/0) by the last value that was not NaN.

`Held` keeps the held values: either along the batch axis (rows in sequence: one controller,
the conformance harness, fuzzylite's `-d inputs.fld`) or per loop of a batch of independent
loops stepped one sample at a time (the controller).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import Diagnostic, FuzzycError
from ..semantics.model import Defuzzifier, RuleBase

# the defuzzifiers that read a term's value (fuzzylite's WeightedAverage/WeightedSum, grouped
# or not), where a Function term is a value of other variables, not a membership of x
TAKAGI_SUGENO = (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM,
                 Defuzzifier.CENTER_OF_AREA, Defuzzifier.GROUPED_SUM)


@dataclass(frozen=True)
class Policy:
    name: str
    keep_nonfinite: bool        # function values NaN/inf carried on (the tools)
    nan_unfired: bool           # NaN where no rule fired (the tools' `default: nan`)
    hold_nan: bool              # lock-previous replaces every NaN (pyfuzzylite 8)


EXACT = Policy("exact", False, False, False)
POLICIES = {"exact": EXACT, "fuzzylite": Policy("fuzzylite", True, True, False),
            "pyfuzzylite": Policy("pyfuzzylite", True, True, True)}


def reads_values(rb: RuleBase) -> bool:
    """Whether rb's outputs must be evaluated in order: a Takagi-Sugeno function term reads
    other variables, or an output holds its value."""
    return any(v.lock_previous or (v.formulas and rb.inference_of(o).defuzzifier in TAKAGI_SUGENO)
               for o, v in enumerate(rb.outputs))


def locked(rb: RuleBase) -> list[str]:
    return [v.name for v in rb.outputs if v.lock_previous]


def refuse_stateless(rb: RuleBase, what: str = "this evaluation") -> None:
    """FuzzycError naming the outputs that hold their value, for a stateless reader."""
    names = locked(rb)
    if names:
        raise FuzzycError([Diagnostic(rb.outputs[rb.output_index(names[0])].loc,
                                      f"`{names[0]}` has lock-previous: it holds its last value "
                                      f"where no rule fires, state that {what} has not (eval "
                                      "--csv --series, simulate and the controller keep it)")])


@dataclass
class Held:
    """The held value of each output (NaN: none yet); `sequence`: the rows of a batch are
    successive samples of one controller, else independent loops stepped together."""
    sequence: bool
    carry: dict[int, np.ndarray] = field(default_factory=dict)

    def hold(self, o: int, value: np.ndarray, new: np.ndarray, source: np.ndarray) -> np.ndarray:
        """value where `new`, else the last value marked `source` before it (the carry from
        earlier calls before any); the carry moves on to the last source."""
        carry = self.carry.get(o, np.nan)
        if not self.sequence:
            out = np.where(new, value, carry)
            self.carry[o] = np.where(source, value, carry)
            return out
        n = value.shape[0]
        last = np.maximum.accumulate(np.where(source, np.arange(n), -1))
        before = np.concatenate([[-1], last[:-1]])
        out = np.where(new, value, np.where(before >= 0, value[before.clip(0)], carry))
        if n and last[-1] >= 0:
            self.carry[o] = value[last[-1]]
        return out


def finish_output(policy: Policy, var, value: np.ndarray, fired: np.ndarray,
                  held: Held | None, o: int) -> np.ndarray:
    """One output's values (NaN where nothing with a value fired) under the policy: its lock,
    then its default (exact) or NaN (the tools) where it has none."""
    if policy.nan_unfired:
        value = np.where(fired, value, np.nan)
        if var.lock_previous:
            keep = ~np.isnan(value) if policy.hold_nan else fired
            source = keep if policy.hold_nan else fired & np.isfinite(value)
            value = held.hold(o, value, keep, source)
        return value
    if var.lock_previous:
        valued = ~np.isnan(value)
        value = held.hold(o, value, valued, valued)
    return np.where(np.isnan(value), var.default, value)

