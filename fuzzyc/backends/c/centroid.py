"""Exact centroid of piecewise-linear output terms, as straight-line C.

At generation time [lo, hi] is cut at every term break point, so inside a segment each term
that is positive there is one line s*u + q.  The aggregated membership
M(u) = AGG_j IMP(alpha_j, s_j u + q_j) then only bends where a line meets a level or two lines
cross (MIN implication: s_j u + q_j = alpha_k, and the fixed crossings of two lines) or, for
PRODUCT implication with MAX, where two scaled lines cross.  Those few candidate points are computed from the levels at run time, clamped into
the segment and sorted by a fixed compare-exchange network; M is linear between consecutive
points, so the trapezoid sums of area and first moment are exact (the engine's closed form).
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from ...engine.defuzz import AT_LEVEL_STEPS
from ...semantics.model import Aggregation, Implication, Inference, TermKind, Variable


@dataclass
class Line:
    term: int
    slope: float
    intercept: float


@dataclass
class Segment:
    x0: float
    x1: float
    lines: list[Line]
    crossings: list[float]     # where two of the lines cross inside the segment


def _piece(a: float, b: float, c: float, d: float, mid: float) -> tuple[float, float] | None:
    """The line of a trapezoid at `mid` (not a break point), or None where it is 0."""
    if mid <= a or mid >= d:
        return None
    if np.isfinite(a) and mid < b:
        return 1.0 / (b - a), -a / (b - a)
    if np.isfinite(d) and mid > c:
        return -1.0 / (d - c), d / (d - c)
    return 0.0, 1.0


def _lines(params: np.ndarray, terms: list[int], x0: float, x1: float) -> list[Line]:
    mid = 0.5 * (x0 + x1)
    out = []
    for t in terms:
        piece = _piece(*params[t], mid)
        if piece is not None:
            out.append(Line(t, *piece))
    return out


def area_segments(var: Variable) -> list[Segment]:
    """The segments of [lo, hi] between term break points, with the lines of the trapezoid
    terms positive in each and the points inside where two of those lines cross."""
    lo, hi = float(var.lo), float(var.hi)
    params = np.asarray(var.params, dtype=float)
    terms = [t for t in range(var.n_terms) if var.kinds[t] == TermKind.TRAPEZOID]
    bounds = sorted({lo, hi} | {float(v) for t in terms for v in params[t] if lo < v < hi})
    segments = []
    for x0, x1 in zip(bounds[:-1], bounds[1:]):
        lines = _lines(params, terms, x0, x1)
        crossings = sorted({(l2.intercept - l1.intercept) / (l1.slope - l2.slope)
                            for l1, l2 in combinations(lines, 2) if l1.slope != l2.slope})
        if lines:
            segments.append(Segment(x0, x1, lines, [u for u in crossings if x0 < u < x1]))
    return segments


STRENGTH_PAIRS = {(Aggregation.MAX, Implication.MIN), (Aggregation.MAX, Implication.PRODUCT),
                  (Aggregation.SUM, Implication.PRODUCT)}


def supported(inference: Inference) -> bool:
    """Whether the levels alpha_j (one per term) determine M and this module emits it: MAX
    aggregation or PRODUCT implication, named pair by pair so an aggregation added to the
    model is not emitted as one of these by accident.  SUM of MIN-clipped rules needs every
    rule as its own item (c_items)."""
    return (inference.aggregation, inference.implication) in STRENGTH_PAIRS


class CentroidEmitter:
    """C statements accumulating area and moment of one output's M, levels in `alpha`."""

    def __init__(self, real, prefix: str, inference: Inference):
        self.real, self.p, self.inf = real, prefix, inference

    def _line(self, line: Line, u: str) -> str:
        lit = self.real.lit
        return lit(line.intercept) if line.slope == 0.0 else \
            f"({lit(line.slope)} * {u} + {lit(line.intercept)})"

    def _value(self, line: Line, u: str, alpha: str) -> str:
        mu = self._line(line, u)
        level = f"{alpha}[{line.term}]"
        if self.inf.implication == Implication.MIN:
            return f"{self.p}lesser({level}, {mu})"
        return f"({level} * {mu})"

    def _membership(self, seg: Segment, u: str, alpha: str) -> str:
        values = [self._value(line, u, alpha) for line in seg.lines]
        out = values[0]
        for v in values[1:]:
            out = f"{self.p}greater({out}, {v})" if self.inf.aggregation == Aggregation.MAX \
                else f"({out} + {v})"
        return out

    def _meets(self, seg: Segment) -> list[tuple[Line, Line]]:
        """(line j, line k) where line j meets k's level (MIN implication: M bends there)."""
        if self.inf.aggregation == Aggregation.SUM or self.inf.implication != Implication.MIN:
            return []
        return [(j, k) for j in seg.lines if j.slope != 0.0 for k in seg.lines]

    def _candidates(self, seg: Segment, alpha: str) -> list[str]:
        lit = self.real.lit
        if self.inf.aggregation == Aggregation.SUM:      # PRODUCT and SUM: linear in segment
            return []
        if self.inf.implication == Implication.MIN:   # line meets a level, or two lines cross
            return [f"({alpha}[{k.term}] - {lit(j.intercept)}) * {lit(1.0 / j.slope)}"
                    for j, k in self._meets(seg)] + [lit(u) for u in seg.crossings]
        out = []
        for j, k in combinations(seg.lines, 2):
            if j.slope == 0.0 and k.slope == 0.0:
                continue
            aj, ak = f"{alpha}[{j.term}]", f"{alpha}[{k.term}]"
            num = f"({ak} * {lit(k.intercept)} - {aj} * {lit(j.intercept)})"
            den = f"({aj} * {lit(j.slope)} - {ak} * {lit(k.slope)})"
            out.append(f"{self.p}ratio_or({num}, {den}, {lit(seg.x0)})")
        return out

    def _nudged(self, u: str, value: str, j: Line, k: Line, alpha: str) -> list[str]:
        """u = where line j meets k's level, moved by an ulp or two toward j's top until j
        reaches the level there (as the engine's defuzz._at_level): rounded, the point can fall
        where j is already below the level, and M there below it ramps the plateau down (a
        level of 1e-6 at 9 - 3e-6 in float rounds to 9, the foot, where j is 0)."""
        toward = "INFINITY" if j.slope > 0 else "(-INFINITY)"
        step = f"if ({self._line(j, u)} < {alpha}[{k.term}]) " \
               f"{u} = {self.real.fn('nextafter')}({u}, {toward});"
        return [f"{u} = {value};"] + [step] * AT_LEVEL_STEPS

    def n_points(self, seg: Segment) -> int:
        """How many points segment_points writes for `seg` (the candidates and both ends)."""
        return len(self._candidates(seg, "alpha")) + 2

    def segment_points(self, seg: Segment, alpha: str) -> list[str]:
        """Declarations and statements filling u[n], f[n] (n = n_points) with the points of
        `seg` where M may bend, sorted, and M at them; M is linear between them."""
        lit = self.real.lit
        cands = self._candidates(seg, alpha)
        n = len(cands) + 2
        code = [f"{self.real.name} u[{n}], f[{n}];",
                f"u[0] = {lit(seg.x0)}; u[{n - 1}] = {lit(seg.x1)};"]
        meets = self._meets(seg)
        for i, c in enumerate(cands, start=1):
            if i <= len(meets):
                code += self._nudged(f"u[{i}]", c, *meets[i - 1], alpha)
                c = f"u[{i}]"
            code.append(f"u[{i}] = {self.p}clamp({c}, {lit(seg.x0)}, {lit(seg.x1)});")
        for i in range(len(cands)):              # bubble network: fixed, data-independent
            for j in range(1, len(cands) - i):
                code.append(f"{self.p}order(&u[{j}], &u[{j + 1}]);")
        for i in range(n):
            code.append(f"f[{i}] = {self._membership(seg, f'u[{i}]', alpha)};")
        return code

    def emit(self, segments: list[Segment], alpha: str) -> list[str]:
        """Statements adding each segment's area and moment to `area` and `moment`."""
        code = []
        for seg in segments:
            # M is 0 on a segment where no term is concluded: skip its arithmetic.
            fired = " || ".join(f"{alpha}[{line.term}] > 0" for line in seg.lines)
            code.append(f"if ({fired}) {{ /* [{seg.x0:.9g}, {seg.x1:.9g}] */")
            code += ["    " + s for s in self.segment_points(seg, alpha)]
            code += [f"    {self.p}piece(u[{i}], u[{i + 1}], f[{i}], f[{i + 1}], "
                     f"&area, &moment);" for i in range(self.n_points(seg) - 1)]
            code.append("}")
        return code

    @staticmethod
    def _gap(before: Segment | None, seg: Segment) -> bool:
        """Whether no term is positive between `before` and `seg` (segments without lines
        are left out): M is 0 there, which the polygon must say with points of its own."""
        return before is not None and before.x1 < seg.x0

    def polygon_size(self, segments: list[Segment]) -> int:
        """The (u, f) pairs emit_polygon stores."""
        return sum(self.n_points(seg) + 2 * self._gap(before, seg)
                   for before, seg in zip([None] + segments[:-1], segments))

    def emit_polygon(self, segments: list[Segment], alpha: str, poly: str) -> list[str]:
        """Statements storing the whole polygon of M, segment after segment, as (u, f) pairs
        in `poly` (polygon_size pairs); a segment where nothing fired stores f = 0, and so do
        the two points at the ends of a gap between segments (M is linear between
        consecutive points: without them a term with a vertical edge after a gap would ramp
        up over the whole gap)."""
        lit = self.real.lit
        code, offset = [], 0
        for before, seg in zip([None] + segments[:-1], segments):
            if self._gap(before, seg):
                code.append(f"{poly}[{2 * offset}] = {lit(before.x1)}; "
                            f"{poly}[{2 * offset + 1}] = {lit(0)}; "
                            f"{poly}[{2 * offset + 2}] = {lit(seg.x0)}; "
                            f"{poly}[{2 * offset + 3}] = {lit(0)};   /* M = 0 in the gap */")
                offset += 2
            code.append(f"{{ /* [{seg.x0:.9g}, {seg.x1:.9g}] */")
            code += ["    " + s for s in self.segment_points(seg, alpha)]
            code.append(f"    {self.p}store({poly} + {2 * offset}, u, f, "
                        f"{self.n_points(seg)});")
            code.append("}")
            offset += self.n_points(seg)
        return code
