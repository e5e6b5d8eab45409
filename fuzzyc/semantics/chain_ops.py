"""The signal chain's operations, one record each, and the one walk that interprets a chain.

A Model's chain is its steps (`Op`: let, delta, prev, lowpass), its rule blocks, then its
outputs (`OutputKind`: direct, integrate, 1 / integrate).  Each kind is said once here: its
state, its update (with the rules for non-finite samples), its first sample, its limits.  The
walk (`run_chain`, `run_step`, `run_output`) reads these records and does all its arithmetic
through a *value domain* (`ChainDomain`), so one walk serves every number type:
- floats on numpy batches, the reference (`fuzzyc.engine.chain`);
- affine forms, sound sets (`fuzzyc.verifier.reach.chain`);
- C text, float/double (`fuzzyc.backends.c.chain`) and fixed point (`fuzzyc.backends.c_fixed.chain`):
  the same operations build expressions and statements instead of numbers.

Non-finite samples (NaN, +-inf) in the float semantics:
- a stateful step stores only finite values (its memory keeps its last finite one) and its
  value for that sample is computed as usual (NaN in, NaN out), so the rule base sees NaN;
- before its first finite sample a memory holds nothing: the step gives its `when_fresh` value;
- an output whose expression is not finite holds: a direct output keeps its state, an
  integrator adds 0.  Outputs are therefore always finite.
A domain whose values cannot be non-finite (integers) keeps the same walk: its tests are
constant; a set domain must read them as "may hold" (the hull of holding and not).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Protocol

from .model import Model, Op, Output, OutputKind, Step

Value = Any     # the domain's value: an array, an affine form, a C expression...


class ChainDomain(Protocol):
    """What the walk asks of a number type."""

    # arithmetic (pure: computes or builds a value)

    def sub(self, a: Value, b: Value) -> Value: ...                   # a - b
    def mix(self, a: float, x: Value, b: float, y: Value) -> Value: ...  # a x + b y, in x's range
    def zero_unless_nan(self, x: Value) -> Value: ...                 # NaN where x is, else 0
    def clamp(self, x: Value, lo: float, hi: float) -> Value: ...
    def if_finite(self, test: Value, then: Value, otherwise: Value) -> Value: ...
    def finite_or_zero(self, x: Value) -> Value: ...
    def saturating_add(self, state: Value, x: Value, lo: float, hi: float) -> Value: ...
    def reciprocal(self, o: Output, state: Value) -> Value: ...       # 1 / state

    # steps: a step's argument, its memory, the choice between a memory's two cases

    def argument(self, s: Step, stateful: bool) -> Value: ...
    def memory(self, s: Step, rule: StepOp, arg: Value) -> Value: ...
    def may_be_seen(self, s: Step) -> bool: ...       # some loop's memory holds a sample
    def may_be_fresh(self, s: Step) -> bool: ...      # some loop's memory holds none yet
    def select(self, s: Step, seen: Value | None, fresh: Value | None) -> Value: ...
    def store(self, s: Step, keep: Value) -> None: ...  # the memory := keep where finite
    def define(self, s: Step, value: Value) -> None: ...  # the step's name := value

    # rule blocks and outputs

    def rule_blocks(self) -> None: ...
    def limits(self, o: Output) -> tuple[float, float]: ...
    def output_value(self, k: int, o: Output) -> Value: ...
    def output_state(self, o: Output) -> Value: ...
    def set_state(self, o: Output, state: Value) -> None: ...
    def read_state(self, o: Output) -> Value: ...
    def emit_output(self, k: int, o: Output, result: Value) -> None: ...


@dataclass(frozen=True)
class StepOp:
    """One kind of chain step.  `when_seen(d, arg, memory, coeffs)` is its value once its
    memory holds a sample, `when_fresh(d, arg)` before; the memory then stores the argument
    (`keeps == "argument"`) or the value (`"value"`), finite values only.
    `memory_bounds(coeffs, lo, hi)`: where the memory (and the value) stays while the argument
    stays in [lo, hi]; None where that is unbounded."""
    op: Op
    word: str
    meaning: str
    stateful: bool
    keeps: str = ""
    when_seen: Callable[..., Value] | None = None
    when_fresh: Callable[..., Value] | None = None
    memory_bounds: Callable[..., tuple[float, float] | None] | None = None
    bounded_when: str = ""      # where memory_bounds is not None, in words

    def kept(self, arg: Value, value: Value) -> Value:
        return arg if self.keeps == "argument" else value


def _lowpass_bounds(coeffs, lo: float, hi: float) -> tuple[float, float] | None:
    """y = a y + b x stays in the hull of [lo, hi] and its gain b / (1 - a) times it, for
    0 <= a < 1 and b >= 0 (a convex mix of the two; the first sample is x itself)."""
    a, b = coeffs
    if not (0.0 <= a < 1.0 and b >= 0.0):
        return None
    gain = b / (1.0 - a)
    return min(lo, gain * lo), max(hi, gain * hi)


STEP_OPS: dict[Op, StepOp] = {r.op: r for r in (
    StepOp(Op.ASSIGN, "let", "name = expr.  A declared range `let x in [lo, hi]` is not applied "
           "by the float semantics; the fixed point takes it as the value's range and saturates "
           "to it (its representation needs one)", stateful=False),
    StepOp(Op.DELTA, "delta(x)", "x(k) - x(k-1), the memory holding x(k-1); first sample 0 "
           "(NaN if x is NaN)", stateful=True, keeps="argument",
           when_seen=lambda d, arg, mem, coeffs: d.sub(arg, mem),
           when_fresh=lambda d, arg: d.zero_unless_nan(arg),
           memory_bounds=lambda coeffs, lo, hi: (lo, hi)),
    StepOp(Op.PREV, "prev(x)", "x(k-1), the memory holding it; first sample x(0)",
           stateful=True, keeps="argument",
           when_seen=lambda d, arg, mem, coeffs: mem,
           when_fresh=lambda d, arg: arg,
           memory_bounds=lambda coeffs, lo, hi: (lo, hi)),
    StepOp(Op.LOWPASS, "lowpass(x, a, b)", "a y(k-1) + b x(k), the memory holding y(k-1); "
           "first sample x(0)", stateful=True, keeps="value",
           when_seen=lambda d, arg, mem, coeffs: d.mix(coeffs[0], mem, coeffs[1], arg),
           when_fresh=lambda d, arg: arg,
           memory_bounds=_lowpass_bounds, bounded_when="0 <= a < 1 and b >= 0"),
)}


@dataclass(frozen=True)
class OutputOp:
    """One kind of controller output: its state (u(k-1), or 1/u(k-1) for a reciprocal), the
    state's limits and initial value, and its update from the expression's value."""
    kind: OutputKind
    word: str
    meaning: str
    integrates: bool
    reciprocal: bool

    def state_limits(self, o: Output) -> tuple[float, float]:
        """[lo, hi], or [1/hi, 1/lo] for a reciprocal (inf for a limit at 0)."""
        if not self.reciprocal:
            return o.lo, o.hi
        return (1.0 / o.hi if o.hi != 0 else math.inf, 1.0 / o.lo if o.lo != 0 else math.inf)

    def initial_state(self, o: Output) -> float:
        """The state before the first sample: `init` (its reciprocal for a reciprocal)."""
        return 1.0 / o.init if self.reciprocal else float(o.init)

    def update(self, d: ChainDomain, value: Value, state: Value, lo: float,
               hi: float) -> Value:
        if not self.integrates:     # a non-finite value holds the state
            return d.if_finite(value, d.clamp(value, lo, hi), state)
        return d.saturating_add(state, d.finite_or_zero(value), lo, hi)   # adds 0

    def result(self, d: ChainDomain, o: Output, state: Value) -> Value:
        return d.reciprocal(o, state) if self.reciprocal else state


OUTPUT_OPS: dict[OutputKind, OutputOp] = {r.kind: r for r in (
    OutputOp(OutputKind.DIRECT, "expr", "u(k) = clamp(expr, lo, hi); u(k-1) where expr is not "
             "finite (`init` before the first finite one)", integrates=False, reciprocal=False),
    OutputOp(OutputKind.INCREMENT, "integrate(expr)", "u(k) = clamp(u(k-1) + expr, lo, hi); "
             "a non-finite expr adds 0", integrates=True, reciprocal=False),
    OutputOp(OutputKind.RECIPROCAL_INCREMENT, "1 / integrate(expr)", "v(k) = clamp(v(k-1) + "
             "expr, 1/hi, 1/lo), u = 1/v; a non-finite expr adds 0", integrates=True,
             reciprocal=True),
)}


def run_step(d: ChainDomain, s: Step) -> None:
    """One step of the chain in domain d."""
    rule = STEP_OPS[s.op]
    arg = d.argument(s, rule.stateful)
    if not rule.stateful:
        d.define(s, arg)
        return
    mem = d.memory(s, rule, arg)
    seen = rule.when_seen(d, arg, mem, s.coeffs) if d.may_be_seen(s) else None
    fresh = rule.when_fresh(d, arg) if d.may_be_fresh(s) else None
    value = d.select(s, seen, fresh)
    d.store(s, rule.kept(arg, value))
    d.define(s, value)


def run_output(d: ChainDomain, k: int, o: Output) -> None:
    """Output k of the chain in domain d."""
    rule = OUTPUT_OPS[o.kind]
    value = d.output_value(k, o)
    lo, hi = d.limits(o)
    d.set_state(o, rule.update(d, value, d.output_state(o), lo, hi))
    d.emit_output(k, o, rule.result(d, o, d.read_state(o)))


def run_chain(model: Model, d: ChainDomain) -> None:
    """One sample of the whole chain: the steps, the rule blocks, the outputs."""
    for s in model.steps:
        run_step(d, s)
    d.rule_blocks()
    for k, o in enumerate(model.outputs):
        run_output(d, k, o)
