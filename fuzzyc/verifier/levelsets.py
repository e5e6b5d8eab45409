"""Where a clause is true at least to a level: closed intervals, in closed form.

The shapes whose registry record has level sets (`Shape.superlevel`: trapezoid, gaussian,
bell, sigmoid, singleton) are quasi-concave or monotone, so {x : mu(x) >= lam} is one closed
interval and {x : 1 - mu(x) >= lam} the complement of an open one; the proof methods take
only those (`fuzzyc.semantics.shapes.provable_kinds`).  That is what makes coverage under the
min t-norm decidable exactly: a rule fires >= level on a box (a union of boxes with `not`),
and boxes are checked exactly.
"""
from __future__ import annotations

import numpy as np

from ..engine.membership import HEDGE_EXPONENT
from ..semantics.model import TermKind, Variable
from ..semantics.shapes import SHAPES

INF = np.inf


def _superlevel(kind: int, p: np.ndarray, lam: float, strict: bool) -> tuple[float, float] | None:
    """{mu >= lam} (or {mu > lam} when strict, returned as its closure's end points).
    None when empty."""
    if lam <= 0 and not strict:
        return (-INF, INF)
    if lam >= 1 and strict or lam > 1:
        return None
    level = SHAPES[TermKind(int(kind))].superlevel
    if level is None:
        raise ValueError(f"{TermKind(int(kind)).name.lower()} terms have no level sets here")
    return level(p, lam, strict)


def clause_intervals(var: Variable, term: int, hedge: int, negated: bool,
                     lam: float) -> list[tuple[float, float]] | None:
    """Closed intervals where the clause's truth (hedge, then not) is >= lam.
    None when the answer is not a union of closed intervals (a negated singleton)."""
    kind, p = int(var.kinds[term]), var.params[term]
    power = HEDGE_EXPONENT[hedge]
    if not negated:
        inside = _superlevel(kind, p, max(lam, 0.0) ** (1.0 / power), strict=False)
        return [] if inside is None else [inside]
    if lam <= 0:
        return [(-INF, INF)]
    if kind == TermKind.SINGLETON and lam < 1:
        return None
    hole = _superlevel(kind, p, (1.0 - lam) ** (1.0 / power), strict=True)
    if hole is None:
        return [(-INF, INF)]
    return [iv for iv in ((-INF, hole[0]), (hole[1], INF)) if iv[0] <= iv[1]
            and not (np.isinf(iv[0]) and np.isinf(iv[1]) and iv[0] == iv[1])]
