"""Linguistic variables and their terms: `var` and `terms` statements, shapes checked and
stored as the model's kind and parameter arrays."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .. import units
from ...engine.formula import FormulaError, parse_formula
from ...semantics.model import SourceLoc, TermKind, Variable
from ...semantics.shapes import WORDS, plain_words, term_core
from ..syntax import Name, Stmt, TermDef

INF = math.inf

# The registry's plain words (numbers = the model's params in order), as
# word -> (kind, arity, the condition that keeps them well defined, how to write them)
PLAIN_SHAPES = {word: (shape.kind, w.arity, w.valid, w.usage)
                for word, (shape, w) in plain_words().items()}

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
    hold: bool = False          # `var y ... hold_last`: Variable.lock_previous
    formulas: dict[int, tuple] = field(default_factory=dict)   # term -> (Formula, its loc)

    def term_names(self) -> list[str]:
        return [t[0] for t in self.terms]


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
        term_locs=[t[3] for t in v.terms], lock_previous=v.hold,
        formulas={t: formula for t, (formula, _) in v.formulas.items()} or None)


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
        var.hold = s.data["hold"]
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
            self.broken.add(name.text)      # its rules say nothing more
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
        self.broken.add(f"{var.name}.{term.name.text}")   # until it is added: rules on a
        self._add_checked_term(var, term)                   # broken term say nothing more

    def _add_checked_term(self, var: LinguisticVar, term: TermDef) -> None:
        if term.shape == "formula":
            self._add_formula_term(var, term)
            return
        shape, word = WORDS[term.shape]
        values = [n.value for n in term.args]
        arity = word.arity or len(values)
        if len(values) != arity:
            self.error(term.args[0].loc if term.args else term.name.loc,
                       f"`{term.shape}` takes {arity} number{'s' if arity > 1 else ''}, "
                       f"got {len(values)}")
            return
        if not word.valid(values):
            self.error(term.args[word.at].loc, word.message(values, term.name.text))
            return
        if var.is_input and not shape.on_inputs:
            self.error(term.name.loc, f"a linear term is a Takagi-Sugeno consequent: input "
                                      f"`{var.name}` cannot have one")
            return
        self._append_term(var, term.name, shape.kind, word.params(values))
        self.broken.discard(f"{var.name}.{term.name.text}")

    def _add_formula_term(self, var: LinguisticVar, term: TermDef) -> None:
        """`f = formula("sin(x) / x")`: fuzzylite's Function term, parsed by its own grammar
        (never evaluated as Python); the names it reads are checked with the rule blocks."""
        if "\\" in term.formula:
            self.error(term.formula_loc, "a formula has no backslash (a .fz string has no "
                                         "escapes); remove it")
            return
        try:
            formula = parse_formula(term.formula)
        except FormulaError as exc:
            self.error(replace(term.formula_loc, col=term.formula_loc.col + exc.offset),
                       str(exc))
            return
        t = self._append_term(var, term.name, TermKind.FUNCTION, (0.0,) * 4)
        var.formulas[t] = (formula, term.formula_loc)
        self.broken.discard(f"{var.name}.{term.name.text}")

    def _append_term(self, var: LinguisticVar, name: Name, kind: TermKind, params,
                     learnable: bool = False) -> int:
        if name.text in var.term_index:
            self.error(name.loc, f"term `{name.text}` is already defined for `{var.name}`; "
                                 "rename one of them")
            return var.term_index[name.text]
        core = term_core(kind, params)
        if kind != TermKind.FUNCTION and (core[1] < var.lo or core[0] > var.hi):
            # legal (FLL, FCL and FIS files have such terms, and .fz says what they say), but
            # likely a slip in a hand-written file: warned, where it is written
            where = f"{core[0]:g}" if core[0] == core[1] else f"[{core[0]:g}, {core[1]:g}]"
            effect = ("inputs inside the range meet only its flank" if var.is_input else
                      "the defuzzifier reads the output's range only")
            self.rep.warn(name.loc, f"term `{name.text}` of `{var.name}` peaks at {where}, "
                                    f"outside the range [{var.lo:g}, {var.hi:g}]: {effect}; "
                                    "widen the range if the term is meant")
        var.term_index[name.text] = len(var.terms)
        var.terms.append((name.text, kind, tuple(float(p) for p in params), name.loc))
        var.learnable.append(learnable)
        return len(var.terms) - 1
