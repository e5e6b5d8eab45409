"""Syntax objects -> Model: resolves names, checks the file, and reports every mistake found.

Builder walks the statements; each kind has its handler in the module of its concern
(chain, terms, rules, properties), all sharing the names and scopes kept here."""

from __future__ import annotations

from dataclasses import replace

import sympy

from .. import units
from ...engine.formula import name_offset
from ...errors import Reporter
from ...semantics.model import Model, Output, Param, Property, Signal, SourceLoc, Step
from ..syntax import Expr, Name, Num, Stmt
from .chain import RESERVED_PREFIX, ChainBuilder
from .properties import PropertiesBuilder
from .rules import BlockSpec, RulesBuilder
from .terms import LinguisticVar, TermsBuilder
from .tunables import TunablesBuilder


class Builder(ChainBuilder, TermsBuilder, RulesBuilder, PropertiesBuilder, TunablesBuilder):
    """One rule file's statements -> a Model, with every mistake reported."""

    def __init__(self, reporter: Reporter):
        self.rep = reporter
        self.params: dict[str, Param] = {}
        self.param_units: dict[str, units.Unit | None] = {}
        self.signals: dict[str, Signal] = {}
        self.steps: list[Step] = []
        self.step_by_name: dict[str, Step] = {}
        self.units: dict[str, units.Unit | None] = {}
        self.vars: dict[str, LinguisticVar] = {}
        self.top = BlockSpec("", None)   # the rules and inference outside any `block`
        self.block = self.top            # where rules and `inference` go now
        self.blocks: list[BlockSpec] = []  # the named blocks, in order
        self.outputs: list[Output] = []
        self.properties: list[Property] = []
        self.property_reads: list = []   # block outputs a property reads (check_property_inputs)
        self.notes: list[str] = []
        self.fuzzylite: dict | None = None    # the `fuzzylite` statements (Model.fuzzylite)
        self.period: float | None = None
        self.declared: dict[str, SourceLoc] = {}
        self.broken: set[str] = set()    # names whose declaration failed: no follow-on errors
        self._hidden_count = 0

    def build(self, tree: dict, text: str, path: str) -> Model | None:
        for stmt in tree["statements"]:
            handler = getattr(self, f"_stmt_{stmt.kind}")
            handler(stmt)
        blocks = self._rulebases()
        self._check_formula_reads(blocks)
        self.check_property_inputs(blocks)
        tunables = self._tunables(tree["statements"], blocks)
        self.rep.raise_if_any()
        return Model(name=tree["name"].text, title=tree["title"], blocks=blocks,
                     period=self.period, params=self.params, signals=list(self.signals.values()),
                     steps=self.steps, outputs=self.outputs, properties=self.properties,
                     source_path=path, source_text=text, notes=self.notes,
                     tunables=tunables, fuzzylite=self.fuzzylite,
                     warnings=list(self.rep.warnings))

    def error(self, loc: SourceLoc, message: str) -> None:
        self.rep.error(loc, message)

    def _check_formula_reads(self, blocks) -> None:
        """The names the `formula(...)` terms read, as the importers check fuzzylite's."""
        if not any(v.formulas for v in self.vars.values()):
            return
        from ...formats.functions import check_reads   # formats builds on the language

        def where(var, t: int, name: str) -> SourceLoc:
            formula, loc = self.vars[var.name].formulas[t]
            return replace(loc, col=loc.col + name_offset(formula.text, name))
        inputs = {name for name, v in self.vars.items() if v.is_input}
        for rb in blocks:
            check_reads(rb, where, self.rep, inputs)

    def _declare(self, name: Name, what: str) -> bool:
        if name.text.startswith(RESERVED_PREFIX):
            self.error(name.loc, f"`{name.text}`: names starting with `{RESERVED_PREFIX}` are "
                                 "reserved for the names fuzzyc generates (the memories of "
                                 f"delta, prev and lowpass); give this {what} another name")
            self.broken.add(name.text)      # no follow-on `unknown name` where it is read
            return False
        if name.text in self.declared:
            first = self.declared[name.text]
            self.error(name.loc, f"`{name.text}` is already declared at line {first.line}; "
                                 f"give this {what} another name")
            return False
        self.declared[name.text] = name.loc
        return True

    def _range(self, rng, what: str) -> tuple[float, float] | None:
        lo, hi = rng
        if not lo.value < hi.value:
            fix = ("write the lower bound first" if lo.value > hi.value
                   else "the upper bound must be above the lower")
            self.error(lo.loc, f"the range of {what} is empty: [{lo.value:g}, {hi.value:g}]; "
                               f"{fix}")
            return None
        return lo.value, hi.value

    def _constant(self, expr: Expr, what: str) -> float | None:
        """A build-time constant: numbers and params only (e.g. lowpass coefficients)."""
        value = self._expression(expr, allow_stateful=False)[0]
        if value is None:
            return None
        value = value.subs({sympy.Symbol(n): p.value for n, p in self.params.items()})
        if not value.is_number:
            self.error(expr.loc, f"{what} must be a number or a param, not a signal")
            return None
        return float(value)

    def _stmt_note(self, s: Stmt) -> None:
        self.notes.append(s.data["text"])

    FUZZYLITE_KEYS = {"lock_range": "NAME...", "resolution": "OUTPUT INTEGER",
                      "nan_default": "OUTPUT...", "replace_nan": "", "flat": "OUTPUT..."}

    def _stmt_fuzzylite(self, s: Stmt) -> None:
        """`fuzzylite KEY ARGS`: a fuzzylite file's setting for its tools' semantics."""
        key, args = s.data["key"], s.data["args"]
        got = self.fuzzylite if self.fuzzylite is not None else \
            {"locked": set(), "resolution": {}, "nan_default": set(), "known": False,
             "flat": set()}
        forms = ", ".join(f"`fuzzylite {k} {v}`".replace(" `", "`") for k, v in
                          self.FUZZYLITE_KEYS.items())
        names = [a for a in args if isinstance(a, Name)]
        numbers = [a for a in args if isinstance(a, Num)]
        where = (numbers or names or [key])[0].loc
        if key.text not in self.FUZZYLITE_KEYS:
            self.error(key.loc, f"unknown fuzzylite setting `{key.text}`: one of {forms}")
        elif key.text == "replace_nan" and args:
            self.error(where, "`fuzzylite replace_nan` takes nothing after it")
        elif key.text in ("lock_range", "nan_default", "flat") and (numbers or not names):
            self.error(where, f"`fuzzylite {key.text}` takes variable names")
        elif key.text == "resolution" and not (
                len(args) == 2 and isinstance(args[0], Name) and isinstance(args[1], Num)
                and args[1].is_int and args[1].value > 1):
            self.error(where, "`fuzzylite resolution` takes an output and an integer above 1 "
                              "(`fuzzylite resolution y 500`)")
        elif any(n.text not in self.vars for n in names):
            bad = next(n for n in names if n.text not in self.vars)
            self.error(bad.loc, f"`fuzzylite {key.text}` names `{bad.text}`, which is no "
                                "variable declared before it")
        elif key.text in ("flat", "nan_default") and any(self.vars[n.text].is_input
                                                         for n in names):
            bad = next(n for n in names if self.vars[n.text].is_input)
            self.error(bad.loc, f"`fuzzylite {key.text}` names the input `{bad.text}`: it "
                                "takes the variables the rules conclude")
        elif key.text == "replace_nan":
            got["known"] = True
        elif key.text == "resolution":
            got["resolution"][args[0].text] = int(args[1].value)
        else:
            got["locked" if key.text == "lock_range" else key.text].update(n.text for n in names)
        self.fuzzylite = got
