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

# The power hedges, indexed by Hedge (NONE VERY SOMEWHAT EXTREMELY); the others (SELDOM,
# SHARPLY) are piecewise and have no entry, so code that only knows powers fails loudly on them.
HEDGE_EXPONENT = np.array([1.0, 2.0, 0.5, 3.0])
LINEAR_SEARCH_BREAKS = 16


def trapezoid(x, a, b, c, d) -> np.ndarray:
    """The trapezoid membership, broadcasting x against the parameters.

    An infinite a (or d) makes a shoulder: its rise (fall) is 1 everywhere.
    """
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        rise = np.where(x >= b, 1.0, np.where(x > a, (x - a) / (b - a), 0.0))
        fall = np.where(x <= c, 1.0, np.where(x < d, (d - x) / (d - c), 0.0))
    rise = np.where(np.isneginf(a), 1.0, rise)
    fall = np.where(np.isposinf(d), 1.0, fall)
    return np.minimum(rise, fall)


def _trapezoid(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return trapezoid(x, p[:, 0], p[:, 1], p[:, 2], p[:, 3])


def _gaussian(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    mean, sigma = p[:, 0], p[:, 1]
    return np.exp(-((x - mean) ** 2) / (2.0 * sigma ** 2))


def _bell(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, width, slope = p[:, 0], p[:, 1], p[:, 2]
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.abs((x - center) / width) ** (2.0 * slope))


def _sigmoid(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, slope = p[:, 0], p[:, 1]
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-slope * (x - center)))


def _singleton(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return (x == p[:, 0]).astype(float)


def _s_shape(x: np.ndarray, s: np.ndarray, e: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return np.where(x <= s, 0.0, np.where(
            x <= 0.5 * (s + e), 2.0 * ((x - s) / (e - s)) ** 2,
            np.where(x < e, 1.0 - 2.0 * ((x - e) / (e - s)) ** 2, 1.0)))


def _z_shape(x: np.ndarray, s: np.ndarray, e: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return np.where(x <= s, 1.0, np.where(
            x < 0.5 * (s + e), 1.0 - 2.0 * ((x - s) / (e - s)) ** 2,
            np.where(x < e, 2.0 * ((x - e) / (e - s)) ** 2, 0.0)))


def _sshape(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _s_shape(x, p[:, 0], p[:, 1])


def _zshape(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _z_shape(x, p[:, 0], p[:, 1])


def _pishape(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _s_shape(x, p[:, 0], p[:, 1]) * _z_shape(x, p[:, 2], p[:, 3])


def _spike(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, width = p[:, 0], p[:, 1]
    return np.exp(-np.abs(10.0 / width * (x - center)))


def _cosine(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, width = p[:, 0], p[:, 1]
    inside = np.abs(x - center) <= 0.5 * width
    # cos of an infinite x is NaN, and x is outside there anyway
    arg = np.where(inside, 2.0 * np.pi / width * (x - center), 0.0)
    return np.where(inside, 0.5 * (1.0 + np.cos(arg)), 0.0)


def _concave(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    i, e = p[:, 0], p[:, 1]
    rising, falling = (i <= e) & (x < e), (i > e) & (x > e)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return np.where(rising, (e - i) / (2.0 * e - i - x),
                        np.where(falling, (i - e) / (i - 2.0 * e + x), 1.0))


def _sig(x: np.ndarray, center: np.ndarray, slope: np.ndarray) -> np.ndarray:
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-slope * (x - center)))


def _sigmoid_difference(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.abs(_sig(x, p[:, 0], p[:, 1]) - _sig(x, p[:, 3], p[:, 2]))


def _sigmoid_product(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _sig(x, p[:, 0], p[:, 1]) * _sig(x, p[:, 3], p[:, 2])


def _gaussian_product(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    left = np.where(x < p[:, 0], _gaussian(x, p[:, 0:2]), 1.0)
    right = np.where(x > p[:, 2], _gaussian(x, p[:, 2:4]), 1.0)
    return left * right


def _binary(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    start, direction = p[:, 0], p[:, 1]
    return (((direction > start) & (x >= start)) | ((direction < start) & (x <= start))) * 1.0


def _circle(x: np.ndarray, center: np.ndarray, r: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """sqrt(r^2 - (x - center)^2) / |r| where `inside` (elsewhere 0: no root of a negative)."""
    dx = np.where(inside, x - center, 0.0)
    return np.where(inside, np.sqrt(np.maximum(r * r - dx * dx, 0.0)) / np.abs(r), 0.0)


def _semi_ellipse(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    s, e = np.minimum(p[:, 0], p[:, 1]), np.maximum(p[:, 0], p[:, 1])
    r = 0.5 * (e - s)
    return _circle(x, s + r, r, (x >= s) & (x <= e))


def _arc(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    s, e = p[:, 0], p[:, 1]
    rising = s < e
    between = np.where(rising, (s <= x) & (x <= e), (e <= x) & (x <= s))
    beyond = np.where(rising, x > e, x < e)
    return np.where(beyond, 1.0, _circle(x, e, e - s, between))


def _linear(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.zeros((x.shape[0], p.shape[0]))   # a consequent value, not a shape


_SHAPES = {
    TermKind.TRAPEZOID: _trapezoid,
    TermKind.GAUSSIAN: _gaussian,
    TermKind.BELL: _bell,
    TermKind.SIGMOID: _sigmoid,
    TermKind.SINGLETON: _singleton,
    TermKind.SSHAPE: _sshape,
    TermKind.ZSHAPE: _zshape,
    TermKind.PISHAPE: _pishape,
    TermKind.SPIKE: _spike,
    TermKind.COSINE: _cosine,
    TermKind.CONCAVE: _concave,
    TermKind.LINEAR: _linear,
    TermKind.SIGMOID_DIFFERENCE: _sigmoid_difference,
    TermKind.SIGMOID_PRODUCT: _sigmoid_product,
    TermKind.GAUSSIAN_PRODUCT: _gaussian_product,
    TermKind.BINARY: _binary,
    TermKind.SEMI_ELLIPSE: _semi_ellipse,
    TermKind.ARC: _arc,
}


def apply_hedges(mu: np.ndarray, hedges: np.ndarray) -> np.ndarray:
    """mu (N, R) with hedges (R,) Hedge per column -> the hedged truth (N, R)."""
    power = HEDGE_EXPONENT[np.where(hedges < len(HEDGE_EXPONENT), hedges, Hedge.NONE)]
    out = mu ** power
    for hedge, low, high in ((Hedge.SELDOM, lambda m: np.sqrt(0.5 * m),
                              lambda m: 1.0 - np.sqrt(0.5 * (1.0 - m))),
                             (Hedge.SHARPLY, lambda m: 2.0 * m * m,
                              lambda m: 1.0 - 2.0 * (1.0 - m) ** 2)):
        cols = np.flatnonzero(hedges == hedge)
        if cols.size:
            m = np.clip(mu[:, cols], 0.0, 1.0)
            out[:, cols] = np.where(m <= 0.5, low(m), high(m))
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


def discrete_problem(values) -> str:
    """'' when x1 y1 x2 y2 ... make a DISCRETE term, else what is wrong."""
    if len(values) < 2 or len(values) % 2 or not all(map(np.isfinite, values)):
        return "a discrete term is pairs of finite numbers x y (at least one)"
    xs, ys = values[0::2], values[1::2]
    if any(p >= q for p, q in zip(xs, xs[1:])) or any(not 0 <= y <= 1 for y in ys):
        return "a discrete term's x values must ascend and its y values lie in [0, 1]"
    return ""


def monotonic(kind: TermKind, params) -> bool:
    """Whether the term has one inverse (Tsukamoto): a shoulder, sigmoid, S/Z shape, concave;
    a singleton counts (its value is its own)."""
    if kind == TermKind.TRAPEZOID:
        return bool(np.isinf(params[0]) != np.isinf(params[3]))
    return kind in (TermKind.SIGMOID, TermKind.SSHAPE, TermKind.ZSHAPE, TermKind.CONCAVE,
                    TermKind.SINGLETON)


def term_inverse(kinds: np.ndarray, params: np.ndarray, y: np.ndarray) -> np.ndarray:
    """z where each monotonic term (kinds (...), params (..., 4)) equals y (...) in (0, 1]."""
    a, b, c, d = np.moveaxis(np.asarray(params, dtype=float), -1, 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        low, high = np.sqrt(y / 2.0), np.sqrt((1.0 - y) / 2.0)
        z = {TermKind.TRAPEZOID: np.where(np.isinf(d), a + (b - a) * y, d - (d - c) * y),
             TermKind.SIGMOID: a - np.log(1.0 / y - 1.0) / b,
             TermKind.SSHAPE: np.where(y <= 0.5, a + (b - a) * low, b - (b - a) * high),
             TermKind.ZSHAPE: np.where(y <= 0.5, b - (b - a) * low, a + (b - a) * high),
             TermKind.CONCAVE: 2.0 * b - a - (b - a) / y,
             TermKind.SINGLETON: a}
    out = np.full(np.shape(y), np.nan)
    for kind, values in z.items():
        out = np.where(kinds == kind, values, out)
    return out


def pointwise(kind: TermKind, params: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The membership of terms of one kind, params (..., 4), each at its own point u (...)."""
    p = np.asarray(params, dtype=float).reshape(-1, 4)
    with np.errstate(invalid="ignore", divide="ignore"):
        return _SHAPES[kind](np.ravel(u), p).reshape(np.shape(u))


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
            if kind == TermKind.DISCRETE:
                # np.interp holds the first and last y beyond the points, as the model says
                for t in cols:
                    xy = (points or {})[int(t)]
                    mu[:, t] = np.interp(x[:, 0], xy[:, 0], xy[:, 1])
                continue
            if kind == TermKind.FUNCTION:
                for t in cols:
                    mu[:, t] = function_membership(formulas[int(t)], x[:, 0])
                continue
            mu[:, cols] = _SHAPES[TermKind(int(kind))](x, params[cols])
    mu[np.isnan(mu)] = 0.0  # NaN x, or an infinite x where a shape has no limit (0 * inf)
    mu[np.isnan(x[:, 0])] = 0.0   # edge shapes' comparisons would read NaN as "beyond the end"
    return mu


def memberships(var: Variable, x: np.ndarray) -> np.ndarray:
    """x (N,) -> mu (N, T) for the terms of `var`."""
    return term_values(var.kinds, var.params, x, var.points, var.formulas)


def function_membership(formula, x: np.ndarray) -> np.ndarray:
    """A FUNCTION term's membership at x (N,): the formula of x, 0 where it is not finite; a
    formula of other variables (a Takagi-Sugeno value) has no shape: 0, as a LINEAR term."""
    if not formula.names() <= {"x"}:
        return np.zeros(x.shape[0])
    mu = np.broadcast_to(formula.evaluate({"x": x}), x.shape)
    return np.where(np.isfinite(mu), mu, 0.0)


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
