"""`bounded` on the signal chain: lets (interval arithmetic) and controller outputs
(saturation; an integrating output without a limit is driven past it by holding the input that
makes the largest increment)."""
from __future__ import annotations

import math

import numpy as np
import sympy

from ..engine import inference as engine
from ..semantics.model import Model, Output, OutputKind
from . import intervals
from .result import Evidence, Status
from .space import dense_grid, tensor_points

TOL = 1e-9


def let_bounded(model: Model, name: str, lo: float, hi: float) -> Evidence:
    rng = intervals.signal_ranges(model).get(name)
    if rng is None:
        return Evidence("proof", Status.UNDECIDED, f"no interval bound for `{name}` (an "
                        f"operation interval arithmetic does not cover)")
    if lo - TOL <= rng[0] and rng[1] <= hi + TOL:
        return Evidence("proof", Status.PROVED, f"interval arithmetic over the input ranges: "
                        f"{name} in [{rng[0]:.6g}, {rng[1]:.6g}]")
    return Evidence("proof", Status.UNDECIDED, f"interval arithmetic gives [{rng[0]:.6g}, "
                    f"{rng[1]:.6g}], wider than [{lo:g}, {hi:g}] (may be pessimistic)")


def output_bounded(model: Model, out: Output, lo: float, hi: float, budget: int) -> Evidence:
    if lo - TOL <= out.lo and out.hi <= hi + TOL:
        return Evidence("proof", Status.PROVED, f"saturated to [{out.lo:g}, {out.hi:g}]")
    values = _chain_values(model, out, budget)
    if values is None:
        return Evidence("proof", Status.UNDECIDED, f"`{out.name}` depends on more than one "
                        f"rule block's outputs and params")
    rb, points, y = values
    if out.kind == OutputKind.DIRECT:
        u = np.clip(y, out.lo, out.hi)
        bad = np.maximum(u - hi, lo - u)
        k = int(np.argmax(bad))
        if bad[k] > TOL:
            return Evidence("grid", Status.VIOLATED, f"{out.name} = {u[k]:.6g} outside "
                            f"[{lo:g}, {hi:g}]", cases=len(u), point=_named(rb, points[k]))
        return Evidence("grid", Status.HELD, f"{len(u)} grid points", cases=len(u))
    if out.kind == OutputKind.INCREMENT:
        return _integrator(model, rb, out, lo, hi, points, y)
    return Evidence("proof", Status.UNDECIDED, "reciprocal integrator without finite limits: "
                    "the closed loop decides")


def _integrator(model, rb, out, lo, hi, points, step) -> Evidence:
    """u(k) = sat(u(k-1) + step): holding the input with the largest step of the wrong sign
    reaches the bound after ceil(distance / step) samples, unless the saturation stops it."""
    for side, bound, sat, k in (("above", hi, out.hi, int(np.argmax(step))),
                                ("below", lo, out.lo, int(np.argmin(step)))):
        direction = 1.0 if side == "above" else -1.0
        if (sat - bound) * direction <= TOL or step[k] * direction <= 0:
            continue
        samples = math.floor(abs(bound - out.init) / abs(step[k])) + 1
        period = f" ({samples * model.period:g} s)" if model.period else ""
        return Evidence("search", Status.VIOLATED,
                        f"holding the rule base's inputs here adds {step[k]:.6g} per sample: "
                        f"{out.name} starts at {out.init:g} and passes {bound:g} {side} after "
                        f"{samples} samples{period}; its saturation is [{out.lo:g}, {out.hi:g}]",
                        cases=len(step), point=_named(rb, points[k]))
    return Evidence("grid", Status.HELD, f"no input drives {out.name} past its bound",
                    cases=len(step))


def _chain_values(model: Model, out: Output, budget: int):
    """(the rule block, a dense grid over its inputs, the output's expression there), where
    the expression reads the outputs of one block and params only; else None."""
    expr = out.expr.subs({sympy.Symbol(k): v for k, v in model.symbol_values().items()})
    for rb in model.blocks:
        names = [v.name for v in rb.outputs]
        if {s.name for s in expr.free_symbols} <= set(names):
            break
    else:
        return None
    points = tensor_points(dense_grid(rb, [], budget))
    y_rb = engine.evaluate(rb, points)
    f = sympy.lambdify([sympy.Symbol(n) for n in names], expr, modules="numpy")
    y = np.broadcast_to(np.asarray(f(*y_rb.T), dtype=float), (len(points),))
    return rb, points, y


def _named(rb, x: np.ndarray) -> dict[str, float]:
    return {v.name: float(x[i]) for i, v in enumerate(rb.inputs)}
