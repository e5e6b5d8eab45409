"""Interval arithmetic over the signal chain's sympy expressions: a proof that a `let` or a
direct output stays in a range, for every input in the declared input ranges. Only the
operations the language writes are handled (+, *, powers, min, max, abs, clamp); anything else
returns None and the search decides."""
from __future__ import annotations

import math

import sympy

from ..semantics.model import Model, Op

Interval = tuple[float, float]


def _mul(a: Interval, b: Interval) -> Interval:
    products = [0.0 if x == 0 or y == 0 else x * y for x in a for y in b]  # 0 * inf = 0 here
    return (min(products), max(products))


def _pow(a: Interval, n) -> Interval | None:
    if n == -1:
        return None if a[0] <= 0 <= a[1] else (1.0 / a[1], 1.0 / a[0])
    if n == int(n) and n >= 0:
        ends = [a[0] ** int(n), a[1] ** int(n)]
        low = 0.0 if int(n) % 2 == 0 and a[0] <= 0 <= a[1] else min(ends)
        return (low, max(ends))
    return None


def evaluate(expr: sympy.Expr, env: dict[str, Interval]) -> Interval | None:
    if expr.is_Number:
        v = float(expr)
        return (v, v)
    if expr.is_Symbol:
        return env.get(expr.name)
    args = [evaluate(a, env) for a in expr.args] if not expr.is_Pow else None
    if args is not None and any(a is None for a in args):
        return None
    if expr.is_Add:
        return (sum(a[0] for a in args), sum(a[1] for a in args))
    if expr.is_Mul:
        out = args[0]
        for a in args[1:]:
            out = _mul(out, a)
        return out
    if expr.is_Pow:
        base = evaluate(expr.base, env)
        return None if base is None or not expr.exp.is_Number else _pow(base, float(expr.exp))
    if isinstance(expr, sympy.Min):
        return (min(a[0] for a in args), min(a[1] for a in args))
    if isinstance(expr, sympy.Max):
        return (max(a[0] for a in args), max(a[1] for a in args))
    if isinstance(expr, sympy.Abs):
        (lo, hi), = args
        return (0.0 if lo <= 0 <= hi else min(abs(lo), abs(hi)), max(abs(lo), abs(hi)))
    return None


def signal_ranges(model: Model) -> dict[str, Interval | None]:
    """A range for every raw input, param and step of the chain, propagated in order.
    DELTA of x in [l, h] is in [l - h, h - l]; PREV keeps x's range; LOWPASS with a, b >= 0 and
    a + b = 1 keeps it (a convex combination of values in the range, by induction)."""
    env: dict[str, Interval | None] = {s.name: (s.lo, s.hi) for s in model.signals}
    env.update({name: (p.value, p.value) for name, p in model.params.items()})
    for step in model.steps:
        arg = evaluate(step.expr, env)
        if arg is None or step.op == Op.ASSIGN or step.op == Op.PREV:
            env[step.name] = arg
        elif step.op == Op.DELTA:
            env[step.name] = (arg[0] - arg[1], arg[1] - arg[0])
        else:
            a, b = step.coeffs
            env[step.name] = arg if a >= 0 and b >= 0 and math.isclose(a + b, 1.0) else None
    return env
