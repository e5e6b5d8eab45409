"""Linguistic variables and their terms: `var` and `terms` statements, shapes checked and
stored as the model's kind and parameter arrays."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import units
from ...engine.membership import discrete_problem
from ...semantics.model import SourceLoc, TermKind, Variable
from ..syntax import Name, Stmt, TermDef

INF = math.inf

SHAPE_ARITY = {"tri": 3, "trap": 4, "lshoulder": 2, "rshoulder": 2, "gauss": 2, "bell": 3,
               "sigmoid": 2, "singleton": 1, "linear": None, "discrete": None}

# Shapes written with their parameters in the model's order: word -> (kind, arity, the condition
# that keeps them well defined, what to say when it fails)
PLAIN_SHAPES = {
    "sshape": (TermKind.SSHAPE, 2, lambda v: v[0] < v[1], "sshape(start, end) with start < end"),
    "zshape": (TermKind.ZSHAPE, 2, lambda v: v[0] < v[1], "zshape(start, end) with start < end"),
    "pishape": (TermKind.PISHAPE, 4, lambda v: v[0] < v[1] and v[2] < v[3],
                "pishape(a, b, c, d) with a < b and c < d"),
    "spike": (TermKind.SPIKE, 2, lambda v: v[1] > 0, "spike(center, width) with width > 0"),
    "cosine": (TermKind.COSINE, 2, lambda v: v[1] > 0, "cosine(center, width) with width > 0"),
    "concave": (TermKind.CONCAVE, 2, lambda v: v[0] != v[1],
                "concave(inflection, end) with inflection != end"),
    "sigmoid_difference": (TermKind.SIGMOID_DIFFERENCE, 4, lambda v: v[1] != 0 and v[2] != 0,
                           "sigmoid_difference(left, rising, falling, right) with slopes != 0"),
    "sigmoid_product": (TermKind.SIGMOID_PRODUCT, 4, lambda v: v[1] != 0 and v[2] != 0,
                        "sigmoid_product(left, rising, falling, right) with slopes != 0"),
    "gaussian_product": (TermKind.GAUSSIAN_PRODUCT, 4, lambda v: v[1] > 0 and v[3] > 0,
                         "gaussian_product(mean_a, sigma_a, mean_b, sigma_b) with sigmas > 0"),
    "binary": (TermKind.BINARY, 2, lambda v: v[0] != v[1],
               "binary(start, direction) with direction != start"),
    "semi_ellipse": (TermKind.SEMI_ELLIPSE, 2, lambda v: v[0] != v[1],
                     "semi_ellipse(start, end) with start != end"),
    "arc": (TermKind.ARC, 2, lambda v: v[0] != v[1], "arc(start, end) with start != end"),
}

SHAPE_ARITY.update({word: arity for word, (_, arity, _, _) in PLAIN_SHAPES.items()})


@dataclass
class LinguisticVar:
    """A variable being assembled from `var`/`terms` statements."""
    name: str
    loc: SourceLoc
    lo: float | None = None
    hi: float | None = None
    unit: units.Unit | None = None
    default: float = 0.0
    terms: list[tuple[str, TermKind, tuple[float, ...], SourceLoc]] = field(default_factory=list)
    learnable: list[bool] = field(default_factory=list)
    is_input: bool = False
    term_index: dict[str, int] = field(default_factory=dict)   # name -> place: linear cost
    stated: bool = False        # a `terms` statement names it (`terms x :` gives no terms)

    def term_names(self) -> list[str]:
        return [t[0] for t in self.terms]


def term_core(kind: TermKind, params) -> tuple[float, float]:
    """The interval where a term is fully true (or its centre): it must meet the range."""
    if kind in (TermKind.TRAPEZOID, TermKind.PISHAPE):
        return params[1], params[2]
    if kind in (TermKind.SIGMOID_DIFFERENCE, TermKind.SIGMOID_PRODUCT):
        return params[0], params[3]
    if kind == TermKind.GAUSSIAN_PRODUCT:
        return params[0], params[2]
    if kind == TermKind.SEMI_ELLIPSE:
        return 0.5 * (params[0] + params[1]), 0.5 * (params[0] + params[1])
    rising = {TermKind.SSHAPE: True, TermKind.ZSHAPE: False,
              TermKind.CONCAVE: params[0] < params[1], TermKind.ARC: params[0] < params[1],
              TermKind.BINARY: params[0] < params[1]}.get(kind)
    if rising is not None:      # an edge: fully true from its end on (up to its end)
        edge = params[0] if kind in (TermKind.ZSHAPE, TermKind.BINARY) else params[1]
        return (edge, INF) if rising else (-INF, edge)
    if kind == TermKind.LINEAR:
        return -INF, INF
    if kind == TermKind.DISCRETE:     # x1 y1 x2 y2 ...: where y is highest
        top = [x for x, y in zip(params[0::2], params[1::2]) if y == max(params[1::2])]
        return top[0], top[-1]
    return params[0], params[0]


def to_variable(v: LinguisticVar) -> Variable:
    kinds = np.array([int(t[1]) for t in v.terms], dtype=np.int64)
    # Linear rows longer than the (T, 4) params live in `coefficients`, discrete points in
    # `points`.
    discrete = {t: np.array(term[2], dtype=float).reshape(-1, 2) for t, term in enumerate(v.terms)
                if term[1] == TermKind.DISCRETE}
    long_rows = {t: np.array(term[2], dtype=float) for t, term in enumerate(v.terms)
                 if len(term[2]) > 4 and t not in discrete}
    params = np.array([(0, 0, 0, 0) if len(term[2]) > 4 or t in discrete else term[2]
                       for t, term in enumerate(v.terms)], dtype=float).reshape(len(v.terms), 4)
    return Variable(
        coefficients=long_rows or None, points=discrete or None,
        name=v.name, lo=float(v.lo), hi=float(v.hi), names=[t[0] for t in v.terms], kinds=kinds,
        params=params, unit=units.format_unit(v.unit) if v.unit else None, default=v.default,
        learnable=None if v.is_input else np.array(v.learnable, dtype=bool), loc=v.loc,
        term_locs=[t[3] for t in v.terms])


class TermsBuilder:
    """The `var` and `terms` statements (a part of `Builder`)."""

    def _stmt_var(self, s: Stmt) -> None:
        name = s.data["name"]
        if not self._declare(name, "variable"):
            return
        var = LinguisticVar(name.text, name.loc)
        rng = self._range(s.data["range"], f"`{name.text}`")
        if rng is None:   # reported; its terms, rules and tables say nothing more
            self.broken.add(name.text)
            return
        var.lo, var.hi = rng
        if s.data["unit"]:
            var.unit = units.make(s.data["unit"])
        if s.data["default"] is not None:
            var.default = s.data["default"].value
        self.vars[name.text] = var

    def _stmt_terms(self, s: Stmt) -> None:
        for name in s.data["names"]:
            var = self._linguistic(name, s.data["range"])
            if var is None:
                continue
            if var.terms:
                self.error(name.loc, f"`{name.text}` already has terms; give all of a "
                                     "variable's terms in one `terms` statement")
                continue
            var.stated = True
            if s.data["default"] is not None:
                var.default = s.data["default"].value
            kind, *rest = s.data["terms"]
            if kind == "uniform":
                self._uniform_terms(var, *rest)
            else:
                for term in rest[0]:
                    self._add_term(var, term)

    def _linguistic(self, name: Name, rng) -> LinguisticVar | None:
        """The variable a `terms` statement talks about; inputs and lets get one on demand."""
        if name.text in self.broken:
            return None
        if name.text in self.vars:
            var = self.vars[name.text]
            if rng is not None:
                r = self._range(rng, f"`{name.text}`")
                if r and var.lo is not None and (var.lo, var.hi) != r:
                    self.error(rng[0].loc, f"`{name.text}` already has the range "
                                           f"[{var.lo:g}, {var.hi:g}]")
            return var
        source = self.signals.get(name.text) or self.step_by_name.get(name.text)
        var = LinguisticVar(name.text, name.loc, is_input=source is not None)
        if source is not None:
            var.lo, var.hi = source.lo, source.hi
            var.unit = self.units.get(name.text)
        elif name.text in self.declared:
            self.error(name.loc, f"`{name.text}` is a param; terms belong to inputs, `let` "
                                 "signals or rule-base outputs declared with `var`")
            return None
        else:
            self.declared[name.text] = name.loc
        if rng is not None:
            r = self._range(rng, f"`{name.text}`")
            if r:
                var.lo, var.hi = r
        if var.lo is None:
            hint = (f"write `let {name.text} in [lo, hi] = ...`" if var.is_input
                    else f"write `terms {name.text} in [lo, hi] : ...` or `var {name.text} in [lo, hi]`")
            self.error(name.loc, f"`{name.text}` needs a range for its terms: {hint}")
            return None
        self.vars[name.text] = var
        return var

    def _uniform_terms(self, var: LinguisticVar, names: list[Name], over) -> None:
        lo, hi = (over[0].value, over[1].value) if over else (var.lo, var.hi)
        if len(names) < 2:
            self.error(names[0].loc, "a uniform partition needs at least two terms")
            return
        last = len(names) - 1
        # One float per knot, shared by both neighbours: peak +- step would put a shared break
        # point in two places 1 ulp apart, and the slivers between them have three positive
        # terms, which turns off the engine's two-terms-per-input path.
        knots = [lo + (hi - lo) * k / last for k in range(last + 1)]
        for i, name in enumerate(names):
            peak = knots[i]
            a = -INF if i == 0 else knots[i - 1]
            d = INF if i == last else knots[i + 1]
            # The end terms are shoulders: 1 beyond the partition, as an operator expects.
            params = (a, a if i == 0 else peak, d if i == last else peak, d)
            self._append_term(var, name, TermKind.TRAPEZOID, params)

    def _add_term(self, var: LinguisticVar, term: TermDef) -> None:
        values = [n.value for n in term.args]
        arity = SHAPE_ARITY[term.shape] or len(values)
        if len(values) != arity:
            self.error(term.args[0].loc if term.args else term.name.loc,
                       f"`{term.shape}` takes {arity} number{'s' if arity > 1 else ''}, "
                       f"got {len(values)}")
            return
        shape = term.shape
        where = term.args[0].loc
        if shape in ("tri", "trap"):
            points = values if shape == "trap" else [values[0], values[1], values[1], values[2]]
            if any(p > q for p, q in zip(points, points[1:])) or points[0] == points[-1]:
                order = "a <= b <= c" if shape == "tri" else "a <= b <= c <= d"
                self.error(where, f"degenerate {shape} `{term.name.text}`"
                                  f"({', '.join(f'{v:g}' for v in values)}): break points must "
                                  f"satisfy {order} with a < {'c' if shape == 'tri' else 'd'}")
                return
            self._append_term(var, term.name, TermKind.TRAPEZOID, tuple(points))
        elif shape == "lshoulder":
            if not values[0] < values[1]:
                self.error(where, f"lshoulder `{term.name.text}` needs its top end before its "
                                  "foot: lshoulder(c, d) with c < d")
                return
            self._append_term(var, term.name, TermKind.TRAPEZOID, (-INF, -INF, *values))
        elif shape == "rshoulder":
            if not values[0] < values[1]:
                self.error(where, f"rshoulder `{term.name.text}` needs rshoulder(a, b) with a < b")
                return
            self._append_term(var, term.name, TermKind.TRAPEZOID, (*values, INF, INF))
        elif shape == "gauss":
            if not values[1] > 0:
                self.error(term.args[1].loc, f"gauss `{term.name.text}` needs a width > 0")
                return
            self._append_term(var, term.name, TermKind.GAUSSIAN, (*values, 0, 0))
        elif shape == "bell":
            if not (values[1] > 0 and values[2] > 0):
                self.error(term.args[1].loc, f"bell `{term.name.text}` needs width > 0 and slope > 0")
                return
            self._append_term(var, term.name, TermKind.BELL, (*values, 0))
        elif shape == "sigmoid":
            if values[1] == 0:
                self.error(term.args[1].loc, f"sigmoid `{term.name.text}` needs a slope other than 0")
                return
            self._append_term(var, term.name, TermKind.SIGMOID, (*values, 0, 0))
        elif shape in PLAIN_SHAPES:
            kind, _, valid, usage = PLAIN_SHAPES[shape]
            if not valid(values):
                self.error(where, f"degenerate {shape} `{term.name.text}`: write {usage}")
                return
            self._append_term(var, term.name, kind, (*values, 0, 0, 0)[:max(4, arity)])
        elif shape == "discrete":      # x1, y1, x2, y2, ...: the points stay as written
            problem = discrete_problem(values)
            if problem:
                self.error(where, f"discrete `{term.name.text}`: {problem}")
                return
            self._append_term(var, term.name, TermKind.DISCRETE, tuple(values))
        elif shape == "linear":
            if var.is_input:
                self.error(term.name.loc, f"a linear term is a Takagi-Sugeno consequent: input "
                                          f"`{var.name}` cannot have one")
                return
            self._append_term(var, term.name, TermKind.LINEAR, (*values, 0, 0, 0)[:max(4, arity)])
        else:
            self._append_term(var, term.name, TermKind.SINGLETON, (values[0], 0, 0, 0))

    def _append_term(self, var: LinguisticVar, name: Name, kind: TermKind, params,
                     learnable: bool = False) -> int:
        if name.text in var.term_index:
            self.error(name.loc, f"term `{name.text}` is already defined for `{var.name}`")
            return var.term_index[name.text]
        core = term_core(kind, params)
        if core[1] < var.lo or core[0] > var.hi:
            where = f"{core[0]:g}" if core[0] == core[1] else f"[{core[0]:g}, {core[1]:g}]"
            self.error(name.loc, f"term `{name.text}` of `{var.name}` peaks at {where}, outside "
                                 f"the range [{var.lo:g}, {var.hi:g}]")
        var.term_index[name.text] = len(var.terms)
        var.terms.append((name.text, kind, tuple(float(p) for p in params), name.loc))
        var.learnable.append(learnable)
        return len(var.terms) - 1
