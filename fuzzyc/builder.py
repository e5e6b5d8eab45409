"""Syntax objects -> Model: resolves names, checks the file, and reports every mistake found.

Expressions become sympy objects built node by node from the parse tree (never from text).
Stateful calls (delta, prev, lowpass) become hidden steps of the signal chain, so every
expression in the Model is a pure function of the current sample.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import sympy

from . import units
from .conditions import Cond, Program, premise, program_array
from .errors import Reporter, source_lines, suggest
from .model import (Aggregation, CondOp, Connective, Defuzzifier, Hedge, Implication, Inference,
                    Model, Op, Output, OutputKind, Param, Property, RuleBase, Signal, SNorm,
                    SourceLoc, Step, TermKind, TNorm, Variable)
from .syntax import Clause, Condition, Expr, Name, Num, Stmt, TermDef

INF = math.inf

INFERENCE_VALUES = {
    "and": {"product": TNorm.PRODUCT, "prod": TNorm.PRODUCT,
            **{t.name.lower(): t for t in TNorm}},
    "or": {"probabilistic_sum": SNorm.PROBSUM, **{t.name.lower(): t for t in SNorm}},
    "implication": {"min": Implication.MIN, "product": Implication.PRODUCT,
                    "prod": Implication.PRODUCT},
    "aggregation": {"probabilistic_sum": Aggregation.PROBSUM,
                    **{a.name.lower(): a for a in Aggregation}},
    "defuzzify": {"centroid": Defuzzifier.CENTROID, "bisector": Defuzzifier.BISECTOR,
                  "mean_of_maximum": Defuzzifier.MEAN_OF_MAXIMUM, "mom": Defuzzifier.MEAN_OF_MAXIMUM,
                  "center_of_area": Defuzzifier.CENTER_OF_AREA, "coa": Defuzzifier.CENTER_OF_AREA,
                  "weighted_average": Defuzzifier.WEIGHTED_AVERAGE,
                  "weighted_sum": Defuzzifier.WEIGHTED_SUM},
}
INFERENCE_FIELD = {"and": "and_", "or": "or_", "implication": "implication",
                   "aggregation": "aggregation", "defuzzify": "defuzzifier"}

SHAPE_ARITY = {"tri": 3, "trap": 4, "lshoulder": 2, "rshoulder": 2, "gauss": 2, "bell": 3,
               "sigmoid": 2, "singleton": 1, "linear": None}
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
}
SHAPE_ARITY.update({word: arity for word, (_, arity, _, _) in PLAIN_SHAPES.items()})
LINEAR_DEFUZZIFIERS = (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM)
PURE_FUNCTIONS = {"clamp": 3, "abs": 1, "min": None, "max": None, "sqrt": 1, "exp": 1, "log": 1}
STATEFUL_FUNCTIONS = {"delta": 1, "prev": 1, "lowpass": 3}
HEDGES = {None: Hedge.NONE, "very": Hedge.VERY, "somewhat": Hedge.SOMEWHAT,
          "extremely": Hedge.EXTREMELY, "seldom": Hedge.SELDOM, "sharply": Hedge.SHARPLY}


@dataclass
class _LinguisticVar:
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

    def term_names(self) -> list[str]:
        return [t[0] for t in self.terms]


@dataclass
class RuleSpec:
    """One rule by names, as a front end collects it, before it becomes rows of the matrices."""
    clauses: dict[str, tuple[int, bool, Hedge]]   # input name -> (term, negated, hedge)
    connective: Connective
    conclusions: dict[str, int]                   # output name -> term index
    weight: float
    loc: SourceLoc
    origin: str
    program: Program | None = None                # a nested condition (clauses is then {})

    def connectives(self) -> set[Connective]:
        """The connectives the rule needs a norm for (those joining two or more parts)."""
        if self.program is not None:
            return {Connective.AND if step[0] == CondOp.AND else Connective.OR
                    for step in self.program if step[0] in (CondOp.AND, CondOp.OR)}
        return {self.connective} if len(self.clauses) > 1 else set()


@dataclass
class _Block:
    """A rule block being assembled: the file's top level, or a `block NAME { ... }`."""
    name: str
    loc: SourceLoc | None
    inference: Inference = field(default_factory=Inference)
    rules: list[RuleSpec] = field(default_factory=list)
    # output name -> its own aggregation and/or defuzzifier, by Inference field
    choices: dict[str, dict[str, Any]] = field(default_factory=dict)

    def reads(self) -> set[str]:
        return {name for r in self.rules
                for name in (r.clauses if r.program is None else [p[1] for p in r.program])
                if name}

    def writes(self) -> set[str]:
        return {name for r in self.rules for name in r.conclusions}

    def inference_of(self, output: str) -> Inference:
        return replace(self.inference, **self.choices.get(output, {}))


class Builder:
    def __init__(self, reporter: Reporter):
        self.rep = reporter
        self.params: dict[str, Param] = {}
        self.param_units: dict[str, units.Unit | None] = {}
        self.signals: dict[str, Signal] = {}
        self.steps: list[Step] = []
        self.step_by_name: dict[str, Step] = {}
        self.units: dict[str, units.Unit | None] = {}
        self.vars: dict[str, _LinguisticVar] = {}
        self.top = _Block("", None)      # the rules and inference outside any `block`
        self.block = self.top            # where rules and `inference` go now
        self.blocks: list[_Block] = []   # the named blocks, in order
        self.outputs: list[Output] = []
        self.properties: list[Property] = []
        self.notes: list[str] = []
        self.period: float | None = None
        self.declared: dict[str, SourceLoc] = {}
        self.broken: set[str] = set()    # names whose declaration failed: no follow-on errors
        self._hidden_count = 0

    # ------------------------------------------------------------------ entry point
    def build(self, tree: dict, text: str, path: str) -> Model | None:
        for stmt in tree["statements"]:
            handler = getattr(self, f"_stmt_{stmt.kind}")
            handler(stmt)
        blocks = self._rulebases()
        self.rep.raise_if_any()
        return Model(name=tree["name"].text, title=tree["title"], blocks=blocks,
                     period=self.period, params=self.params, signals=list(self.signals.values()),
                     steps=self.steps, outputs=self.outputs, properties=self.properties,
                     source_path=path, source_text=text, notes=self.notes)

    # ------------------------------------------------------------------ helpers
    def error(self, loc: SourceLoc, message: str) -> None:
        self.rep.error(loc, message)

    def _declare(self, name: Name, what: str) -> bool:
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
        value = self._sympy(expr, allow_stateful=False)[0]
        if value is None:
            return None
        value = value.subs({sympy.Symbol(n): p.value for n, p in self.params.items()})
        if not value.is_number:
            self.error(expr.loc, f"{what} must be a number or a param, not a signal")
            return None
        return float(value)

    # ------------------------------------------------------------------ declarations
    def _stmt_period(self, s: Stmt) -> None:
        unit = units.make(s.data["unit"])
        scale = units.SECONDS.get(unit[0][0]) if len(unit) == 1 and unit[0][1] == 1 else None
        if scale is None:
            self.error(s.data["value"].loc, "period needs a time unit: s, ms or us")
            return
        self.period = s.data["value"].value * scale

    def _stmt_param(self, s: Stmt) -> None:
        name = s.data["name"]
        if self._declare(name, "param"):
            unit = units.make(s.data["unit"]) if s.data["unit"] else None
            self.params[name.text] = Param(name.text, s.data["value"].value,
                                           units.format_unit(unit) if unit else None, name.loc)
            self.units[name.text] = unit

    def _stmt_input(self, s: Stmt) -> None:
        name = s.data["name"]
        rng = self._range(s.data["range"], f"input `{name.text}`")
        if rng is None:
            self.broken.add(name.text)
        if self._declare(name, "input") and rng:
            unit = units.make(s.data["unit"]) if s.data["unit"] else None
            self.signals[name.text] = Signal(name.text, rng[0], rng[1],
                                             units.format_unit(unit) if unit else None, name.loc)
            self.units[name.text] = unit

    def _stmt_let(self, s: Stmt) -> None:
        name = s.data["name"]
        if not self._declare(name, "signal"):
            return
        declared = units.make(s.data["unit"]) if s.data["unit"] else None
        expr, unit = self._sympy(s.data["expr"], allow_stateful=True, owner=name.text)
        rng = self._range(s.data["range"], f"`{name.text}`") if s.data["range"] else None
        if expr is None or (s.data["range"] and rng is None):
            self.broken.add(name.text)
            return
        if declared is not None and unit is not None and declared != unit:
            self.error(s.data["expr"].loc,
                       f"`{name.text}` is declared in {units.format_unit(declared)} but its "
                       f"expression is in {units.format_unit(unit)}")
        self.units[name.text] = declared if declared is not None else unit
        step = Step(name.text, Op.ASSIGN, expr,
                    unit=units.format_unit(self.units[name.text]) if self.units[name.text] else None,
                    lo=rng[0] if rng else None, hi=rng[1] if rng else None, loc=name.loc)
        self._add_step(step)

    def _add_step(self, step: Step) -> None:
        self.steps.append(step)
        self.step_by_name[step.name] = step

    def _stmt_var(self, s: Stmt) -> None:
        name = s.data["name"]
        if not self._declare(name, "variable"):
            return
        var = _LinguisticVar(name.text, name.loc)
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

    def _stmt_note(self, s: Stmt) -> None:
        self.notes.append(s.data["text"])

    # ------------------------------------------------------------------ terms
    def _stmt_terms(self, s: Stmt) -> None:
        for name in s.data["names"]:
            var = self._linguistic(name, s.data["range"])
            if var is None:
                continue
            if var.terms:
                self.error(name.loc, f"`{name.text}` already has terms; give all of a "
                                     "variable's terms in one `terms` statement")
                continue
            if s.data["default"] is not None:
                var.default = s.data["default"].value
            kind, *rest = s.data["terms"]
            if kind == "uniform":
                self._uniform_terms(var, *rest)
            else:
                for term in rest[0]:
                    self._add_term(var, term)

    def _linguistic(self, name: Name, rng) -> _LinguisticVar | None:
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
        var = _LinguisticVar(name.text, name.loc, is_input=source is not None)
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

    def _uniform_terms(self, var: _LinguisticVar, names: list[Name], over) -> None:
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

    def _add_term(self, var: _LinguisticVar, term: TermDef) -> None:
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
        elif shape == "linear":
            if var.is_input:
                self.error(term.name.loc, f"a linear term is a Takagi-Sugeno consequent: input "
                                          f"`{var.name}` cannot have one")
                return
            self._append_term(var, term.name, TermKind.LINEAR, (*values, 0, 0, 0)[:max(4, arity)])
        else:
            self._append_term(var, term.name, TermKind.SINGLETON, (values[0], 0, 0, 0))

    def _append_term(self, var: _LinguisticVar, name: Name, kind: TermKind, params,
                     learnable: bool = False) -> int:
        if name.text in var.term_index:
            self.error(name.loc, f"term `{name.text}` is already defined for `{var.name}`")
            return var.term_index[name.text]
        core = _core(kind, params)
        if core[1] < var.lo or core[0] > var.hi:
            where = f"{core[0]:g}" if core[0] == core[1] else f"[{core[0]:g}, {core[1]:g}]"
            self.error(name.loc, f"term `{name.text}` of `{var.name}` peaks at {where}, outside "
                                 f"the range [{var.lo:g}, {var.hi:g}]")
        var.term_index[name.text] = len(var.terms)
        var.terms.append((name.text, kind, tuple(float(p) for p in params), name.loc))
        var.learnable.append(learnable)
        return len(var.terms) - 1

    # ------------------------------------------------------------------ inference
    def _stmt_inference(self, s: Stmt) -> None:
        output = s.data["output"]
        var = output and self._output_var(output)
        for key, value in s.data["settings"]:
            options = INFERENCE_VALUES[key]
            if value.text not in options:
                self.error(value.loc, f"unknown {key} `{value.text}`: "
                                      f"{suggest(value.text, list(options))}")
            elif output is None:
                setattr(self.block.inference, INFERENCE_FIELD[key], options[value.text])
            elif key not in ("aggregation", "defuzzify"):
                self.error(value.loc, f"`{key}` belongs to the whole rule base (or block); an "
                                      f"output has its own aggregation and defuzzify only")
            elif var is not None:
                self.block.choices.setdefault(var.name, {})[INFERENCE_FIELD[key]] = \
                    options[value.text]

    def _stmt_block(self, s: Stmt) -> None:
        name = s.data["name"]
        if any(b.name == name.text for b in self.blocks):
            self.error(name.loc, f"there is already a block `{name.text}`")
        # a block starts from the inference given outside blocks (its defaults)
        self.block = _Block(name.text, name.loc, replace(self.top.inference),
                            choices={k: dict(v) for k, v in self.top.choices.items()})
        for stmt in s.data["statements"]:
            getattr(self, f"_stmt_{stmt.kind}")(stmt)
        self.blocks.append(self.block)
        self.block = self.top

    # ------------------------------------------------------------------ rules
    def _input_var(self, name: Name) -> _LinguisticVar | None:
        var = self.vars.get(name.text)
        if var is None and name.text in self.broken:
            return None
        if var is None:
            known = [v for v, lv in self.vars.items() if lv.is_input]
            self.error(name.loc, f"unknown input `{name.text}` in a condition: "
                                 f"{suggest(name.text, known)}")
            return None
        if not var.is_input and self.block is self.top:
            self.error(name.loc, f"`{name.text}` is a rule-base output; conditions name inputs "
                                 "(or, inside a `block`, outputs of earlier blocks) "
                                 f"({', '.join(v for v, lv in self.vars.items() if lv.is_input)})")
            return None
        return var

    def _output_var(self, name: Name) -> _LinguisticVar | None:
        var = self.vars.get(name.text)
        if var is None and name.text in self.broken:
            return None
        if var is None:
            known = [v for v, lv in self.vars.items() if not lv.is_input]
            self.error(name.loc, f"unknown output `{name.text}`: {suggest(name.text, known)}")
            return None
        if var.is_input:
            outs = [v for v, lv in self.vars.items() if not lv.is_input]
            self.error(name.loc, f"`{name.text}` is an input of the rule base; a conclusion names "
                                 f"an output ({', '.join(outs) or 'declare one with `var`'})")
            return None
        return var

    def _term(self, var: _LinguisticVar, term: Name, context: str) -> int | None:
        names = var.term_names()
        if term.text not in names:
            self.error(term.loc, f"unknown term `{term.text}` of `{var.name}` in {context}: "
                                 f"{suggest(term.text, names)} (known terms are {' '.join(names)})")
            return None
        return names.index(term.text)

    def _leaf(self, clause: Clause, context: str) -> Cond | None:
        var = self._input_var(clause.var)
        term = None if var is None else self._term(var, clause.term, context)
        if term is None:
            return None
        return Cond("is", leaf=(var.name, (term, clause.negated, HEDGES[clause.hedge])))

    def _clause(self, clause: Clause, rule_clauses: dict, context: str) -> bool:
        """One clause of a flat conjunction (a table's guard, a `where`)."""
        leaf = self._leaf(clause, context)
        if leaf is None:
            return False
        name, value = leaf.leaf
        if name in rule_clauses:
            self.error(clause.var.loc, f"`{name}` appears twice in one guard")
            return False
        rule_clauses[name] = value
        return True

    def _condition(self, cond: Clause | Condition, context: str) -> Cond | None:
        if isinstance(cond, Clause):
            return self._leaf(cond, context)
        parts = [self._condition(p, context) for p in cond.parts]
        return None if None in parts else Cond(cond.connective, parts)

    def _conclusion(self, var: _LinguisticVar, term, context: str,
                    learnable: bool = False, label: str = "") -> int | None:
        """A term name, or a number: a singleton consequent of its own."""
        if isinstance(term, Num):
            name = Name(label or f"_v{len(var.terms)}", term.loc)
            if not (var.lo <= term.value <= var.hi):
                self.error(term.loc, f"value {term.value:g} is outside `{var.name}`'s range "
                                     f"[{var.lo:g}, {var.hi:g}]")
                return None
            return self._append_term(var, name, TermKind.SINGLETON, (term.value, 0, 0, 0), learnable)
        return self._term(var, term, context)

    def _stmt_rule(self, s: Stmt) -> None:
        label = f"rule {s.data['name'].text}" if s.data["name"] else f"rule at line {s.loc.line}"
        condition = self._condition(s.data["condition"], label)
        ok = condition is not None
        conclusions = {}
        for concl in s.data["conclusions"]:
            var = self._output_var(concl.var)
            if var is None:
                ok = False
                continue
            term = self._conclusion(var, concl.term, label)
            if term is None:
                ok = False
            elif var.name in conclusions:
                self.error(concl.var.loc, f"`{var.name}` is concluded twice in one rule")
                ok = False
            else:
                conclusions[var.name] = term
        weight = self._weight(s.data["weight"])
        if ok and weight is not None:
            clauses, connective, program = premise(condition)
            self.block.rules.append(RuleSpec(clauses, connective, conclusions, weight, s.loc, label,
                                       program))

    def _weight(self, num: Num | None) -> float | None:
        if num is None:
            return 1.0
        if not 0.0 <= num.value <= 1.0:
            self.error(num.loc, f"a rule weight lies in [0, 1], got {num.value:g}")
            return None
        return num.value

    def _stmt_table2d(self, s: Stmt) -> None:
        d = s.data
        out = self._output_var(d["output"])
        guard: dict = {}
        guard_ok = all([self._clause(c, guard, f"the guard of table {d['output'].text}")
                        for c in d["guard"]])
        axes = {}
        for kind, var_name, terms in d["axes"]:
            if kind in axes:
                self.error(var_name.loc, f"table has two `{kind}` axes; give one `rows` and one `cols`")
                return
            var = self._input_var(var_name)
            if var is None:
                return
            if var.name in guard:
                self.error(var_name.loc, f"`{var.name}` is both a table axis and in the guard")
                return
            idx = [self._term(var, t, f"the {kind} of table {d['output'].text}") for t in terms]
            axes[kind] = (var, idx, terms)
        if out is None or not guard_ok or len(axes) != 2 or any(None in a[1] for a in axes.values()):
            return
        (row_var, row_idx, row_terms), (col_var, col_idx, col_terms) = axes["rows"], axes["cols"]
        cells = d["cells"]
        if not self._table_shape(s, cells, len(row_idx), len(col_idx)):
            return
        guard_text = ("when " + " and ".join(f"{c.var.text} is {c.term.text}" for c in d["guard"])
                      + ", ") if d["guard"] else ""
        for r, (ri, rt) in enumerate(zip(row_idx, row_terms)):
            for c, (ci, ct) in enumerate(zip(col_idx, col_terms)):
                cell = cells[r * len(col_idx) + c]
                if isinstance(cell, Name) and cell.text == "-":
                    continue
                origin = (f"table {out.name} {guard_text}row {row_var.name}={rt.text}, "
                          f"col {col_var.name}={ct.text}")
                if d["learnable"] and not isinstance(cell, Num):
                    self.error(cell.loc, "cells of a learnable table are numbers (the initial "
                                         f"weights), not `{cell.text}`")
                    continue
                term = self._conclusion(out, cell, f"table {out.name}", d["learnable"],
                                        label=f"w_{rt.text}_{ct.text}" if d["learnable"] else "")
                if term is None:
                    continue
                clauses = dict(guard)
                clauses[row_var.name] = (ri, False, Hedge.NONE)
                clauses[col_var.name] = (ci, False, Hedge.NONE)
                self.block.rules.append(RuleSpec(clauses, Connective.AND, {out.name: term}, 1.0,
                                        cell.loc, origin))

    def _table_shape(self, s: Stmt, cells, n_rows: int, n_cols: int) -> bool:
        """Each printed line of the table is one row of the declared width."""
        lines: dict[int, list] = {}
        for cell in cells:
            lines.setdefault(cell.loc.line, []).append(cell)
        rows = list(lines.values())
        for row in rows:
            if len(row) != n_cols:
                self.error(row[0].loc, f"this table row has {len(row)} cells; the table declares "
                                       f"{n_cols} columns")
                return False
        if len(rows) != n_rows:
            self.error(s.loc, f"table `{s.data['output'].text}` has {len(rows)} rows; its "
                              f"`rows` axis declares {n_rows}")
            return False
        return True

    def _stmt_list_table(self, s: Stmt) -> None:
        d = s.data
        premises = [self._input_var(n) for n in d["premises"]]
        outputs = [self._output_var(n) for n in d["outputs"]]
        if None in premises or None in outputs:
            return
        labels: dict[int, SourceLoc] = {}
        for row in d["rows"]:
            label = int(row["label"].value)
            if label in labels:
                self.error(row["label"].loc, f"rule {label} is numbered twice in this table")
            labels[label] = row["label"].loc
            context = f"table rule {label}"
            if len(row["premises"]) != len(premises) or len(row["conclusions"]) != len(outputs):
                self.error(row["label"].loc,
                           f"rule {label} has {len(row['premises'])} premise and "
                           f"{len(row['conclusions'])} conclusion cells; the table header "
                           f"declares {len(premises)} and {len(outputs)}")
                continue
            clauses: dict = {}
            ok = True
            for var, cell in zip(premises, row["premises"]):
                if cell.text == "*":
                    continue
                term = self._term(var, cell, context)
                ok = ok and term is not None
                clauses[var.name] = (term, False, Hedge.NONE)
            conclusions = {}
            for var, cell in zip(outputs, row["conclusions"]):
                term = self._term(var, cell, context)
                ok = ok and term is not None
                conclusions[var.name] = term
            weight = self._weight(row["weight"])
            if ok and weight is not None:
                self.block.rules.append(RuleSpec(clauses, Connective.AND, conclusions, weight,
                                        row["label"].loc, context))

    # ------------------------------------------------------------------ outputs
    def _stmt_output(self, s: Stmt) -> None:
        d = s.data
        name = d["name"]
        if not self._declare(name, "output"):
            return
        rng = self._range(d["range"], f"output `{name.text}`")
        expr_node = d["expr"]
        kind, inner = OutputKind.DIRECT, expr_node
        if expr_node.op == "call" and expr_node.name == "integrate":
            kind, inner = OutputKind.INCREMENT, expr_node.args
        elif (expr_node.op == "div" and expr_node.args[0].op == "constant"
              and expr_node.args[0].args[0] == 1.0 and expr_node.args[1].op == "call"
              and expr_node.args[1].name == "integrate"):
            kind, inner = OutputKind.RECIPROCAL_INCREMENT, expr_node.args[1].args
        if isinstance(inner, list):
            if len(inner) != 1:
                self.error(expr_node.loc, "integrate takes one argument: the increment per sample")
                return
            inner = inner[0]
        expr, _unit = self._sympy(inner, allow_stateful=False)
        if expr is None or rng is None:
            return
        if kind == OutputKind.RECIPROCAL_INCREMENT and rng[0] <= 0:
            self.error(d["range"][0].loc, "a reciprocal output needs a range above 0")
            return
        init = d["init"].value if d["init"] is not None else rng[0]
        if not rng[0] <= init <= rng[1]:
            self.error(d["init"].loc, f"start value {init:g} is outside [{rng[0]:g}, {rng[1]:g}]")
            return
        unit = units.make(d["unit"]) if d["unit"] else None
        self.units[name.text] = unit
        self.outputs.append(Output(name.text, kind, expr, rng[0], rng[1], init,
                                   units.format_unit(unit) if unit else None, name.loc))

    # ------------------------------------------------------------------ expressions
    def _known_symbol(self, name: str) -> bool:
        return (name in self.params or name in self.signals or name in self.step_by_name
                or (name in self.vars and not self.vars[name].is_input))

    def _sympy(self, node: Expr, allow_stateful: bool, owner: str = ""):
        """(sympy expression, unit) for an expression node; (None, None) after an error."""
        op = node.op
        if op == "constant":
            value, is_int = node.args
            return (sympy.Integer(int(value)) if is_int else sympy.Float(value)), None
        if op == "symbol":
            name = node.args[0]
            if name in self.broken:
                return None, None
            if not self._known_symbol(name):
                steps = [n for n, st in self.step_by_name.items() if not st.hidden]
                outs = [n for n, v in self.vars.items() if not v.is_input]
                known = sorted([*self.params, *self.signals, *steps, *outs])
                self.error(node.loc, f"unknown name `{name}`: {suggest(name, known)}")
                return None, None
            return sympy.Symbol(name), self.units.get(name)
        if op == "call":
            return self._call(node, allow_stateful, owner)
        if op == "neg":
            a, ua = self._sympy(node.args[0], allow_stateful, owner)
            return (None, None) if a is None else (-a, ua)
        return fold_left(node, lambda n: self._sympy(n, allow_stateful, owner),
                         self._sympy_binary)

    def _sympy_binary(self, node: Expr, left, right):
        """(sympy, unit) of a binary `node` from its operands' (either (None, None) after an
        error)."""
        op = node.op
        (a, ua), (b, ub) = left, right
        if a is None or b is None:
            return None, None
        if op in ("add", "sub"):
            return (a + b if op == "add" else a - b), self._same_unit(ua, ub, node, op)
        if op == "mul":
            return a * b, units.multiply(ua, ub)
        if op == "div":
            return a / b, units.multiply(ua, ub, -1)
        if op == "pow":
            exponent = int(b) if b.is_Integer else None
            if ua is not None and exponent is None:
                self.error(node.loc, "a quantity with a unit can only be raised to a whole number")
                return None, None
            return a ** b, units.power(ua, exponent) if exponent is not None else None
        raise AssertionError(op)

    def _same_unit(self, ua, ub, node: Expr, what: str):
        if ua is not None and ub is not None and ua != ub:
            verb = {"add": "add", "sub": "subtract", "compare": "compare"}.get(what, "combine")
            self.error(node.loc, f"unit mismatch: cannot {verb} {units.format_unit(ua)} and "
                                 f"{units.format_unit(ub)}")
        return ua if ua is not None else ub

    def _call(self, node: Expr, allow_stateful: bool, owner: str):
        fn, args = node.name, node.args
        arity = PURE_FUNCTIONS.get(fn, STATEFUL_FUNCTIONS.get(fn, -1))
        if arity == -1:
            hint = ("; integrate() is only allowed as a whole output expression"
                    if fn == "integrate" else "")
            known = [*PURE_FUNCTIONS, *STATEFUL_FUNCTIONS]
            self.error(node.loc, f"unknown function `{fn}`: {suggest(fn, known)}{hint}")
            return None, None
        if arity is not None and len(args) != arity:
            self.error(node.loc, f"`{fn}` takes {arity} argument{'s' if arity > 1 else ''}, "
                                 f"got {len(args)}")
            return None, None
        if fn in STATEFUL_FUNCTIONS:
            if not allow_stateful:
                self.error(node.loc, f"`{fn}` keeps state: use it in a `let`, then name that signal")
                return None, None
            return self._stateful(node, owner)
        parts = [self._sympy(a, allow_stateful, owner) for a in args]
        if any(p[0] is None for p in parts):
            return None, None
        values = [p[0] for p in parts]
        unit = parts[0][1]
        if fn in ("clamp", "min", "max"):
            for p in parts[1:]:
                unit = self._same_unit(unit, p[1], node, "combine")
        if fn == "clamp":
            return sympy.Min(sympy.Max(values[0], values[1]), values[2]), unit
        if fn in ("min", "max"):
            return (sympy.Min if fn == "min" else sympy.Max)(*values), unit
        if fn == "abs":
            return sympy.Abs(values[0]), unit
        function = {"sqrt": sympy.sqrt, "exp": sympy.exp, "log": sympy.log}[fn]
        if fn != "sqrt" and unit:
            self.error(node.loc, f"`{fn}` needs a dimensionless argument, got {units.format_unit(unit)}")
        return function(values[0]), None

    def _stateful(self, node: Expr, owner: str):
        arg, unit = self._sympy(node.args[0], True, owner)
        if arg is None:
            return None, None
        coeffs = (0.0, 0.0)
        op = {"delta": Op.DELTA, "prev": Op.PREV, "lowpass": Op.LOWPASS}[node.name]
        if op == Op.LOWPASS:
            a = self._constant(node.args[1], "the lowpass coefficient a")
            b = self._constant(node.args[2], "the lowpass coefficient b")
            if a is None or b is None:
                return None, None
            if not (0 <= a < 1 and b > 0):
                self.error(node.args[1].loc, f"lowpass(x, a, b) needs 0 <= a < 1 and b > 0 "
                                             f"(y = a*y_prev + b*x), got a={a:g}, b={b:g}")
                return None, None
            coeffs = (a, b)
        self._hidden_count += 1
        name = f"_{node.name}{self._hidden_count}_{owner}"
        self._add_step(Step(name, op, arg, coeffs, units.format_unit(unit) if unit else None,
                            hidden=True, loc=node.loc))
        self.units[name] = unit
        return sympy.Symbol(name), unit

    # ------------------------------------------------------------------ verification
    def _stmt_verify(self, s: Stmt) -> None:
        for prop in s.data["properties"]:
            built = getattr(self, f"_prop_{prop.kind}")(prop)
            if built is not None:
                self.properties.append(Property(prop.kind, built, prop.loc,
                                                self._source_text(prop)))

    def _source_text(self, s: Stmt) -> str:
        lines = source_lines(self.rep.text)
        if s.end is None or s.loc.line > len(lines):
            return ""
        if s.loc.line == s.end.line:
            return lines[s.loc.line - 1][s.loc.col - 1:s.end.col - 1].strip()
        return lines[s.loc.line - 1][s.loc.col - 1:].strip() + " ..."

    def _prop_covers(self, p: Stmt):
        names = [self._input_var(n) for n in p.data["inputs"]]
        if None in names:
            return None
        return {"inputs": [v.name for v in names], "level": p.data["level"].value}

    def _prop_consistent(self, p: Stmt):
        return {}

    def _optional_output(self, p: Stmt):
        name = p.data["output"]
        if name is None:
            return {"output": None}
        var = self._output_var(name)
        return None if var is None else {"output": var.name}

    _prop_complete = _optional_output
    _prop_continuous = _optional_output

    def _prop_monotone(self, p: Stmt):
        out, inp = self._output_var(p.data["output"]), self._input_var(p.data["input"])
        where: dict = {}
        ok = all([self._clause(c, where, "a `where` guard") for c in p.data["where"]])
        if out is None or inp is None or not ok:
            return None
        return {"output": out.name, "input": inp.name, "direction": p.data["direction"],
                "where": [(v, t, neg) for v, (t, neg, _h) in where.items()]}

    def _prop_bounded(self, p: Stmt):
        name = p.data["signal"]
        known = [*self.signals, *self.step_by_name, *(o.name for o in self.outputs),
                 *(v for v, lv in self.vars.items() if not lv.is_input)]
        if name.text not in known:
            self.error(name.loc, f"unknown signal `{name.text}` in `bounded`: "
                                 f"{suggest(name.text, known)}")
            return None
        rng = self._range(p.data["range"], f"`bounded {name.text}`")
        return None if rng is None else {"signal": name.text, "lo": rng[0], "hi": rng[1]}

    def _seconds(self, num: Num, unit, what: str) -> float | None:
        if unit is None:
            return num.value
        u = units.make(unit)
        scale = units.SECONDS.get(u[0][0]) if len(u) == 1 and u[0][1] == 1 else None
        if scale is None:
            self.error(num.loc, f"{what} needs a time unit (s, ms, min)")
            return None
        return num.value * scale

    def _prop_closed_loop(self, p: Stmt):
        d = p.data
        duration = self._seconds(d["duration"], d["unit"], "the loop duration")
        settings, ranges, before, faults, checks = {}, {}, {}, [], []
        for item in d["items"]:
            if item.kind == "set":
                settings[item.data["key"].text] = item.data["value"].value
            elif item.kind == "vary":
                key = item.data["key"].text
                rng = self._range(item.data["range"], f"`vary {key}`")
                if rng and self._varied_key(item.data["key"]):
                    ranges[key] = rng
                if item.data["before"]:
                    seconds = self._seconds(*item.data["before"], "`steps before`")
                    if seconds is not None:
                        before[key] = seconds
            elif item.kind == "fault":
                seconds = self._seconds(item.data["seconds"], item.data["unit"], "a fault")
                if seconds is not None and seconds <= 0:
                    self.error(item.data["seconds"].loc, "a fault lasts a positive time")
                elif seconds is not None:
                    faults.append((item.data["signal"].text, item.data["kind"], seconds))
            else:
                check = self._temporal(item)
                if check is not None:
                    checks.append(Property(item.kind, check, item.loc, self._source_text(item)))
        if duration is None:
            return None
        return {"scenario": d["scenario"].text, "duration": duration, "set": settings,
                "vary": ranges, "steps_before": before, "faults": faults, "checks": checks}

    def _varied_key(self, key) -> bool:
        """`vary plant.NAME` (a plant parameter, resolved with the scenario) or
        `vary controller.NAME` (a param of this file: a set point)."""
        kind, _, name = key.text.partition(".")
        if kind == "controller" and name in self.params:
            return True
        if kind == "controller":
            self.error(key.loc, f"`{key.text}`: this file has no param `{name}`"
                       + (f"; params: {', '.join(self.params)}" if self.params else ""))
        elif kind != "plant" or not name:
            self.error(key.loc, f"`vary {key.text}`: vary a plant parameter (plant.NAME) or a "
                       f"param of this file (controller.NAME)")
        return kind == "plant" and bool(name)

    def _predicate(self, node: Expr):
        """Comparisons over plant and controller signals; names are resolved at run time."""
        if node.op in ("and", "or"):
            parts = [self._predicate(a) for a in node.args]
            if any(p is None for p in parts):
                return None
            return (sympy.And if node.op == "and" else sympy.Or)(*parts)
        left, right = self._free_expr(node.args[0]), self._free_expr(node.args[1])
        if left is None or right is None:
            return None
        relation = {"<": sympy.Lt, "<=": sympy.Le, ">": sympy.Gt, ">=": sympy.Ge}[node.name]
        return relation(left, right, evaluate=False)

    def _free_expr(self, node: Expr):
        """An expression in a loop property: any name (a plant signal) is allowed."""
        if node.op == "symbol":
            return sympy.Symbol(node.args[0])
        if node.op == "constant":
            return sympy.Float(node.args[0])
        if node.op == "call" and node.name in ("abs", "min", "max"):
            args = [self._free_expr(a) for a in node.args]
            if None in args:
                return None
            return {"abs": sympy.Abs, "min": sympy.Min, "max": sympy.Max}[node.name](*args)
        if node.op == "call":
            self.error(node.loc, f"`{node.name}` is not allowed in a loop property: abs, min, max")
            return None
        if node.op == "neg":
            arg = self._free_expr(node.args[0])
            return None if arg is None else -arg
        ops = {"add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
               "div": lambda a, b: a / b, "pow": lambda a, b: a ** b}
        return fold_left(node, self._free_expr, lambda n, a, b: None if a is None or b is None
                         else ops[n.op](a, b))

    def _temporal(self, item: Stmt):
        d = item.data
        if item.kind == "always":
            pred = self._predicate(d["predicate"])
            return None if pred is None else {"predicate": pred}
        if item.kind == "eventually":
            pred = self._predicate(d["predicate"])
            within = self._seconds(d["within"], d["unit"], "`within`")
            return None if pred is None or within is None else {"predicate": pred, "within": within}
        if item.kind == "settles":
            target = self._free_expr(d["target"])
            by = self._seconds(d["by"], d["unit"], "`by`")
            if target is None or by is None:
                return None
            return {"signal": d["signal"].text, "target": target,
                    "tolerance": d["tolerance"].value, "by": by}
        return {"signal": d["signal"].text, "limit": d["limit"].value}

    # ------------------------------------------------------------------ the rule base
    def _rulebases(self) -> list[RuleBase]:
        blocks = self.blocks or [self.top]
        if self.blocks and self.top.rules:
            self.error(self.top.rules[0].loc, "a rule outside the blocks: when a file has "
                                              "`block`s, every rule belongs to one")
        written = {name for b in blocks for name in b.writes()}
        for v in self.vars.values():
            if not v.terms and not (not v.is_input and v.name in written):
                self.error(v.loc, f"`{v.name}` has no terms: add `terms {v.name} : ...`")
            if not v.is_input and v.lo is not None and not v.lo <= v.default <= v.hi:
                self.error(v.loc, f"the default {v.default:g} of `{v.name}` is outside its range "
                                  f"[{v.lo:g}, {v.hi:g}]")
        if not self.blocks:     # one rule base: every input and every output variable
            inputs = [v for v in self.vars.values() if v.is_input]
            outputs = [v for v in self.vars.values() if not v.is_input]
        made = {name: _variable(v) for name, v in self.vars.items() if v.lo is not None}
        rulebases, done = [], set()
        for b in blocks:
            if self.blocks:     # a block: the variables its rules read and write
                inputs = [v for n, v in self.vars.items() if n in b.reads()]
                outputs = [v for n, v in self.vars.items() if n in b.writes()]
                self._check_chain(b, inputs, outputs, done)
            for v in outputs:
                self._check_linear_terms(v, len(inputs), b.inference_of(v.name))
            if any(v.name not in made for v in inputs + outputs):
                continue        # reported where the variable was declared
            rb = assemble_rulebase([made[v.name] for v in inputs],
                                   [made[v.name] for v in outputs], merge_rules(b.rules),
                                   b.inference)
            rb.name = b.name
            rb.output_choices = {v.name: (b.inference_of(v.name).aggregation,
                                          b.inference_of(v.name).defuzzifier)
                                 for v in outputs if v.name in b.choices}
            rulebases.append(rb)
        return rulebases

    def _check_chain(self, b: _Block, inputs, outputs, done: set[str]) -> None:
        """A block reads signals and outputs of earlier blocks; it writes outputs no other
        block writes."""
        for v in inputs:
            if not v.is_input and v.name not in done:
                later = " (a later block computes it: order the blocks)" \
                    if any(v.name in o.writes() for o in self.blocks) else ""
                self.error(b.loc, f"block `{b.name}` reads `{v.name}` before any block "
                                  f"computes it{later}")
        for v in outputs:
            if v.name in done:
                self.error(b.loc, f"block `{b.name}` concludes on `{v.name}`, which an earlier "
                                  "block computes: an output belongs to one block")
            done.add(v.name)

    def _check_linear_terms(self, v: _LinguisticVar, n_inputs: int, inference: Inference) -> None:
        for name, kind, params, loc in v.terms:
            if kind != TermKind.LINEAR:
                continue
            if inference.defuzzifier not in LINEAR_DEFUZZIFIERS:
                self.error(loc, f"linear term `{name}` needs defuzzify = weighted_average or "
                                "weighted_sum")
            if any(params[n_inputs + 1:]):     # zeros are the (T, 4) padding
                self.error(loc, f"linear `{name}` has more coefficients than c0 and one per "
                                f"rule-base input ({n_inputs})")


BINARY_OPS = ("add", "sub", "mul", "div", "pow")


def fold_left(node: Expr, leaf, binary):
    """Evaluate an expression tree without recursing down left operands: a sum of 1000 terms is
    a left-deep chain 1000 deep. `leaf(n)` gives the value of a node that is no binary operator
    (and of every right operand), `binary(n, left_value, right_value)` that of a binary node."""
    spine = []
    while node.op in BINARY_OPS:
        spine.append(node)
        node = node.args[0]
    value = leaf(node)
    for parent in reversed(spine):
        value = binary(parent, value, leaf(parent.args[1]))
    return value


def assemble_rulebase(inputs: list[Variable], outputs: list[Variable], rules: list[RuleSpec],
                      inference: Inference) -> RuleBase:
    """The rule matrices of the IR from rules written by name (shared by every front end)."""
    in_index = {v.name: i for i, v in enumerate(inputs)}
    out_index = {v.name: i for i, v in enumerate(outputs)}
    n = len(rules)
    ante = np.full((n, len(inputs)), -1, dtype=np.int64)
    negated = np.zeros((n, len(inputs)), dtype=bool)
    hedges = np.zeros((n, len(inputs)), dtype=np.int64)
    cons = np.full((n, len(outputs)), -1, dtype=np.int64)
    conditions = {r: program_array(rule.program, in_index)
                  for r, rule in enumerate(rules) if rule.program is not None}
    for r, rule in enumerate(rules):
        for name, (term, neg, hedge) in rule.clauses.items():
            ante[r, in_index[name]] = term
            negated[r, in_index[name]] = neg
            hedges[r, in_index[name]] = int(hedge)
        for name, term in rule.conclusions.items():
            cons[r, out_index[name]] = term
    return RuleBase(
        inputs=inputs, outputs=outputs, antecedents=ante, consequents=cons,
        weights=np.array([r.weight for r in rules], dtype=float), negated=negated, hedges=hedges,
        connective=np.array([int(r.connective) for r in rules], dtype=np.int64),
        inference=inference, rule_locs=[r.loc for r in rules], origins=[r.origin for r in rules],
        conditions=conditions)


def merge_rules(rules: list[RuleSpec]) -> list[RuleSpec]:
    """Rules with the same premise and weight concluding on different outputs become one rule
    with several conclusions (the papers print one table per output for one set of premises).
    A premise that concludes twice on the same output stays two rules: that is a consistency
    question for the verifier, not something to hide here."""
    merged: list[RuleSpec] = []
    by_premise: dict = {}
    for rule in rules:
        key = (tuple(sorted(rule.clauses.items())), rule.connective, rule.program, rule.weight)
        target = by_premise.get(key)
        if target is not None and not set(target.conclusions) & set(rule.conclusions):
            target.conclusions.update(rule.conclusions)
            target.origin += "; " + rule.origin
            continue
        copy = RuleSpec(dict(rule.clauses), rule.connective, dict(rule.conclusions), rule.weight,
                        rule.loc, rule.origin, rule.program)
        merged.append(copy)
        by_premise.setdefault(key, copy)
    return merged


def _core(kind: TermKind, params) -> tuple[float, float]:
    """The interval where a term is fully true (or its centre): it must meet the range."""
    if kind in (TermKind.TRAPEZOID, TermKind.PISHAPE):
        return params[1], params[2]
    rising = {TermKind.SSHAPE: True, TermKind.ZSHAPE: False,
              TermKind.CONCAVE: params[0] < params[1]}.get(kind)
    if rising is not None:      # an edge: fully true from its end on (up to its end)
        edge = params[1] if kind != TermKind.ZSHAPE else params[0]
        return (edge, INF) if rising else (-INF, edge)
    if kind == TermKind.LINEAR:
        return -INF, INF
    return params[0], params[0]


def _variable(v: _LinguisticVar) -> Variable:
    kinds = np.array([int(t[1]) for t in v.terms], dtype=np.int64)
    # Linear rows longer than the (T, 4) params live in `coefficients`.
    long_rows = {t: np.array(term[2], dtype=float) for t, term in enumerate(v.terms)
                 if len(term[2]) > 4}
    params = np.array([term[2] if len(term[2]) <= 4 else (0, 0, 0, 0) for term in v.terms],
                      dtype=float).reshape(len(v.terms), 4)
    return Variable(
        coefficients=long_rows or None,
        name=v.name, lo=float(v.lo), hi=float(v.hi), names=[t[0] for t in v.terms], kinds=kinds,
        params=params, unit=units.format_unit(v.unit) if v.unit else None, default=v.default,
        learnable=None if v.is_input else np.array(v.learnable, dtype=bool), loc=v.loc,
        term_locs=[t[3] for t in v.terms])
