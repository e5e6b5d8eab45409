"""Sound enclosures of a term's membership over intervals: for boxes [lo, hi] (N,) and terms
p (T, 4), the least and largest membership the engine reaches for any x in the box (N, T).

Two ways, both sound:
- by critical points: where a shape may change direction or jump is known in closed form
  (a peak, a plateau's ends, a jump), so between them it is monotone and its extremes over a
  box are among its values at lo, hi and the critical points inside.  Exact: the extremes are
  values the shape takes in the box (a jump counts: the shape takes its value at the jump
  point; every shape here is closed at its jumps).
- by composition: a shape built from monotone factors (sigmoid difference and product, a
  pi shape whose S and Z overlap) bounds each factor by its end values and combines the
  factor intervals (product of non-negative intervals, |difference|): sound, not exact.
Values are the engine's own (the registry's membership functions, NaN read as 0), so the
bounds hold the engine's floating-point numbers, not only the real ones.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

Membership = Callable[[np.ndarray, np.ndarray], np.ndarray]


def values(membership: Membership, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The engine's membership (N, T) of terms p at x (N,): NaN results and NaN x read 0."""
    x = np.asarray(x, dtype=float).reshape(-1, 1)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        mu = np.array(np.broadcast_to(membership(x, p), (x.shape[0], p.shape[0])), dtype=float)
    mu[np.isnan(mu)] = 0.0
    mu[np.isnan(x[:, 0])] = 0.0
    return mu


def by_critical_points(membership: Membership, critical: Callable[[np.ndarray], np.ndarray]):
    """The enclosure of a shape monotone between its critical points (T, K) (NaN: none)."""
    def enclose(p: np.ndarray, lo: np.ndarray, hi: np.ndarray):
        at_lo, at_hi = values(membership, lo, p), values(membership, hi, p)
        low, high = np.minimum(at_lo, at_hi), np.maximum(at_lo, at_hi)
        points = np.asarray(critical(p), dtype=float).reshape(len(p), -1)   # (T, K)
        if points.shape[1]:
            k = points.shape[1]
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
                at = membership(points.ravel(), np.repeat(p, k, axis=0)).reshape(len(p), k)
            at = np.where(np.isnan(at), 0.0, at)
            inside = (lo[:, None, None] <= points) & (points <= hi[:, None, None])   # (N, T, K)
            low = np.minimum(low, np.where(inside, at, np.inf).min(axis=2))
            high = np.maximum(high, np.where(inside, at, -np.inf).max(axis=2))
        return low, high
    return enclose


def monotone_range(membership: Membership, p: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """A monotone factor over [lo, hi]: its end values, ordered."""
    at_lo, at_hi = values(membership, lo, p), values(membership, hi, p)
    return np.minimum(at_lo, at_hi), np.maximum(at_lo, at_hi)


def product_of(first: Membership, second: Membership):
    """The enclosure of first * second, both monotone and in [0, 1]."""
    def enclose(p, lo, hi):
        l1, h1 = monotone_range(first, p, lo, hi)
        l2, h2 = monotone_range(second, p, lo, hi)
        return l1 * l2, h1 * h2
    return enclose


def distance_of(first: Membership, second: Membership):
    """The enclosure of |first - second|, both monotone."""
    def enclose(p, lo, hi):
        l1, h1 = monotone_range(first, p, lo, hi)
        l2, h2 = monotone_range(second, p, lo, hi)
        least, most = l1 - h2, h1 - l2
        low = np.where((least <= 0) & (most >= 0), 0.0,
                       np.minimum(np.abs(least), np.abs(most)))
        return low, np.maximum(np.abs(least), np.abs(most))
    return enclose


def choose(use_first: Callable[[np.ndarray], np.ndarray], first, second):
    """Per term, the first enclosure where use_first(p) (T,) holds, else the second."""
    def enclose(p, lo, hi):
        pick = np.asarray(use_first(p), dtype=bool)
        l1, h1 = first(p, lo, hi)
        l2, h2 = second(p, lo, hi)
        return np.where(pick, l1, l2), np.where(pick, h1, h2)
    return enclose


def zero(p, lo, hi):
    """A shape that is 0 everywhere (a linear consequent's membership): exactly [0, 0]."""
    out = np.zeros((len(lo), len(p)))
    return out, out.copy()


def discrete(xy: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """One DISCRETE term's points xy (K, 2) over boxes (N,): linear between its points, so
    the extremes are at lo, hi and the points' x inside.  Exact.  -> (N,), (N,)."""
    def at(x):
        mu = np.interp(x, xy[:, 0], xy[:, 1])
        return np.where(np.isnan(x), 0.0, mu)
    at_lo, at_hi = at(lo), at(hi)
    inside = (lo[:, None] <= xy[None, :, 0]) & (xy[None, :, 0] <= hi[:, None])
    low = np.minimum(np.minimum(at_lo, at_hi), np.where(inside, xy[None, :, 1], np.inf).min(1))
    high = np.maximum(np.maximum(at_lo, at_hi), np.where(inside, xy[None, :, 1], -np.inf).max(1))
    return low, high
