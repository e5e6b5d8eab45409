"""Syntax objects -> Model: resolves names, checks the file, and reports every mistake found.

Builder walks the statements; each kind has its handler in the module of its concern
(chain, terms, rules, properties), all sharing the names and scopes kept here."""

from __future__ import annotations

import sympy

from .. import units
from ...errors import Reporter
from ...semantics.model import Model, Output, Param, Property, Signal, SourceLoc, Step
from ..syntax import Expr, Name, Stmt
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
        self.period: float | None = None
        self.declared: dict[str, SourceLoc] = {}
        self.broken: set[str] = set()    # names whose declaration failed: no follow-on errors
        self._hidden_count = 0

    def build(self, tree: dict, text: str, path: str) -> Model | None:
        for stmt in tree["statements"]:
            handler = getattr(self, f"_stmt_{stmt.kind}")
            handler(stmt)
        blocks = self._rulebases()
        self.check_property_inputs(blocks)
        tunables = self._tunables(tree["statements"], blocks)
        self.rep.raise_if_any()
        return Model(name=tree["name"].text, title=tree["title"], blocks=blocks,
                     period=self.period, params=self.params, signals=list(self.signals.values()),
                     steps=self.steps, outputs=self.outputs, properties=self.properties,
                     source_path=path, source_text=text, notes=self.notes,
                     tunables=tunables)

    def error(self, loc: SourceLoc, message: str) -> None:
        self.rep.error(loc, message)

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
