"""Exact centroid in closed form, without sorting break points per sample.

Two cases where the aggregated membership M(u) is a fixed combination of fixed shapes, each cut
or scaled by one level that depends on the sample:
- MAX aggregation of MIN-clipped terms, when at most two terms are positive at any u:
  max_j g_j = sum_j g_j - sum_{j<k overlapping} min(g_j, g_k) (inclusion-exclusion; at a point
  where only one term is positive the pair terms vanish), with g_j = min(alpha_j, mu_j) and
  min(g_j, g_k) = min(min(alpha_j, alpha_k), min(mu_j, mu_k)).  min(mu_j, mu_k) is a fixed
  polyline, so every piece is "a fixed polyline clipped at a level h".
- SUM aggregation of PRODUCT-scaled terms: M = sum_j alpha_j mu_j, linear in alpha.
Integral and first moment of a polyline clipped at h: on each segment, min(h, line) is linear on
both sides of the point where the line crosses h, so two trapezoids are exact.
Everything else (and singleton or smooth output terms) keeps the general path in `defuzz`.
"""
from __future__ import annotations

from itertools import combinations

import numpy as np

from .expressions import clip
from .membership import LocalPartition, trapezoid
from .norms import row_sum
from .workspace import Workspace
from ..semantics.model import Aggregation, Implication, Inference, TermKind, Variable


def _polyline(var: Variable, terms: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (u, min over `terms` of mu) of that function on [lo, hi]: the terms' break
    points and the crossings of their edges (where the minimum switches term)."""
    lo, hi = float(var.lo), float(var.hi)
    p = np.asarray(var.params, dtype=float)[list(terms)]
    knots = [lo, hi] + [v for v in p.ravel() if lo < v < hi]
    edges = [(a, b) for a, b, _, _ in p if np.isfinite(a)] + \
        [(d, c) for _, _, c, d in p if np.isfinite(d)]   # lines through (foot, 0), (top, 1)
    for (a1, b1), (a2, b2) in combinations(edges, 2):
        s1, s2 = 1.0 / (b1 - a1), 1.0 / (b2 - a2)
        if s1 != s2:                           # s1 (u - a1) = s2 (u - a2)
            knots.append((s1 * a1 - s2 * a2) / (s1 - s2))
    u = np.unique(np.clip([k for k in knots if np.isfinite(k)], lo, hi))
    y = trapezoid(u[:, None], p[:, 0], p[:, 1], p[:, 2], p[:, 3]).min(axis=1)
    return u, y


class Segments:
    """Pieces (x0, y0)-(x1, y1) of polylines, each with a sign; the signed area and first
    moment of min(h, piece) for a level h per piece and sample, in closed form.

    With ylo, yhi the piece's lower and upper end, b = min(h, ylo) and g = clip(h - ylo, 0,
    yhi - ylo): min(h, y) = b + min(g, y - ylo), and the part above ylo is a triangle cut at g,
    whose run is w = g dx / (yhi - ylo).  Integrating (u du, u^2 du):
      area   = b dx + g (dx - w / 2)
      moment = b C + g (C - w (e + s w / 6)),  C = (x1^2 - x0^2) / 2,
    e = x0 / 2, s = +1 for a rising piece, e = x1 / 2, s = -1 for a falling one.  Both are
    polynomials in g whose coefficients add up over pieces with the same (level, ylo, yhi), so
    such pieces (the two edges of a triangle, say) are evaluated as one.
    """

    def __init__(self, pieces: np.ndarray):
        """pieces (S, 6): level index, sign, x0, x1, y0, y1."""
        level, sign, x0, x1, y0, y1 = pieces.T
        ylo, rise = np.minimum(y0, y1), np.abs(y1 - y0)
        dx = x1 - x0
        run = np.divide(dx, rise, out=np.zeros_like(dx), where=rise > 0)
        e = 0.5 * np.where(y1 >= y0, x0, x1)
        q = np.where(y1 >= y0, 1.0, -1.0) / 6.0
        # signed coefficients: area = b DX + g (DX - g H), moment = b C + g (C - g (E + g Q))
        coeffs = sign[:, None] * np.stack([dx, 0.5 * run, 0.5 * (x1 * x1 - x0 * x0),
                                           run * e, q * run * run], axis=1)
        keys, group = np.unique(np.stack([level, ylo, rise], axis=1), axis=0,
                                return_inverse=True)
        summed = np.zeros((len(keys), 5))
        np.add.at(summed, group.ravel(), coeffs)
        self.level = keys[:, 0].astype(np.intp)
        self.ylo, self.rise = keys[:, 1, None], keys[:, 2, None]
        self.dx, self.h, self.c, self.e, self.q = (summed[:, k, None] for k in range(5))

    def __len__(self) -> int:
        return len(self.level)

    def integrals(self, levels: np.ndarray, work: Workspace | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
        """levels (L, N) -> (area (N,), moment (N,)): sums over the pieces, fixed order; with
        a workspace, in its buffers (the same operations in the same order, so the same bits)."""
        n = levels.shape[1]
        work = work if work is not None else Workspace(n)
        shape = (len(self.level), n)                                     # (G, N)
        h = np.take(levels, self.level, axis=0, mode="clip", out=work.array("cf_h", shape))
        b = np.minimum(h, self.ylo, out=work.array("cf_b", shape))
        g = clip(np.subtract(h, self.ylo, out=h), 0.0, self.rise, out=h)
        # area = b * dx + g * (dx - g * h)
        area, t = work.array("cf_area", shape), work.array("cf_t", shape)
        np.multiply(g, self.h, out=t)
        np.multiply(g, np.subtract(self.dx, t, out=t), out=t)
        np.add(np.multiply(b, self.dx, out=area), t, out=area)
        # moment = b * c + g * (c - g * (e + g * q)), in b's buffer once b is read
        np.multiply(g, self.q, out=t)
        np.multiply(g, np.add(self.e, t, out=t), out=t)
        np.multiply(g, np.subtract(self.c, t, out=t), out=t)
        moment = np.add(np.multiply(b, self.c, out=b), t, out=b)
        return (row_sum(area, work.array("cf_area_sum", (n,))),
                row_sum(moment, work.array("cf_moment_sum", (n,))))



class ClosedFormCentroid:
    """The exact centroid of one output from its term strengths alpha (N, T)."""

    def __init__(self, var: Variable, clip_pairs: list[tuple[int, int]] | None):
        self.default = float(var.default)
        self.clip = clip_pairs is not None
        shapes = [(j,) for j in range(var.n_terms)] + (clip_pairs or [])
        self.pairs = np.array(clip_pairs or [], dtype=np.intp).reshape(-1, 2)
        segments = []          # (shape, sign, x0, x1, y0, y1) of every piece with some area
        for s, terms in enumerate(shapes):
            u, y = _polyline(var, terms)
            sign = 1.0 if len(terms) == 1 else -1.0
            segments += [(s, sign, u[k], u[k + 1], y[k], y[k + 1]) for k in range(len(u) - 1)
                         if u[k + 1] > u[k] and max(y[k], y[k + 1]) > 0.0]
        self.segments = Segments(np.array(segments, dtype=float).reshape(-1, 6))
        if not self.clip:      # area and moment of each whole term, scaled by alpha later
            # "sample" t: term t at an infinite level (not clipped), the others at 0
            levels = np.where(np.eye(var.n_terms) > 0, np.inf, 0.0)
            self.term_area, self.term_moment = self.segments.integrals(levels)

    @classmethod
    def build(cls, var: Variable, inference: Inference) -> "ClosedFormCentroid | None":
        """The closed form for this output, or None where it does not apply."""
        a, b, c, d = np.asarray(var.params, dtype=float).T
        vertical = np.any(np.isfinite(a) & (a >= b)) or np.any(np.isfinite(d) & (c >= d))
        if var.n_terms == 0 or np.any(var.kinds != TermKind.TRAPEZOID) or vertical:
            return None
        if inference.aggregation == Aggregation.SUM and \
                inference.implication == Implication.PRODUCT:
            return cls(var, None)
        if inference.aggregation == Aggregation.MAX and \
                inference.implication == Implication.MIN and LocalPartition.build(var) is not None:
            pairs = [(j, k) for j, k in combinations(range(var.n_terms), 2)
                     if np.any(_polyline(var, (j, k))[1] > 0.0)]
            return cls(var, pairs)
        return None

    def work_per_sample(self) -> int:
        return 16 * len(self.segments)

    def __call__(self, alpha: np.ndarray, work: Workspace | None = None,
                 out: np.ndarray | None = None) -> np.ndarray:
        """alpha (N, T) -> the centroid (N,), the default where M has no area; with a
        workspace the temporaries are its buffers (see Segments.integrals), with out (N,) the
        result is written there."""
        if not self.clip:
            area = (alpha * self.term_area).sum(axis=1)
            moment = (alpha * self.term_moment).sum(axis=1)
        else:
            n = alpha.shape[0]
            work = work if work is not None else Workspace(n)
            levels = alpha.T                                             # (T, N)
            if len(self.pairs):     # the terms' levels, then min of each overlapping pair's
                rows = work.array("cf_levels", (len(levels) + len(self.pairs), n))
                rows[:len(levels)] = levels
                for p, (j, k) in enumerate(self.pairs):
                    np.minimum(levels[j], levels[k], out=rows[len(levels) + p])
                levels = rows
            area, moment = self.segments.integrals(levels, work)
        n = len(area)
        work = work if work is not None else Workspace(n)
        # where(area > 0, moment / where(area > 0, area, 1), default), without temporaries
        ok = np.greater(area, 0.0, out=work.array("cf_ok", (n,), bool))
        den = work.array("cf_den", (n,))
        den.fill(1.0)
        np.copyto(den, area, where=ok)
        out = np.divide(moment, den, out=out)
        np.copyto(out, self.default, where=np.logical_not(ok, out=ok))
        return out
