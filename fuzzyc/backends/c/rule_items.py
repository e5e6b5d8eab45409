"""Area-based defuzzifiers of SUM-aggregated MIN-implied rules in C: every rule its own item.

With aggregation = sum and implication = min the engine's M(u) = sum_k min(level_k, mu_{t_k}(u))
over the candidate rules k (fuzzyc/engine/defuzz.py, `ids` of shape (N, C)): two rules concluding the
same term at different levels give two different clipped shapes whose sum is not one clipped
shape, so the terms' strengths alpha_j do not determine M and every rule is kept on its own.
The items are the engine's candidates: all rules on the dense path, the 2**I x depth cells'
rules on the sparse path (slot r * depth + d), level = the rule's (weighted) activation, term =
its consequent for the output (a rule saying nothing about it contributes 0).

- centroid, piecewise-linear terms: the integral of a sum is the sum of the integrals, so the
  exact centroid adds each item's clipped trapezoid over [lo, hi] in closed form (rise line,
  plateau at the level, fall line); no polygon of M at all;
- bisector and mean of maximum, piecewise-linear terms: the exact polygon of M, whose break
  points are the terms' break points (fixed, sorted at generation) and each item's two clip
  points (sorted at run time by a fixed loop, merged in place), walked by c_area's algorithms;
- gaussian, bell or sigmoid terms: c_area's grid walk, M at a grid point summed over the items.
No heap; every array size is fixed at generation.
"""
from __future__ import annotations

import numpy as np

from ...engine.defuzz import AT_LEVEL_STEPS
from ...semantics.model import Aggregation, Defuzzifier, Implication, Inference, TermKind, Variable
from .area import FUNCTION_OF, AreaWriter, is_sampled


def per_item(inference: Inference) -> bool:
    """Whether M needs every rule as its own item: SUM of MIN-clipped rules."""
    return (inference.aggregation, inference.implication) == (Aggregation.SUM, Implication.MIN)


def fixed_points(var: Variable, real_name: str) -> np.ndarray:
    """The break points of M that do not move with the levels, in the C real type: lo, hi and
    the trapezoid terms' break points inside; at a vertical edge (a == b or c == d) inside the
    range also the next representable value on each side, so the pieces next to it do not
    ramp over the jump (the engine's points, fuzzyc/engine/defuzz.py, at this type's resolution)."""
    dtype = np.float32 if real_name == "float" else np.float64
    lo, hi = dtype(var.lo), dtype(var.hi)
    params = np.asarray(var.params, dtype=float)[var.kinds == TermKind.TRAPEZOID].astype(dtype)
    points = [lo, hi] + [v for v in params.ravel() if lo < v < hi]
    vertical = [v for a, b, c, d in params for v, w in ((a, b), (c, d)) if v == w and lo < v < hi]
    points += [np.nextafter(v, dtype(side)) for v in vertical for side in (-np.inf, np.inf)]
    return np.unique(np.clip(np.array(points, dtype=dtype), lo, hi))


class ItemWriter:
    """C text for the outputs defuzzified item by item in one header.

    rule: the C expression of item k's rule index (`k` on the dense path, `ru[k]` on the
    sparse one, where `ru` records the rule of every candidate slot)."""

    def __init__(self, area: AreaWriter, P: str, n_items: int, rule_type: str | None):
        self.area, self.real, self.p, self.P = area, area.real, area.p, P
        self.t = area.t
        self.n_items = n_items
        self.rule_type = rule_type          # None: dense, item k is rule k
        self.rule = "k" if rule_type is None else "ru[k]"
        self.n_fixed: dict[int, int] = {}

    # -- the rule loop ----------------------------------------------------------------------

    def declarations(self) -> list[str]:
        """The items' levels (and rules on the sparse path), set by `store` in the rule loop."""
        t, lit, K = self.t, self.real.lit, self.n_items
        code = [f"{t} lv[{K}] = {{{lit(0)}}};   /* the level of every item (candidate rule) */"]
        if self.rule_type is not None:
            code.append(f"{self.rule_type} ru[{K}];   /* its rule (N_RULES: padding) */")
        return code

    def store(self, act: str, rule: str, slot: str) -> list[str]:
        code = [f"lv[{slot}] = {act};"]
        if self.rule_type is not None:
            code.append(f"ru[{slot}] = ({self.rule_type}){rule};")
        return code

    # -- once per header --------------------------------------------------------------------

    def helpers(self, centroid: bool, polygon: bool) -> list[str]:
        code = self._pack() + self._clip_points()
        if centroid:
            code += self._clipped()
        if polygon:
            code += self._polygon()
        return code

    def _signature_rules(self) -> str:
        return "" if self.rule_type is None else f"const {self.rule_type} *ru, "

    def _pack(self) -> list[str]:
        t, p, lit, K = self.t, self.p, self.real.lit, self.n_items
        return [
            "/* The items of output o as one context for the walk: levels c[0..K) (0 where the "
            "rule says nothing about o) and term ids c[K..2K) (exact small integers). */",
            f"static inline void {p}pack(const {t} *lv, {self._signature_rules()}int o, "
            f"int n_terms, {t} *c) {{",
            "    int k;",
            f"    for (k = 0; k < {K}; ++k) {{",
            f"        int j = {self.P}CONSEQUENTS[{self.rule}][o];",
            f"        c[k] = j < n_terms ? lv[k] : {lit(0)};",
            f"        c[{K} + k] = ({t})(j < n_terms ? j : 0);",
            "    }",
            "}",
        ]

    def _clip_points(self) -> list[str]:
        t, p, lit = self.t, self.p, self.real.lit
        nextafter = self.real.fn("nextafter")
        return [
            "/* Where min(level, trapezoid q) bends: its rise and its fall meet the level (b and "
            "c at level 1, the edge at a vertical edge), clamped into [lo, hi]. */",
            f"static inline void {p}clip_points({t} level, const {t} q[6], {t} lo, {t} hi, "
            f"{t} at[2]) {{",
            f"    {t} h = {p}lesser(level, {lit(1)});",
            "    at[0] = q[4] > 0 ? q[0] + h * (q[1] - q[0]) : q[1];",
            "    at[1] = q[5] > 0 ? q[3] - h * (q[3] - q[2]) : q[2];",
            "    /* rounded, a point can fall where the term is already below h (at its foot for "
            "a tiny h): an ulp or two toward the top (the engine's defuzz._at_level) */",
            *[f"    if ({p}trapezoid(at[0], q) < h) at[0] = {nextafter}(at[0], INFINITY);"
              for _ in range(AT_LEVEL_STEPS)],
            *[f"    if ({p}trapezoid(at[1], q) < h) at[1] = {nextafter}(at[1], -INFINITY);"
              for _ in range(AT_LEVEL_STEPS)],
            f"    at[0] = {p}clamp(at[0], lo, hi);",
            f"    at[1] = {p}clamp(at[1], lo, hi);",
            "}",
        ]

    def _clipped(self) -> list[str]:
        t, p, lit = self.t, self.p, self.real.lit
        return [
            "/* Exact area and moment over [lo, hi] of min(level, trapezoid q): on the rise "
            "the term's own line, then the plateau at the level, then the fall line. */",
            f"static inline void {p}clipped({t} level, const {t} q[6], {t} lo, {t} hi, "
            f"{t} *area, {t} *moment) {{",
            f"    {t} h = {p}lesser(level, {lit(1)}), at[2];",
            f"    {t} a = {p}clamp(q[0], lo, hi), d = {p}clamp(q[3], lo, hi);",
            "    if (!(h > 0)) return;",
            f"    {p}clip_points(level, q, lo, hi, at);",
            "    /* M = min(h, term): at a clip point moved toward the top the term exceeds h */",
            f"    if (q[4] > 0) {p}piece(a, at[0], {p}lesser(h, (a - q[0]) * q[4]), "
            f"{p}lesser(h, (at[0] - q[0]) * q[4]), area, moment);",
            f"    {p}piece(at[0], at[1], h, h, area, moment);",
            f"    if (q[5] > 0) {p}piece(at[1], d, {p}lesser(h, (q[3] - at[1]) * q[5]), "
            f"{p}lesser(h, (q[3] - d) * q[5]), area, moment);",
            "}",
        ]

    def _polygon(self) -> list[str]:
        t, p, lit = self.t, self.p, self.real.lit
        return [
            "/* The polygon of M = sum_k min(c[k], term c[K + k]) over [lo, hi] as (u, f) pairs "
            "in poly[2 * (n_fixed + 2K)]: the items' clip points, sorted by a fixed loop in "
            "poly[0..2K), merged from the back with the sorted fixed points (the write "
            "position 2m stays above every unread clip point), then M at every point. */",
            f"static inline void {p}items_polygon(const {t} *c, int n_items, "
            f"const {t} (*terms)[6], const {t} *fixed, int n_fixed, {t} lo, {t} hi, "
            f"{t} *poly) {{",
            "    int n_clip = 2 * n_items, n = n_fixed + n_clip, i, j, k;",
            "    for (k = 0; k < n_items; ++k)",
            f"        {p}clip_points(c[k], terms[(int)c[n_items + k]], lo, hi, poly + 2 * k);",
            "    for (i = 0; i + 1 < n_clip; ++i)",
            f"        for (j = 0; j + 1 < n_clip - i; ++j) {p}order(&poly[j], &poly[j + 1]);",
            "    i = n_fixed - 1;",
            "    j = n_clip - 1;",
            "    for (k = n - 1; k >= 0; --k)",
            "        poly[2 * k] = (j < 0 || (i >= 0 && fixed[i] > poly[j])) ? fixed[i--] "
            ": poly[j--];",
            "    for (k = 0; k < n; ++k) {",
            f"        {t} m = {lit(0)};",
            "        for (j = 0; j < n_items; ++j)",
            f"            m += {p}lesser(c[j], {p}trapezoid(poly[2 * k], "
            "terms[(int)c[n_items + j]]));",
            "        poly[2 * k + 1] = m;",
            "    }",
            "}",
        ]

    # -- per output ---------------------------------------------------------------------------

    def tables(self, o: int, var: Variable, rows: list[list[float]]) -> list[str]:
        """The output's trapezoid rows (rows: c.py's, one per term; singletons +inf: no area)
        and, for the polygon, its fixed points."""
        if is_sampled(var):
            return []
        inf = [np.inf] * 4 + [0.0, 0.0]
        rows = [row if kind == TermKind.TRAPEZOID else inf for row, kind in zip(rows, var.kinds)]
        lit = self.real.lit
        code = [f"static const {self.t} {self.P}ITEM_TERMS_{o}[{var.n_terms}][6] = "
                "{" + ", ".join("{" + ", ".join(lit(v) for v in row) + "}" for row in rows)
                + "};"]
        if self.area.inf.defuzzifier != Defuzzifier.CENTROID:
            fixed = fixed_points(var, self.t)
            self.n_fixed[o] = len(fixed)
            code.append(f"static const {self.t} {self.P}FIXED_{o}[{len(fixed)}] = "
                        "{" + ", ".join(lit(v) for v in fixed) + "};")
        return code

    def _pack_call(self, o: int, var: Variable) -> list[str]:
        ru = "" if self.rule_type is None else "ru, "
        return [f"  {self.t} items[{2 * self.n_items}];   /* levels and term ids */",
                f"  {self.p}pack(lv, {ru}{o}, {var.n_terms}, items);"]

    def defuzzify(self, o: int, var: Variable) -> list[str]:
        """Statements setting y[o] from the items."""
        t, lit, P = self.t, self.real.lit, self.P
        fallback = lit(var.default)
        if is_sampled(var):         # the grid walk, its context the packed items
            return ["{"] + self._pack_call(o, var) + \
                ["  " + s for s in self.area.defuzzify(o, var, "items")] + ["}"]
        lo, hi = lit(var.lo), lit(var.hi)
        if self.area.inf.defuzzifier == Defuzzifier.CENTROID:
            return [f"{{ {t} area = {lit(0)}, moment = {lit(0)};",
                    "  int k;",
                    f"  for (k = 0; k < {self.n_items}; ++k) {{",
                    f"    int j = {P}CONSEQUENTS[{self.rule}][{o}];",
                    f"    if (j < {var.n_terms}) {self.p}clipped(lv[k], {P}ITEM_TERMS_{o}[j], "
                    f"{lo}, {hi}, &area, &moment);",
                    "  }",
                    f"  y[{o}] = area > 0 ? moment / area : {fallback}; }}"]
        n = self.n_fixed[o] + 2 * self.n_items
        method = FUNCTION_OF[self.area.inf.defuzzifier]
        return ["{"] + self._pack_call(o, var) + [
            f"  {t} poly[{2 * n}];   /* the polygon of M: {n} (u, f) pairs */",
            f"  {self.p}items_polygon(items, {self.n_items}, {P}ITEM_TERMS_{o}, {P}FIXED_{o}, "
            f"{self.n_fixed[o]}, {lo}, {hi}, poly);",
            f"  y[{o}] = {self.p}{method}({self.p}polygon_point, poly, {n}, {fallback});",
            "}"]
