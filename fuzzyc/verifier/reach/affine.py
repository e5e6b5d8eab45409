"""Affine forms over a batch of boxes: the set type of the closed-loop proofs.

A quantity is x = c + sum_k g_k eps_k with every noise symbol eps_k in [-1, 1], one (c, g) per
box of the batch (arrays (B,) and (B, K)). Symbols are shared by every form of one run
(`Symbols`), so x - x is 0 and a feedback loop keeps the correlation between its signals: plain
intervals would add the width of the controller's answer to the plant's instead of cancelling
it (the wrapping effect), and no stable loop stays bounded under them for long.

Linear operations are exact. A nonlinear function f of one form goes through `apply`: the
secant slope a over the form's range [lo, hi], and the range of f(x) - a x over [lo, hi],
bounded piece by piece on `PIECES` sub-intervals with f's interval extension (`f_box(lo, hi)`
must return a sound enclosure of f over [lo, hi]); the result is a x + mid + rad eps_new.
Any slope gives a sound form; the secant makes the new error small.

Rounding: the arithmetic is plain float64 (round to nearest). Every new error term is widened
by `SLACK` (relative) + `TINY` (absolute), which covers the rounding of the operation that made
it; the linear operations' own rounding (a few ulps of values of order 1e2 per step) is far
below the margins the decisions keep (fuzzyc.verifier.reach.decide.MARGIN).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

PIECES = 24
SLACK = 1e-12
TINY = 1e-15

BoxFunction = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


class Symbols:
    """The noise symbols of one run: a counter; forms pad their generators to it lazily."""

    def __init__(self, batch: int):
        self.batch = batch
        self.count = 0

    def fresh(self) -> int:
        self.count += 1
        return self.count - 1


class Affine:
    __slots__ = ("sym", "c", "g")
    __array_ufunc__ = None      # numpy scalars defer to the reflected operators below

    def __init__(self, sym: Symbols, c, g: np.ndarray | None = None):
        self.sym = sym
        if not (isinstance(c, np.ndarray) and c.shape == (sym.batch,) and c.dtype == float):
            c = np.broadcast_to(np.asarray(c, dtype=float), (sym.batch,)).copy()
        self.c = c         # forms never write into their arrays: sharing them is safe
        self.g = np.zeros((sym.batch, 0)) if g is None else g

    # --- construction ---------------------------------------------------------------------
    @classmethod
    def interval(cls, sym: Symbols, lo, hi) -> "Affine":
        """A new symbol spanning [lo, hi] (per box)."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        out = cls(sym, 0.5 * (lo + hi))
        return out.with_error(0.5 * (hi - lo))

    def with_error(self, radius) -> "Affine":
        """self + radius * eps_new (radius >= 0 per box)."""
        k = self.sym.fresh()
        g = self._padded(k + 1)
        g[:, k] = np.abs(np.broadcast_to(radius, (self.sym.batch,)))
        return Affine(self.sym, self.c, g)

    # --- views ------------------------------------------------------------------------------
    def _padded(self, width: int) -> np.ndarray:
        g = self.g
        if g.shape[1] < width:
            g = np.concatenate([g, np.zeros((g.shape[0], width - g.shape[1]))], axis=1)
        else:
            g = g.copy()
        return g

    def radius(self) -> np.ndarray:
        return np.abs(self.g).sum(axis=1)

    def lo(self) -> np.ndarray:
        return self.c - self.radius()

    def hi(self) -> np.ndarray:
        return self.c + self.radius()

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        r = self.radius()
        return self.c - r, self.c + r

    # --- linear arithmetic ------------------------------------------------------------------
    def __add__(self, other) -> "Affine":
        if isinstance(other, Affine):
            width = max(self.g.shape[1], other.g.shape[1])
            return Affine(self.sym, self.c + other.c,
                          self._padded(width) + other._padded(width))
        return Affine(self.sym, self.c + np.asarray(other, float), self.g)

    __radd__ = __add__

    def __neg__(self) -> "Affine":
        return Affine(self.sym, -self.c, -self.g)

    def __sub__(self, other) -> "Affine":
        return self + (-other)

    def __rsub__(self, other) -> "Affine":
        return (-self) + other

    def scale(self, k) -> "Affine":
        k = np.asarray(k, float)
        kg = k[:, None] if k.ndim == 1 else k
        return Affine(self.sym, self.c * k, self.g * kg)

    def __mul__(self, other) -> "Affine":
        if not isinstance(other, Affine):
            return self.scale(other)
        # (c1 + g1)(c2 + g2) = c1 c2 + c1 g2 + c2 g1 + g1 g2, |g1 g2| <= r1 r2
        width = max(self.g.shape[1], other.g.shape[1])
        g = self.c[:, None] * other._padded(width) + other.c[:, None] * self._padded(width)
        out = Affine(self.sym, self.c * other.c, g)
        return out.with_error(self.radius() * other.radius() * (1 + SLACK) + TINY)

    __rmul__ = __mul__

    # --- nonlinear functions ------------------------------------------------------------------
    def apply(self, f_box: BoxFunction) -> "Affine":
        """f(self) for f with the interval extension f_box (see the module docstring)."""
        lo, hi = self.bounds()
        flo_a, fhi_a = f_box(lo, lo)
        flo_b, fhi_b = f_box(hi, hi)
        width = hi - lo
        wide = width > 0
        slope = np.where(wide, (0.5 * (flo_b + fhi_b) - 0.5 * (flo_a + fhi_a))
                         / np.where(wide, width, 1.0), 0.0)
        t = np.linspace(0.0, 1.0, PIECES + 1)
        edges = lo[:, None] + width[:, None] * t
        edges[:, -1] = hi
        a, b = edges[:, :-1], edges[:, 1:]
        flo, fhi = f_box(a, b)
        s = slope[:, None]
        low = (flo - np.maximum(s * a, s * b)).min(axis=1)
        high = (fhi - np.minimum(s * a, s * b)).max(axis=1)
        mid, rad = 0.5 * (low + high), 0.5 * (high - low)
        rad = rad + SLACK * (np.abs(mid) + rad) + TINY
        return (self.scale(slope) + mid).with_error(rad)

    def clip(self, lo: float, hi: float) -> "Affine":
        """clip(self, lo, hi); a box already inside keeps its form (apply would widen it by
        the pieces' slack because another box of the batch needs the clip)."""
        xlo, xhi = self.bounds()
        inside = (xlo >= lo) & (xhi <= hi)
        if np.all(inside):
            return self
        return where(inside, self, self.apply(monotone(lambda x: np.clip(x, lo, hi))))


def where(mask: np.ndarray, a: Affine, b: Affine) -> Affine:
    """Per box, a where mask (B,) holds, else b: the boxes are separate runs, so each may take
    either form of the same symbols."""
    width = max(a.g.shape[1], b.g.shape[1])
    return Affine(a.sym, np.where(mask, a.c, b.c),
                  np.where(mask[:, None], a._padded(width), b._padded(width)))


def join(pairs: list[tuple[Affine, Affine]]) -> list[Affine]:
    """Per box, either every first form of the pairs or every second one (two sets of runs of
    one state, over the same symbols): Girard's enclosure of the convex hull of two
    zonotopes. For a = ca + Ga e and b = cb + Gb e,
        x = (ca + cb)/2 + (Ga + Gb)/2 e + (ca - cb)/2 s + (Ga - Gb)/2 d
    with s and d (one new symbol per symbol the pairs differ in) new and shared by every
    pair: s = 1, d = e gives a, s = -1, d = -e gives b, for all pairs at once, so the joined
    quantities keep their correlations with each other and, through e, with every other form.
    Linear arithmetic only: no error term (the module docstring's rounding note)."""
    sym = pairs[0][0].sym
    width = max(f.g.shape[1] for pair in pairs for f in pair)
    ga = np.stack([a._padded(width) for a, _ in pairs])                  # (F, B, K)
    gb = np.stack([b._padded(width) for _, b in pairs])
    half_c = np.stack([0.5 * (a.c - b.c) for a, b in pairs])            # (F, B)
    half_g = 0.5 * (ga - gb)
    differ = np.flatnonzero(np.any(half_g != 0, axis=(0, 1)))
    first = sym.count
    sym.count += 1 + len(differ)
    new = np.zeros(half_g.shape[:2] + (sym.count - width,))
    new[:, :, first - width] = half_c
    new[:, :, first - width + 1:] = half_g[:, :, differ]
    g = np.concatenate([0.5 * (ga + gb), new], axis=2)
    return [Affine(sym, 0.5 * (a.c + b.c), np.ascontiguousarray(g[i]))
            for i, (a, b) in enumerate(pairs)]


def join_common(a: Affine, b: Affine) -> Affine:
    """A form holding a and b at every point of the symbols (each loop takes one of them), for
    one quantity joined alone. Per symbol a common generator m: their mean where both have
    one, 0 where only one does; then a(eps) - (c + m eps) lies within R_a = |c_a - c| +
    sum |g_a - m| (b likewise), and the join is c + m eps + max(R_a, R_b) eps_new, c the
    centres' mean. So joining the same form with a different last symbol (a value from
    another period) gives that form again with one new symbol, where `join`'s hull would add
    one per differing symbol."""
    width = max(a.g.shape[1], b.g.shape[1])
    ga, gb = a._padded(width), b._padded(width)
    common = np.where((ga != 0) & (gb != 0), 0.5 * (ga + gb), 0.0)
    c = 0.5 * (a.c + b.c)
    reach = np.maximum(np.abs(a.c - c) + np.abs(ga - common).sum(axis=1),
                       np.abs(b.c - c) + np.abs(gb - common).sum(axis=1))
    return Affine(a.sym, c, common).with_error(reach)


def monotone(f: Callable[[np.ndarray], np.ndarray], increasing: bool = True) -> BoxFunction:
    """The interval extension of a monotone (possibly discontinuous) function: its ends."""
    def box(lo, hi):
        a, b = f(lo), f(hi)
        return (a, b) if increasing else (b, a)
    return box


def reduce(sym: Symbols, forms: list[Affine], keep: int, groups=None) -> list[Affine]:
    """The same forms over at most keep + len(forms) symbols (Girard's box reduction): per box,
    the symbols with the smallest generators (summed over the forms) are merged into one new
    symbol per form, with radius the sum of what it loses. The boxes are separate runs, so each
    keeps its own symbols (a narrow box beside a wide one would otherwise keep the wide one's
    choice) and renumbers them its own way; rows of the same `groups` id (B,) keep the same
    symbols (copies of one box that are joined, as the loop's step taken once joins them: any
    choice is sound, the same one keeps them close). Every form that lives on must be
    passed."""
    width = sym.count
    if width <= keep + len(forms):
        return forms
    g = np.stack([f._padded(width) for f in forms], axis=1)          # (B, F, K)
    score = np.abs(g).sum(axis=1)                                      # (B, K)
    if groups is not None:
        summed = np.zeros((groups.max() + 1, width))
        np.add.at(summed, groups, score)
        score = summed[groups]
    order = np.argsort(score, axis=1)                                  # (B, K) per box
    merged, kept = order[:, :width - keep], np.sort(order[:, width - keep:], axis=1)
    lost = np.take_along_axis(np.abs(g), merged[:, None, :], axis=2).sum(axis=2)   # (B, F)
    new = np.zeros(g.shape[:2] + (len(forms),))
    idx = np.arange(len(forms))
    new[:, idx, idx] = lost * (1 + SLACK)
    g = np.concatenate([np.take_along_axis(g, kept[:, None, :], axis=2), new], axis=2)
    sym.count = g.shape[2]
    return [Affine(sym, f.c, np.ascontiguousarray(g[:, i])) for i, f in enumerate(forms)]
