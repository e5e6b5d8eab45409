"""The rule base's input space as grids: dense search grids and the break-point grid, with a
`where` guard restricting the guarded inputs to the points where the guard is fully true
(membership 1: the core of the term, e.g. e1 = 1 for a triangle peaking at 1)."""
from __future__ import annotations

import numpy as np

from ..engine.membership import HEDGE_EXPONENT, term_values
from ..semantics.model import RuleBase, Variable

FULL = 1.0 - 1e-12


def break_points(var: Variable) -> np.ndarray:
    p = var.params
    pts = np.concatenate([[var.lo, var.hi], p[np.isfinite(p)]])
    return np.unique(pts[(pts >= var.lo) & (pts <= var.hi)])


def dense_axis(var: Variable, n: int) -> np.ndarray:
    return np.unique(np.concatenate([np.linspace(var.lo, var.hi, n), break_points(var)]))


def guard_truth(rb: RuleBase, where, i: int, x: np.ndarray) -> np.ndarray:
    """Truth of the guard's clauses on input i at x (1 where input i is not guarded)."""
    truth = np.ones(len(x))
    for name, term, negated in where:
        if rb.input_index(name) != i:
            continue
        var = rb.inputs[i]
        mu = term_values(var.kinds[term:term + 1], var.params[term:term + 1], x)[:, 0]
        truth = np.minimum(truth, 1.0 - mu if negated else mu)
    return truth


def restrict(rb: RuleBase, where, axes: list[np.ndarray]) -> list[np.ndarray]:
    """Keep, on each guarded axis, the points where the guard is fully true."""
    return [ax[guard_truth(rb, where, i, ax) >= FULL] for i, ax in enumerate(axes)]


def dense_grid(rb: RuleBase, where, budget: int) -> list[np.ndarray]:
    """Per input a dense axis (break points included), about `budget` points in all."""
    free = [i for i in range(len(rb.inputs)) if not any(rb.input_index(w[0]) == i for w in where)]
    n = max(3, int(budget ** (1.0 / max(len(free), 1))))
    axes = [dense_axis(v, n if i in free else max(n, 201)) for i, v in enumerate(rb.inputs)]
    return restrict(rb, where, axes)


def tensor_points(axes: list[np.ndarray]) -> np.ndarray:
    grids = np.meshgrid(*axes, indexing="ij")
    return np.stack([g.ravel() for g in grids], axis=1)


def hedge_free(rb: RuleBase) -> bool:
    return not np.any(HEDGE_EXPONENT[rb.hedges] != 1.0)
