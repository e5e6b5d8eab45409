"""The t-norms and s-norms of the model, elementwise on arrays (fuzzylite's definitions).

Each norm's function is its record's in the operator registry (fuzzyc.semantics.operators);
these tables only index them by enum, so the engine calls every norm through the registry.
Every norm has its neutral element (1 for t-norms, 0 for s-norms), so an absent clause can be
stood in for by it.  Rules with more than two clauses fold left to right: ((a1 * a2) * a3) ...
"""
from __future__ import annotations

import numpy as np

from ..semantics import operators
from ..semantics.model import ACTIVATION_FLOOR, SNorm, TNorm

T_NORMS = {t: rec.numpy for t, rec in operators.T_NORMS.items()}
S_NORMS = {s: rec.numpy for s, rec in operators.S_NORMS.items()}


def implied(level: np.ndarray, mu: np.ndarray, implication) -> np.ndarray:
    """A rule's level applied to a term's membership: the implication's t-norm (broadcast)."""
    return T_NORMS[TNorm(int(implication))](level, mu)


def combine(values: list[np.ndarray], norm: TNorm | SNorm, conjunction: bool,
            tables: tuple[dict, dict] | None = None) -> np.ndarray:
    """values[0] (norm) values[1] (norm) ..., left to right; `tables`: (t-norms, s-norms)
    functions by enum in place of the model's (a tool's own arithmetic, tool_semantics)."""
    t_norms, s_norms = tables or (T_NORMS, S_NORMS)
    op = t_norms[TNorm(int(norm))] if conjunction else s_norms[SNorm(int(norm))]
    out = values[0]
    for v in values[1:]:
        out = op(out, v)
    return out


def firing(act: np.ndarray) -> np.ndarray:
    """Rule activations with those below ACTIVATION_FLOOR set to 0 (they do not fire)."""
    return np.where(act < ACTIVATION_FLOOR, 0.0, act)


def firing_in_place(act: np.ndarray, below: np.ndarray) -> np.ndarray:
    """`firing` written into act itself, with `below` (bool, act's shape) as the mask buffer:
    the same values without a temporary."""
    np.less(act, ACTIVATION_FLOOR, out=below)
    np.copyto(act, 0.0, where=below)
    return act


def row_sum(a: np.ndarray, out: np.ndarray) -> np.ndarray:
    """a (G, N) summed over G row by row, ((a0 + a1) + a2) ..., into out (N,): a fixed order,
    so a sample's result is independent of N.  numpy's a.sum(axis=0) runs in this order while
    N > 1 (one pass over the rows); at N = 1 the column is contiguous and numpy sums it
    pairwise, so that case adds row by row here."""
    if len(a) == 0:
        out.fill(0.0)
    elif a.shape[1] > 1:
        np.add.reduce(a, axis=0, out=out)     # a.sum without its Python wrapper
    else:
        out[...] = a[0]
        for row in a[1:]:
            np.add(out, row, out=out)
    return out
