"""Membership functions of a variable's terms, vectorized over a batch of crisp values.

`memberships` is the reference (it follows the model's docstring literally). `LocalPartition`
is the fast path the engine uses when a variable's terms are continuous piecewise-linear and at
most two of them are positive at any point (the usual triangle partitions): per sample it finds
the segment between break points with one `searchsorted` and evaluates only the two terms that
can be active there, with the very same arithmetic as `memberships` (bit-identical results).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..semantics.model import Hedge, TermKind, Variable
from ..semantics.shape_functions import discrete_problem, mu_function, trapezoid
from ..semantics.shapes import SHAPES
from ..semantics.operators import HEDGES, power_exponents

# The power hedges' exponents, indexed by Hedge (NONE VERY SOMEWHAT EXTREMELY: the operator
# registry's); the others (SELDOM, SHARPLY) are piecewise and have no entry, so code that only
# knows powers fails loudly on them.
HEDGE_EXPONENT = power_exponents()
PIECEWISE_HEDGES = tuple(h for h, rec in HEDGES.items() if rec.exponent is None)
LINEAR_SEARCH_BREAKS = 16


def apply_hedges(mu: np.ndarray, hedges: np.ndarray) -> np.ndarray:
    """mu (N, R) with hedges (R,) Hedge per column -> the hedged truth (N, R)."""
    power = HEDGE_EXPONENT[np.where(hedges < len(HEDGE_EXPONENT), hedges, Hedge.NONE)]
    out = mu ** power
    for hedge in PIECEWISE_HEDGES:      # each its registry record's function
        cols = np.flatnonzero(hedges == hedge)
        if cols.size:
            out[:, cols] = HEDGES[hedge].numpy(mu[:, cols])
    return out


def linear_coefficients(var: Variable, n_inputs: int) -> np.ndarray:
    """(T, 1 + n_inputs): c0, c1.. of each LINEAR term of an output (rows of other terms 0)."""
    out = np.zeros((var.n_terms, 1 + n_inputs))
    for t in np.flatnonzero(var.kinds == TermKind.LINEAR):
        extra = (var.coefficients or {}).get(int(t))
        row = np.asarray(extra if extra is not None else var.params[t], dtype=float)
        if n_inputs + 1 > len(row) or np.any(row[n_inputs + 1:] != 0.0):
            raise ValueError(f"linear term `{var.names[t]}` of `{var.name}` has "
                             f"{len(row)} coefficients for {n_inputs} inputs")
        out[t] = row[:n_inputs + 1]
    return out


def monotonic(kind: TermKind, params) -> bool:
    """Whether the term has one inverse (Tsukamoto): the registry's record says."""
    return SHAPES[TermKind(int(kind))].monotone(params)


def term_inverse(kinds: np.ndarray, params: np.ndarray, y: np.ndarray) -> np.ndarray:
    """z where each monotonic term (kinds (...), params (..., 4)) equals y (...) in (0, 1]."""
    a, b, c, d = np.moveaxis(np.asarray(params, dtype=float), -1, 0)
    out = np.full(np.shape(y), np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        for kind, record in SHAPES.items():
            if record.inverse is not None:
                out = np.where(kinds == kind, record.inverse(a, b, c, d, y), out)
    return out


def pointwise(kind: TermKind, params: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The membership of terms of one kind, params (..., 4), each at its own point u (...)."""
    p = np.asarray(params, dtype=float).reshape(-1, 4)
    with np.errstate(invalid="ignore", divide="ignore"):
        return SHAPES[kind].membership(np.ravel(u), p).reshape(np.shape(u))


def term_values(kinds: np.ndarray, params: np.ndarray, x: np.ndarray,
                points: dict[int, np.ndarray] | None = None,
                formulas: dict | None = None) -> np.ndarray:
    """Membership of terms given as (kinds (T,), params (T, 4)) at x (N,) -> (N, T); `points`
    are the DISCRETE terms' (Variable.points), `formulas` the FUNCTION terms'.

    NaN x gives 0 for every term; infinities give the shapes' limits (never NaN).
    """
    x = np.asarray(x, dtype=float).reshape(-1, 1)
    params = np.asarray(params, dtype=float)
    mu = np.zeros((x.shape[0], len(kinds)))
    for kind in np.unique(kinds):
        cols = np.flatnonzero(kinds == kind)
        with np.errstate(invalid="ignore"):
            record = SHAPES[TermKind(int(kind))]
            if record.per_term:     # a DISCRETE term's points, a FUNCTION term's formula
                data = points if kind == TermKind.DISCRETE else formulas
                for t in cols:
                    mu[:, t] = record.membership(x[:, 0], (data or {})[int(t)])
                continue
            mu[:, cols] = record.membership(x, params[cols])
    mu[np.isnan(mu)] = 0.0  # NaN x, or an infinite x where a shape has no limit (0 * inf)
    mu[np.isnan(x[:, 0])] = 0.0   # edge shapes' comparisons would read NaN as "beyond the end"
    return mu


def memberships(var: Variable, x: np.ndarray) -> np.ndarray:
    """x (N,) -> mu (N, T) for the terms of `var`."""
    return term_values(var.kinds, var.params, x, var.points, var.formulas)


def function_membership(formula, x: np.ndarray) -> np.ndarray:
    """A FUNCTION term's membership at x (N,) (the registry's record)."""
    return mu_function(x, formula)


@dataclass
class LocalPartition:
    """Per segment between break points, the (at most two) terms that can be positive there.

    Segment k = searchsorted(breaks, x, 'right'); slot s of segment k holds a term id (or the
    dummy id T) and the piece mu = (x - anchor) / width + offset of that term on the segment:
    a rise (anchor a, width b - a), a fall (anchor d, width c - d) or the top (width inf,
    offset 1).  The dummy slot is (anchor 0, width inf, offset 0) = 0.
    """
    breaks: np.ndarray    # (B,) sorted finite break points
    table: np.ndarray     # (B + 1, 8): anchor, width, offset, term id of the two slots
    n_terms: int

    def __post_init__(self):
        self.columns = np.ascontiguousarray(self.table[:, :6].T)  # anchor, width, offset
        self.count_breaks = len(self.breaks) <= LINEAR_SEARCH_BREAKS
        self.column_breaks = self.breaks[:, None]

    @classmethod
    def build(cls, var: Variable) -> "LocalPartition | None":
        """The partition of `var`, or None if the fast path does not apply to its terms."""
        kinds, p = var.kinds, np.asarray(var.params, dtype=float)
        if len(kinds) == 0 or np.any(kinds != TermKind.TRAPEZOID):
            return None
        a, b, c, d = p.T
        # Vertical edges would make the membership discontinuous at a break point.
        if np.any(np.isfinite(a) & (a >= b)) or np.any(np.isfinite(d) & (c >= d)):
            return None
        breaks = np.unique(p[np.isfinite(p)])
        if breaks.size == 0:
            return None
        inner = 0.5 * (breaks[:-1] + breaks[1:])
        probes = np.concatenate([[breaks[0] - 1.0], inner, [breaks[-1] + 1.0]])
        mu = memberships(var, probes)
        if np.any((mu > 0).sum(axis=1) > 2):
            return None
        n_seg, n_terms = len(probes), len(kinds)
        terms = np.full((n_seg, 2), n_terms)
        anchor = np.zeros((n_seg, 2))
        width = np.full((n_seg, 2), np.inf)
        offset = np.zeros((n_seg, 2))
        for k, u in enumerate(probes):
            for s, t in enumerate(np.flatnonzero(mu[k] > 0)):
                terms[k, s] = t
                if not np.isneginf(a[t]) and u < b[t]:
                    anchor[k, s], width[k, s] = a[t], b[t] - a[t]
                elif not np.isposinf(d[t]) and u > c[t]:
                    anchor[k, s], width[k, s] = d[t], c[t] - d[t]
                else:
                    offset[k, s] = 1.0
        return cls(breaks, np.hstack([anchor, width, offset, terms]), n_terms)

    def locate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """x (N,) -> (segment (N,), memberships of the segment's two slots (2, N)).

        NaN x -> segment 0 with memberships 0.  Slot-major so numpy's loops run over N."""
        # Outside the outermost break points every term is constant, so clipping changes no
        # membership and keeps infinities out of the arithmetic.
        xc = np.clip(x, self.breaks[0], self.breaks[-1])
        if self.count_breaks:       # counting beats a binary search here
            seg = (xc >= self.column_breaks).sum(axis=0)
        else:
            seg = np.searchsorted(self.breaks, xc, side="right")
        has_nan = np.isnan(xc.sum())      # one pass; an inf - inf false alarm only costs time
        if has_nan:
            nan = np.isnan(xc)
            xc = np.where(nan, self.breaks[0], xc)
            seg = np.where(nan, 0, seg)
        row = self.columns.take(seg, axis=1)
        mu = (xc - row[0:2]) / row[2:4] + row[4:6]
        if has_nan:
            mu[:, nan] = 0.0
        return seg, mu

    def active(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """x (N,) -> (term ids (N, 2), memberships (N, 2)); NaN x -> dummy ids, 0."""
        seg, mu = self.locate(x)
        terms = self.table[seg, 6:8].astype(np.intp)
        terms[np.isnan(x)] = self.n_terms
        return terms, mu.T
