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
from .helpers import helper_lines

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
        """The walk's functions this header needs (sections of real_helpers.c): its one
        defuzzifier, and the polygon's point function where a piecewise-linear output is
        walked; before them the constants they use, which belong to the real type."""
        method = self.inf.defuzzifier
        P = self.p.upper()
        names = ["points"] + (["polygon"] if polygon else [])
        if method != Defuzzifier.MEAN_OF_MAXIMUM:
            names.append("sums")
        names.append({Defuzzifier.CENTROID: "centroid", Defuzzifier.BISECTOR: "bisector",
                      Defuzzifier.MEAN_OF_MAXIMUM: "mom"}[method])
        defines = {Defuzzifier.BISECTOR: [f"#define {P}SQRT {self.real.fn('sqrt')}"],
                   Defuzzifier.MEAN_OF_MAXIMUM: [
                       f"#define {P}TOP_SHARE {self.real.lit(1.0 - self.tolerance())}"]}
        return defines.get(method, []) + helper_lines(names, self.p, P)

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
