"""The defuzzifiers' formulas: a crisp value from an aggregated shape or from term strengths.

Moved out of `defuzz` (which prepares the shapes and strengths) so that the operator registry
(`fuzzyc.semantics.operators`) can name each defuzzifier's own function, and the engine calls
it through the registry.  Three families, by what they read:
- area (x, f, default): M piecewise linear through the points (x, f) (N, P), exactly;
- peaks (num, den, default): num = sum_j alpha_j z_j, den = sum_j alpha_j (N,);
- the same ratio for Tsukamoto, whose z_r are the terms' inverses at the rules' levels.
"""
from __future__ import annotations

import numpy as np

# M counts as maximal where M >= top (1 - FLAT_TOLERANCE), top = max(M): relative, so that a
# low top is not flat everywhere (the absolute top - 1e-12 made every point of a top of 1e-15
# a maximum, the mean of maximum the range's midpoint; the float C's 4.8e-7 did at 1e-9)
FLAT_TOLERANCE = 1e-12
# ulps a clip point may move toward its term's top (_at_level; the C headers do the same): the
# rounding of a + h (b - a) or of d - h (d - c) is half an ulp, the term's value there a few
AT_LEVEL_STEPS = 3


def safe_ratio(num: np.ndarray, den: np.ndarray, default) -> np.ndarray:
    """num / den where den > 0, else default (a number, or an array broadcast against them)."""
    if np.size(den) and den.min() > 0:      # every den positive (a NaN min is not): no mask
        return num / den
    ok = den > 0
    return np.where(ok, num / np.where(ok, den, 1.0), default)


def weighted_sum(num: np.ndarray, den: np.ndarray, default) -> np.ndarray:
    """num where some strength is positive, else default (the neuro-fuzzy output)."""
    return np.where(den > 0, num, default)


def _pieces(x: np.ndarray, f: np.ndarray):
    x0, x1, f0, f1 = x[:, :-1], x[:, 1:], f[:, :-1], f[:, 1:]
    dx = x1 - x0
    piece_area = 0.5 * (f0 + f1) * dx
    return x0, x1, f0, f1, dx, piece_area, piece_area.sum(axis=1)


def centroid(x: np.ndarray, f: np.ndarray, default: float) -> np.ndarray:
    """Exact centroid of the piecewise-linear (x, f)."""
    x0, x1, f0, f1, dx, _, area = _pieces(x, f)
    moment = (dx * (f0 * (2 * x0 + x1) + f1 * (x0 + 2 * x1)) / 6.0).sum(axis=1)
    return safe_ratio(moment, area, default)


def bisector(x: np.ndarray, f: np.ndarray, default: float) -> np.ndarray:
    """Exact bisector of the piecewise-linear (x, f)."""
    x0, _, f0, f1, dx, piece_area, area = _pieces(x, f)
    return np.where(area > 0, _bisector(x0, dx, f0, f1, piece_area, area), default)


def _bisector(x0, dx, f0, f1, piece_area, area) -> np.ndarray:
    """The leftmost u with int_lo^u M = area / 2, solving the quadratic inside its piece."""
    half = 0.5 * area
    before = np.cumsum(piece_area, axis=1) - piece_area
    k = np.argmax(before + piece_area >= half[:, None], axis=1)[:, None]
    take = lambda a: np.take_along_axis(a, k, axis=1)[:, 0]   # noqa: E731
    rem = half - take(before)
    a0, d, g0, g1 = take(x0), take(dx), take(f0), take(f1)
    slope = np.where(d > 0, (g1 - g0) / np.where(d > 0, d, 1.0), 0.0)
    # t solves g0 t + slope t^2 / 2 = rem; this form is stable for slope = 0 too.
    den = g0 + np.sqrt(np.maximum(g0 * g0 + 2.0 * slope * rem, 0.0))
    t = np.where(den > 0, 2.0 * rem / np.where(den > 0, den, 1.0), 0.0)
    return a0 + np.clip(t, 0.0, d)


def smallest_of_maximum(x: np.ndarray, f: np.ndarray, default: float) -> np.ndarray:
    """The smallest x where the piecewise-linear (x, f) is largest (as mean_of_maximum)."""
    return _end_of_maximum(x, f, default, last=False)


def largest_of_maximum(x: np.ndarray, f: np.ndarray, default: float) -> np.ndarray:
    """The largest x where the piecewise-linear (x, f) is largest (as mean_of_maximum)."""
    return _end_of_maximum(x, f, default, last=True)


def _end_of_maximum(x: np.ndarray, f: np.ndarray, default: float, last: bool) -> np.ndarray:
    top = f.max(axis=1)
    is_top = f >= (top * (1.0 - FLAT_TOLERANCE))[:, None]
    k = is_top.shape[1] - 1 - np.argmax(is_top[:, ::-1], axis=1) if last \
        else np.argmax(is_top, axis=1)
    at = np.take_along_axis(np.broadcast_to(x, f.shape), k[:, None], axis=1)[:, 0]
    return np.where(top > 0, at, default)


def mean_of_maximum(x: np.ndarray, f: np.ndarray, default: float) -> np.ndarray:
    """The mean of the set where the piecewise-linear (x, f) is largest."""
    top = f.max(axis=1)
    is_top = f >= (top * (1.0 - FLAT_TOLERANCE))[:, None]
    x0, x1 = x[:, :-1], x[:, 1:]
    # A vertical edge is stored as two points a few ulps apart (_at_level moves clip points
    # by up to AT_LEVEL_STEPS ulps): a piece that short is one point, not a plateau, or a
    # one-ulp "plateau" at a vertical edge would outweigh every isolated peak.
    apart = (x1 - x0) > 2 * AT_LEVEL_STEPS * np.spacing(np.maximum(np.abs(x0), np.abs(x1)))
    plateau = is_top[:, :-1] & is_top[:, 1:] & apart
    length = np.where(plateau, x1 - x0, 0.0)
    total = length.sum(axis=1)
    plateau_mean = (length * 0.5 * (x0 + x1)).sum(axis=1) / np.where(total > 0, total, 1.0)
    # Isolated maxima: each run of top points closer than `apart` is one point, counted at its
    # first (the point list repeats a point, or splits it across a vertical edge).
    starts = ~(is_top[:, :-1] & ~apart)
    distinct = np.concatenate([np.ones((len(x), 1), bool), starts], axis=1) & is_top
    point_mean = (np.where(distinct, x, 0.0).sum(axis=1)
                  / np.maximum(distinct.sum(axis=1), 1))
    return np.where(top > 0, np.where(total > 0, plateau_mean, point_mean), default)
