"""Bisector and mean of maximum, and every area-based defuzzifier over smooth output terms, in C.

The engine (fuzzyc/engine/defuzz.py) defines these on a list of points (u_i, M(u_i)) with M linear
between consecutive points.  The C walks the same kind of list through a point function
`at(ctx, i, &u, &f)`, so one copy of each algorithm serves both sources of points:
- piecewise-linear output terms: the exact polygon of M that c_centroid builds per segment,
  stored as (u, f) pairs in a fixed-size array on the stack (its size known at generation);
- gaussian, bell or sigmoid output terms: the engine's grid of GRID_POINTS over [lo, hi]; the
  terms' memberships at the grid points are a constant table (computed by the engine's own
  `term_values`, so both sides start from the same numbers), M is formed while streaming over
  it, no array of M is kept.
Centroid over piecewise-linear terms stays the straight-line exact form of c_centroid.
The algorithms follow defuzz.py step by step: the bisector is the leftmost u where the running
area reaches half, solved inside its piece with the same stable quadratic form; the mean of
maximum averages the maximal plateaus, or the distinct maximal points where there is none.
"""
from __future__ import annotations

import numpy as np

from ...engine.defuzz import FLAT_TOLERANCE, GRID_POINTS
from ...escape import c_comment
from ...engine.membership import term_values
from ...semantics.model import Aggregation, Defuzzifier, Implication, Inference, TermKind, Variable
from .centroid import CentroidEmitter, area_segments

FLOAT_FLAT_TOLERANCE = 4 * 2.0 ** -23
"""assumption: the float C evaluates M with a few roundings (a line, a product or min, a sum
over terms), so two points equal in exact arithmetic can differ by a few float ulps; 4 ulps
of the top count as the maximum, M >= top (1 - 4 2^-23) (the engine's relative 1e-12 is
below float resolution).  The double C uses the engine's FLAT_TOLERANCE."""

FUNCTION_OF = {Defuzzifier.CENTROID: "centroid_of", Defuzzifier.BISECTOR: "bisector_of",
               Defuzzifier.MEAN_OF_MAXIMUM: "mom_of"}


def is_sampled(var: Variable) -> bool:
    """Whether the engine samples this output's M on the grid (a smooth term is present)."""
    return bool(np.any((var.kinds != TermKind.TRAPEZOID) & (var.kinds != TermKind.SINGLETON)))


class AreaWriter:
    """C text of the walk over M's points for one header (real type, name prefix)."""

    def __init__(self, real, prefix: str, inference: Inference):
        self.real, self.p, self.inf = real, prefix, inference
        self.t = real.name
        self.grids: dict[bytes, int] = {}   # outputs with the same terms share one table

    @staticmethod
    def _grid_key(var: Variable) -> bytes:
        return np.asarray(var.kinds).tobytes() + np.asarray(var.params, dtype=float).tobytes() \
            + np.array([var.lo, var.hi], dtype=float).tobytes()

    def tolerance(self) -> float:
        return FLOAT_FLAT_TOLERANCE if self.t == "float" else FLAT_TOLERANCE

    # -- the algorithms, once per header --------------------------------------------------

    def helpers(self, polygon: bool) -> list[str]:
        """The walk's functions this header needs: its one defuzzifier, and the polygon's
        point function where a piecewise-linear output is walked."""
        method = self.inf.defuzzifier
        code = self._points() + (self._polygon() if polygon else [])
        if method != Defuzzifier.MEAN_OF_MAXIMUM:
            code += self._sums()
        return code + {Defuzzifier.CENTROID: self._centroid, Defuzzifier.BISECTOR: self._bisector,
                       Defuzzifier.MEAN_OF_MAXIMUM: self._mom}[method]()

    def _points(self) -> list[str]:
        """The type of a point function."""
        t, p = self.t, self.p
        return [
            "/* The points of M, (u, f) with M linear between them: the i-th of a stored "
            "polygon or of the grid. */",
            f"typedef void (*{p}points)(const {t} *c, int i, {t} *u, {t} *f);",
        ]

    def _polygon(self) -> list[str]:
        """Reading and storing a polygon of (u, f) pairs."""
        t, p = self.t, self.p
        return [
            f"static inline void {p}polygon_point(const {t} *c, int i, {t} *u, {t} *f) "
            f"{{ *u = c[2 * i]; *f = c[2 * i + 1]; }}",
            f"static inline void {p}store({t} *poly, const {t} *u, const {t} *f, int n) {{",
            "    int i;",
            "    for (i = 0; i < n; ++i) { poly[2 * i] = u[i]; poly[2 * i + 1] = f[i]; }",
            "}",
        ]

    def _sums(self) -> list[str]:
        """Compensated area and moment of the first points."""
        t, p, lit = self.t, self.p, self.real.lit
        return [
            "/* Compensated (Kahan) sums: 2000 grid pieces summed in float would lose "
            "~1e-5 of the range. */",
            f"static inline void {p}add_piece({t} u0, {t} u1, {t} f0, {t} f1, {t} sum[4]) {{",
            f"    {t} piece[2] = {{{lit(0)}, {lit(0)}}};",
            "    int k;",
            f"    {p}piece(u0, u1, f0, f1, &piece[0], &piece[1]);",
            "    for (k = 0; k < 2; ++k) {   /* sum[k] with its compensation sum[k + 2] */",
            f"        {t} y = piece[k] - sum[k + 2], s = sum[k] + y;",
            "        sum[k + 2] = (s - sum[k]) - y;",
            "        sum[k] = s;",
            "    }",
            "}",
            "/* Area and moment of the first n points into sum[0], sum[1]; stops early (returns "
            "the piece's index) once the area would reach `stop`. */",
            f"static inline int {p}integrate({p}points at, const {t} *c, int n, {t} stop, "
            f"{t} sum[4]) {{",
            f"    {t} u0, f0, u1, f1;",
            "    int i;",
            "    at(c, 0, &u0, &f0);",
            "    for (i = 1; i < n; ++i) {",
            "        at(c, i, &u1, &f1);",
            f"        if ({lit(0.5)} * (f0 + f1) * (u1 - u0) + sum[0] >= stop) return i;",
            f"        {p}add_piece(u0, u1, f0, f1, sum);",
            "        u0 = u1; f0 = f1;",
            "    }",
            "    return n;",
            "}",
        ]

    def _centroid(self) -> list[str]:
        """Centroid: moment over area."""
        t, p, lit = self.t, self.p, self.real.lit
        return [
            f"static inline {t} {p}centroid_of({p}points at, const {t} *c, int n, "
            f"{t} fallback) {{",
            f"    {t} sum[4] = {{{lit(0)}, {lit(0)}, {lit(0)}, {lit(0)}}};",
            f"    {p}integrate(at, c, n, INFINITY, sum);",
            "    return sum[0] > 0 ? sum[1] / sum[0] : fallback;",
            "}",
        ]

    def _bisector(self) -> list[str]:
        """Bisector, solved inside its piece."""
        t, p, lit = self.t, self.p, self.real.lit
        return [
            "/* Bisector: the leftmost u where the running area reaches half the area, solved "
            "in its piece: g0 t + slope t^2 / 2 = rem, in a form stable for slope 0. */",
            f"static inline {t} {p}bisect_piece({t} u0, {t} d, {t} g0, {t} g1, {t} rem) {{",
            f"    {t} slope = d > 0 ? (g1 - g0) / d : {lit(0)};",
            f"    {t} den = g0 + {self.real.fn('sqrt')}({p}greater(g0 * g0 + {lit(2)} * slope "
            f"* rem, {lit(0)}));",
            f"    {t} t = den > 0 ? {lit(2)} * rem / den : {lit(0)};",
            f"    return u0 + {p}clamp(t, {lit(0)}, d);",
            "}",
            f"static inline {t} {p}bisector_of({p}points at, const {t} *c, int n, "
            f"{t} fallback) {{",
            f"    {t} sum[4] = {{{lit(0)}, {lit(0)}, {lit(0)}, {lit(0)}}}, half, u0, f0, u1, f1;",
            "    int i;",
            f"    {p}integrate(at, c, n, INFINITY, sum);",
            f"    half = {lit(0.5)} * sum[0];",
            "    if (!(half > 0)) return fallback;",
            f"    sum[0] = sum[1] = sum[2] = sum[3] = {lit(0)};",
            f"    i = {p}integrate(at, c, n, half, sum);",
            "    if (i >= n) { at(c, n - 1, &u0, &f0); return u0; }   /* rounding: the end */",
            "    at(c, i - 1, &u0, &f0);",
            "    at(c, i, &u1, &f1);",
            f"    return {p}bisect_piece(u0, u1 - u0, f0, f1, half - sum[0]);",
            "}",
        ]

    def _mom(self) -> list[str]:
        """Mean of maximum with this real type's tolerance."""
        t, p, lit = self.t, self.p, self.real.lit
        return [
            "/* Mean of maximum: the mean of the maximal plateaus, else of the distinct maximal "
            f"points; maximal = at least top x (1 - {self.tolerance():.3g}). */",
            f"static inline {t} {p}mom_of({p}points at, const {t} *c, int n, {t} fallback) {{",
            f"    {t} top = {lit(0)}, floor_, total = {lit(0)}, sum = {lit(0)}, "
            f"points = {lit(0)}, count = {lit(0)}, u0, u1, f1;",
            "    int i, top0, top1;",
            "    for (i = 0; i < n; ++i) {",
            "        at(c, i, &u1, &f1);",
            f"        top = {p}greater(top, f1);",
            "    }",
            "    if (!(top > 0)) return fallback;",
            f"    floor_ = top * {lit(1.0 - self.tolerance())};",
            "    at(c, 0, &u0, &f1);",
            "    top0 = f1 >= floor_;",
            f"    if (top0) {{ points = u0; count = {lit(1)}; }}",
            "    for (i = 1; i < n; ++i) {",
            "        at(c, i, &u1, &f1);",
            "        top1 = f1 >= floor_;",
            f"        if (top0 && top1) {{ total += u1 - u0; "
            f"sum += (u1 - u0) * {lit(0.5)} * (u0 + u1); }}",
            "        /* a repeated u counts once; a jump up to the top at a repeated u is new */",
            f"        if (top1 && (u1 > u0 || !top0)) {{ points += u1; count += {lit(1)}; }}",
            "        u0 = u1; top0 = top1;",
            "    }",
            "    return total > 0 ? sum / total : points / count;",
            "}",
        ]

    # -- per output -------------------------------------------------------------------------

    def grid_getter(self, o: int, var: Variable, n_items: int = 0) -> list[str]:
        """The constant table of the terms at the grid points and the point function forming
        M at grid point i from the levels (ctx = alpha), or with n_items from the items of
        c_items (ctx = n_items levels, then their term ids); nothing where an earlier output
        has the same terms."""
        if self._grid_key(var) in self.grids:
            return []
        self.grids[self._grid_key(var)] = o
        t, p = self.t, self.p
        lo, hi = float(var.lo), float(var.hi)
        grid = np.linspace(lo, hi, GRID_POINTS)
        mu = term_values(var.kinds, var.params, grid)                    # (P, T), the engine's
        table = f"{self.p.upper()}GRID_{o}"
        rows = ",\n".join("{" + ", ".join(self._grid_lit(v) for v in row) + "}" for row in mu)
        body = self._item_sum(n_items) if n_items else [f"    *f = {self._strengths_m(var)};"]
        return [f"/* `{c_comment(var.name)}`: its terms at the {GRID_POINTS} grid points over "
                f"[{lo:g}, {hi:g}] (the engine's sampling of smooth terms). */",
                f"static const {t} {table}[{GRID_POINTS}][{var.n_terms}] = {{\n{rows}}};",
                "/* u is the grid index (exact in float); the caller maps it to lo + i * step: "
                "all three defuzzifiers commute with that map. */",
                f"static inline void {p}grid_{o}(const {t} *alpha, int i, {t} *u, {t} *f) {{",
                f"    const {t} *mu = {table}[i];",
                f"    *u = ({t})i;",
                *body,
                "}"]

    def _strengths_m(self, var: Variable) -> str:
        """M at the grid point from the terms' levels alpha[j] and memberships mu[j]."""
        terms = [self._implied(f"alpha[{j}]", f"mu[{j}]") for j in range(var.n_terms)]
        value = terms[0]
        for term in terms[1:]:
            value = f"{self.p}greater({value}, {term})" \
                if self.inf.aggregation == Aggregation.MAX else f"{value} + {term}"
        return value

    def _item_sum(self, n_items: int) -> list[str]:
        """M at the grid point as the sum over the items of min(level, its term's mu)."""
        return [f"    {self.t} m = {self.real.lit(0)};",
                "    int k;",
                f"    for (k = 0; k < {n_items}; ++k) "
                f"m += {self.p}lesser(alpha[k], mu[(int)alpha[{n_items} + k]]);",
                "    *f = m;"]

    def _grid_lit(self, value: float) -> str:
        """A table entry, rounded to the real type first (shortest text, no underflowing
        literal for a gaussian's far tail)."""
        if self.t == "float":
            return np.format_float_positional(np.float32(value), unique=True, trim="0") + "f"
        return repr(float(value))

    def _implied(self, level: str, mu: str) -> str:
        if self.inf.implication == Implication.MIN:
            return f"{self.p}lesser({level}, {mu})"
        return f"{level} * {mu}"

    def defuzzify(self, o: int, var: Variable, alpha: str) -> list[str]:
        """Statements setting y[o] from the levels `alpha` (centroid of piecewise-linear terms
        is c_centroid's, not this)."""
        method = FUNCTION_OF[self.inf.defuzzifier]
        fallback = self.real.lit(var.default)
        if is_sampled(var):      # in grid indices, -1 = no area; back to u as np.linspace
            lit, step = self.real.lit, (float(var.hi) - float(var.lo)) / (GRID_POINTS - 1)
            grid = self.grids[self._grid_key(var)]
            return [f"{{ {self.t} index = {self.p}{method}({self.p}grid_{grid}, {alpha}, "
                    f"{GRID_POINTS}, {lit(-1)});",
                    f"  y[{o}] = index >= 0 ? index * {lit(step)} + {lit(var.lo)} : {fallback}; }}"]
        emitter = CentroidEmitter(self.real, self.p, self.inf)
        segments = area_segments(var)
        n = emitter.polygon_size(segments)
        if n == 0:                    # no trapezoid reaches into [lo, hi]: M has no area
            return [f"y[{o}] = {fallback};"]
        code = [f"{{ {self.t} poly[{2 * n}];   /* the polygon of M: {n} (u, f) pairs */"]
        code += ["  " + s for s in emitter.emit_polygon(segments, alpha, "poly")]
        return code + [f"  y[{o}] = {self.p}{method}({self.p}polygon_point, poly, {n}, "
                       f"{fallback}); }}"]
