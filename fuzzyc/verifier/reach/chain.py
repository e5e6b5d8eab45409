"""A Model's signal chain on affine forms: the set-valued twin of `fuzzyc.engine.chain`.

Expressions are walked like `fuzzyc.engine.expressions` walks them, one node kind at a time; linear nodes are
exact, the others go through `Affine.apply` with their interval extension. Stateful steps keep
affine memories, so delta(lowpass(x)) cancels exactly as it does on numbers. The rule base is
linearized per box: slopes from central differences of the engine (any slope is sound), the
remainder bounded by the interval rule base (`reach.rulebase`) on a grid of sub-boxes.
A node, step or rule base with no set-valued meaning raises `Unsupported` naming it.
"""
from __future__ import annotations

import itertools

import numpy as np
import sympy

from ...engine import inference as engine
from ...semantics.chain_ops import OUTPUT_OPS, run_chain
from ...semantics.model import Model
from . import rulebase as set_rulebase
from .affine import Affine, Symbols, join_common, monotone, where

SUB_BOXES = 1024    # sub-boxes per box for the rule base remainder (n per axis, n^I about this)


class Unsupported(ValueError):
    """A piece of the loop the proof has no set-valued evaluation for (named in the message)."""


Value = "Affine | float"


def _relu(lo, hi):
    return np.maximum(lo, 0.0), np.maximum(hi, 0.0)


def _abs(lo, hi):
    low = np.where((lo <= 0) & (hi >= 0), 0.0, np.minimum(np.abs(lo), np.abs(hi)))
    return low, np.maximum(np.abs(lo), np.abs(hi))


def _power(n: int):
    def box(lo, hi):
        a, b = lo ** n, hi ** n
        if n % 2:
            return a, b
        low = np.where((lo <= 0) & (hi >= 0), 0.0, np.minimum(a, b))
        return low, np.maximum(a, b)
    return box


def apply_fn(x: Value, box, point) -> Value:
    return x.apply(box) if isinstance(x, Affine) else float(point(x))


def maximum(a: Value, b: Value) -> Value:
    """max(a, b): with a number, one monotone step; of two forms, b + relu(a - b)."""
    if not isinstance(a, Affine) and not isinstance(b, Affine):
        return max(a, b)
    if not isinstance(a, Affine) or not isinstance(b, Affine):
        form, c = (a, float(b)) if isinstance(a, Affine) else (b, float(a))
        return form.clip(c, np.inf)
    return b + apply_fn(a - b, _relu, lambda v: max(v, 0.0))


def minimum(a: Value, b: Value) -> Value:
    return -maximum(-a, -b)


def _clamp(expr: sympy.Expr, env: dict) -> Value | None:
    """clamp(e, lo, hi) as the language writes it, Min(hi, Max(lo, e)): one clip."""
    if not isinstance(expr, sympy.Min) or len(expr.args) != 2:
        return None
    inner = [a for a in expr.args if isinstance(a, sympy.Max) and len(a.args) == 2]
    hi = [a for a in expr.args if a.is_number]
    lo = [a for a in inner[0].args if a.is_number] if inner else []
    if not (inner and hi and lo):
        return None
    (rest,) = [a for a in inner[0].args if not a.is_number]
    value = evaluate(rest, env)
    if not isinstance(value, Affine):
        return float(np.clip(value, float(lo[0]), float(hi[0])))
    return value.clip(float(lo[0]), float(hi[0]))


def evaluate(expr: sympy.Expr, env: dict) -> Value:
    """expr over env (Affine forms and numbers)."""
    if isinstance(expr, sympy.Symbol):
        if expr.name not in env:
            raise Unsupported(f"no value for `{expr.name}`")
        return env[expr.name]
    if expr.is_number:
        return float(expr)
    clamped = _clamp(expr, env)
    if clamped is not None:
        return clamped
    args = [evaluate(a, env) for a in expr.args] if not isinstance(expr, sympy.Pow) else None
    if isinstance(expr, sympy.Add):
        return sum(args[1:], args[0])
    if isinstance(expr, sympy.Mul):
        out = args[0]
        for a in args[1:]:
            out = out * a
        return out
    if isinstance(expr, (sympy.Min, sympy.Max)):
        fold = minimum if isinstance(expr, sympy.Min) else maximum
        out = args[0]
        for a in args[1:]:
            out = fold(out, a)
        return out
    if isinstance(expr, sympy.Abs):
        return apply_fn(args[0], _abs, abs)
    if isinstance(expr, sympy.exp):
        return apply_fn(args[0], monotone(np.exp), np.exp)
    if isinstance(expr, sympy.Pow) and expr.exp.is_number:
        return _pow(evaluate(expr.base, env), float(expr.exp), expr)
    raise Unsupported(f"`{expr}`: {type(expr).__name__} has no set-valued evaluation")


def _pow(base: Value, n: float, expr) -> Value:
    if not isinstance(base, Affine):
        return float(base) ** n
    lo, hi = base.bounds()
    if n == int(n) and n >= 1:
        return base.apply(_power(int(n)))
    if n == -1 and (np.all(lo > 0) or np.all(hi < 0)):
        return base.apply(monotone(lambda x: 1.0 / x, increasing=False))
    if n == 0.5 and np.all(lo >= 0):
        return base.apply(monotone(np.sqrt))
    raise Unsupported(f"`{expr}`: a power {n:g} of a set that reaches [{lo.min():.6g}, "
                      f"{hi.max():.6g}]")


def _reciprocal(state: Affine, lo: float, hi: float) -> Affine:
    """1 / state for a state clipped to [lo, hi] (lo > 0): every true value lies there, though
    the clipped form's bounds may overshoot it, so 1 / clip(x, lo, hi) is the same function on
    them and monotone everywhere."""
    return state.apply(monotone(lambda x: 1.0 / np.clip(x, lo, hi), increasing=False))


def rulebase_forms(rb, xs: list[Affine], memo: dict | None = None) -> list[Affine]:
    """The rule base's outputs as affine forms of its inputs, per box: y = sum_i s_i x_i +
    mid + rad eps_new, the remainder bounded on sub-boxes by the interval rule base. The
    slopes and the remainder depend on the inputs' bounds only: `memo` keeps them per box's
    bounds (a loop whose inputs hold still, as a plant's params do, pays for them once)."""
    sym = xs[0].sym
    lo = np.stack([x.lo() for x in xs], axis=1)
    hi = np.stack([x.hi() for x in xs], axis=1)
    keys = [row.tobytes() for row in np.concatenate([lo, hi], axis=1)]
    memo = {} if memo is None else memo
    new = sorted({i for i, key in enumerate(keys) if key not in memo})
    if new:
        if len(memo) > MEMO_SIZE:
            memo.clear()
        for i, found in zip(new, zip(*_linearize(rb, lo[new], hi[new]))):
            memo[keys[i]] = found
    slopes, low, high = (np.stack(part) for part in zip(*(memo[key] for key in keys)))
    out = []
    for o in range(low.shape[1]):
        form = Affine(sym, 0.5 * (low[:, o] + high[:, o]))
        for i, x in enumerate(xs):
            form = form + x.scale(slopes[:, i, o])
        out.append(form.with_error(0.5 * (high[:, o] - low[:, o]) * (1 + 1e-12) + 1e-15))
    return out


MEMO_SIZE = 100_000     # linearizations kept per rule block (cleared when full)


def _linearize(rb, lo: np.ndarray, hi: np.ndarray):
    """Per box (rows of lo, hi (N, I)): the slopes (N, I, O) and the remainder's bounds
    low, high (N, O) of the rule base's outputs over the box."""
    n, k = lo.shape
    centre, radius = 0.5 * (lo + hi), 0.5 * (hi - lo)
    # slopes: central differences of the engine across each box
    points = np.repeat(centre[:, None, :], 2 * k, axis=1)
    for i in range(k):
        points[:, 2 * i, i] += radius[:, i]
        points[:, 2 * i + 1, i] -= radius[:, i]
    y = engine.evaluate(rb, points.reshape(-1, k)).reshape(n, 2 * k, -1)
    slopes = np.where(radius[:, :, None] > 0, (y[:, 0::2] - y[:, 1::2])
                      / np.where(radius > 0, 2 * radius, 1.0)[:, :, None], 0.0)  # (B, I, O)
    # remainder on a grid of sub-boxes
    per_axis = max(1, int(round(SUB_BOXES ** (1.0 / k))))
    t = np.linspace(0.0, 1.0, per_axis + 1)
    cells = np.array(list(itertools.product(range(per_axis), repeat=k)))       # (C, I)
    a = lo[:, None, :] + (hi - lo)[:, None, :] * t[cells]                        # (B, C, I)
    b = lo[:, None, :] + (hi - lo)[:, None, :] * t[cells + 1]
    b = np.where(cells + 1 == per_axis, hi[:, None, :], b)
    y_lo, y_hi = set_rulebase.evaluate(rb, a.reshape(-1, k), b.reshape(-1, k))
    y_lo, y_hi = y_lo.reshape(n, len(cells), -1), y_hi.reshape(n, len(cells), -1)
    low, high = np.empty((n, y_lo.shape[2])), np.empty((n, y_lo.shape[2]))
    for o in range(y_lo.shape[2]):
        s = slopes[:, None, :, o]
        lin_lo = np.minimum(s * a, s * b).sum(axis=2)
        lin_hi = np.maximum(s * a, s * b).sum(axis=2)
        low[:, o] = (y_lo[:, :, o] - lin_hi).min(axis=1)
        high[:, o] = (y_hi[:, :, o] - lin_lo).max(axis=1)
    return slopes, low, high


class SetController:
    """The chain of a Model on affine forms, one period at a time (`step`)."""

    def __init__(self, model: Model, sym: Symbols, params: dict):
        self.model, self.sym, self.params = model, sym, params
        for rb in model.blocks:
            reason = set_rulebase.unsupported(rb)
            if reason:
                raise Unsupported(f"rule block {rb.name or 1}: {reason}")
        self.state: dict[str, Affine | float] = {}     # step memories, output states
        self.memos = [{} for _ in model.blocks]       # per rule block: rulebase_forms' memo
        for out in model.outputs:
            self.state["out:" + out.name] = OUTPUT_OPS[out.kind].initial_state(out)

    def step(self, inputs: dict) -> dict:
        chain = SetChain(self, {**self.params, **inputs})
        run_chain(self.model, chain)
        chain.env.update(chain.outputs)
        self.signals = chain.env
        return chain.outputs

    def _form(self, value: Value) -> Affine:
        return value if isinstance(value, Affine) else Affine(self.sym, value)


def _unbounded(x: Value) -> np.ndarray | bool:
    """Per box, whether x may take a non-finite value (its bounds are not finite)."""
    if not isinstance(x, Affine):
        return not np.isfinite(x)
    lo, hi = x.bounds()
    return ~(np.isfinite(lo) & np.isfinite(hi))


class SetChain:
    """The chain walk's set domain (`fuzzyc.semantics.chain_ops`): one period of a
    SetController on affine forms (numbers where a value does not vary).  Sound: where a set
    may hold a non-finite value, the float semantics' holding rules are read as "may hold" (the
    join of holding and not); a memory that may store one is refused (Unsupported), as its
    last finite value has no bounded set."""

    def __init__(self, controller: SetController, env: dict):
        self.c, self.env = controller, env
        self.outputs: dict[str, Value] = {}

    def _form(self, value: Value) -> Affine:
        return self.c._form(value)

    # -- arithmetic -----------------------------------------------------------------------

    @staticmethod
    def sub(a, b):
        return a - b

    @staticmethod
    def mix(a, x, b, y):
        return x * a + y * b

    @staticmethod
    def zero_unless_nan(x):
        return float("nan") if not isinstance(x, Affine) and np.isnan(x) else 0.0

    def clamp(self, x, lo: float, hi: float) -> Affine:
        """clip(x, lo, hi); a box where x is unbounded may be anywhere in [lo, hi]."""
        bad = _unbounded(x)
        if not np.any(bad):
            return self._form(x).clip(lo, hi)
        whole = Affine.interval(self.c.sym, lo, hi)
        if not isinstance(x, Affine):
            return whole
        with np.errstate(invalid="ignore", over="ignore"):
            clipped = x.clip(lo, hi)
        return where(bad, whole, clipped)

    def if_finite(self, test, then, otherwise):
        bad = _unbounded(test)
        if not np.any(bad):
            return then
        if not isinstance(test, Affine):       # a number that is not finite: holds
            return otherwise
        return where(bad, join_common(self._form(then), self._form(otherwise)), then)

    @staticmethod
    def finite_or_zero(x):
        # a set of finite values is itself; an unbounded one makes the sum unbounded, which
        # `clamp` reads as the whole range (sound for x and 0 alike)
        return 0.0 if not isinstance(x, Affine) and not np.isfinite(x) else x

    def saturating_add(self, state, x, lo: float, hi: float):
        return self.clamp(state + x, lo, hi)

    @staticmethod
    def reciprocal(o, state):
        lo, hi = OUTPUT_OPS[o.kind].state_limits(o)
        return _reciprocal(state, lo, hi)

    # -- steps ----------------------------------------------------------------------------

    def argument(self, s, stateful: bool):
        return evaluate(s.expr, self.env)

    def memory(self, s, rule, arg):
        return self.c.state.get("mem:" + s.name)

    def may_be_seen(self, s) -> bool:
        return ("mem:" + s.name) in self.c.state

    def may_be_fresh(self, s) -> bool:
        return ("mem:" + s.name) not in self.c.state

    @staticmethod
    def select(s, seen, fresh):
        return fresh if seen is None else seen

    def store(self, s, keep) -> None:
        if np.any(_unbounded(keep)):
            raise Unsupported(f"`{s.name}` may not be finite: its memory has no bounded set")
        self.c.state["mem:" + s.name] = keep

    def define(self, s, value) -> None:
        self.env[s.name] = value

    # -- rule blocks and outputs --------------------------------------------------------------

    def rule_blocks(self) -> None:
        env = self.env
        for rb, memo in zip(self.c.model.blocks, self.c.memos):   # in order: a block may
            xs = [self._form(env[v.name]) for v in rb.inputs]      # read an earlier one's
            for v, y in zip(rb.outputs, rulebase_forms(rb, xs, memo)):   # outputs
                env[v.name] = y

    @staticmethod
    def limits(o) -> tuple[float, float]:
        return OUTPUT_OPS[o.kind].state_limits(o)

    def output_value(self, k: int, o):
        return evaluate(o.expr, self.env)

    def output_state(self, o):
        return self.c.state["out:" + o.name]

    def set_state(self, o, state) -> None:
        self.c.state["out:" + o.name] = state

    read_state = output_state

    def emit_output(self, k: int, o, result) -> None:
        self.outputs[o.name] = result
