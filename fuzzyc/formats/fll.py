"""fuzzylite's FLL, as fuzzylite 6-8 write it: import and export.

FLL is line-oriented (`key: value`, sections opened by `Engine:`, `InputVariable:`,
`OutputVariable:`, `RuleBlock:`), so it is read line by line, every token keeping its column;
only the rule lines need a grammar, and they share the FCL one (`rule_text`).

Mapping (exact unless said):
  Triangle, Trapezoid, Rectangle, Ramp -> TRAPEZOID (Ramp = shoulder); Gaussian, Bell, Sigmoid;
  SShape, ZShape, PiShape, Spike, Cosine, Concave as themselves; Constant -> SINGLETON; Linear
  -> LINEAR (coefficients per input, then the optional constant).  Every t-norm and s-norm of
  fuzzylite as conjunction/disjunction (NormalizedSum = BoundedSum: pyfuzzylite 8 computes
  (a+b)/max(1, a+b); fuzzylite 6 C++ computes a + b/max(1, max(a, b)), i.e. a+b).  Implication
  Minimum/AlgebraicProduct; aggregation Maximum/UnboundedSum/AlgebraicSum/BoundedSum (MAX, SUM,
  PROBSUM, BOUNDED_SUM).  Hedges very, somewhat, seldom;
  fuzzylite's `extremely` (contrast intensification) -> SHARPLY; `x is any` -> the clause left
  out of an and-rule (the rule fires 1 if it is an or-rule; `not any` never fires).
  Centroid, Bisector, MeanOfMaximum -> exact integrals here; fuzzylite samples the range at
  `resolution` midpoints (see fuzzylite_compat).  WeightedAverage groups the activations of each
  term with the output's aggregation: `none`/UnboundedSum -> WEIGHTED_AVERAGE,
  Maximum/AlgebraicSum/BoundedSum -> CENTER_OF_AREA with that aggregation (fuzzylite's
  grouped_terms fold each term's degrees with the aggregation's s-norm).  WeightedSum with
  `none`/UnboundedSum -> WEIGHTED_SUM, with another aggregation -> GROUPED_SUM (the same
  grouping; fuzzylite 6 sums over the rules: tool_semantics); WeightedAverage over monotonic terms (Ramp, Sigmoid, SShape,
  ZShape, Concave) -> TSUKAMOTO.  Every fuzzylite t-norm as implication, every s-norm as
  aggregation (DrasticSum, EinsteinSum, HamacherSum, NilpotentMaximum integrate on the
  engine's grid).
Each output keeps its own aggregation and defuzzifier (RuleBase.output_choices where it differs
from the first output's).  Rule blocks whose operators agree make one rule base; blocks with
their own operators become rule blocks of the model, each concluding its own outputs (an output
concluded in two blocks whose operators differ is reported).
Function terms (a formula: fuzzyc.engine.formula) and lock-previous (fuzzyc.engine.held_outputs) as the model's
FUNCTION terms and Variable.lock_previous.  Anything else (term heights, activation methods
other than General, ...) is reported with its place.
"""
from __future__ import annotations

import math
import re

import numpy as np
from lark.exceptions import UnexpectedInput

from ..errors import Reporter, source_lines
from ..escape import one_line
from ..semantics.model import (Aggregation, Connective, Defuzzifier, Inference, Model,
                     SourceLoc, TermKind)
from ..engine.membership import linear_coefficients
from ..semantics import operators as ops
from ..semantics.shapes import SHAPES, TRAPEZOID_NEEDS, TRIANGLE_NEEDS
from ..language.numbers import not_a_number, parse_number
from .common import (PLAIN_SHAPES, Collected, TermSpec, VarSpec, degenerate, discrete_or_none,
                     nan_default, plain_needs, plain_shape_or_none, shape, trapezoid_or_none,
                     tsukamoto_terms)
from .blocks import (block_names, block_view, chain_warning, file_variables, linear_on,
                     one_output)
from .export import (all_singletons, compound_negations, finish, left_out, model_identifier, num,
                     peaks_instead, rule_sentence, unsayable_hedges, unsayable_names)
from .functions import function_term
from .rules import fcl_lark, rule_from_tree, syntax_error

# fuzzylite's operator words: the operator registry's (fuzzylite's `extremely` is SHARPLY;
# NormalizedSum is read as BoundedSum)
HEDGES = ops.format_words(ops.HEDGES, "fll")
TNORMS = ops.format_words(ops.T_NORMS, "fll")
SNORMS = ops.format_words(ops.S_NORMS, "fll")
# fuzzylite's names of the plain shapes (numbers in the model's order): the shape registry's
FLL_SHAPES = {SHAPES[kind].fll: kind for kind in PLAIN_SHAPES}
# what the other shapes' numbers must satisfy (fuzzylite's parameter names)
FLL_NEEDS = {"Triangle": f"a b c needs {TRIANGLE_NEEDS}",
             "Trapezoid": f"a b c d needs {TRAPEZOID_NEEDS}",
             "Rectangle": "start end needs start < end", "Ramp": "start end needs start != end",
             "Gaussian": "mean deviation needs deviation > 0",
             "Bell": "center width slope needs width > 0 and slope > 0",
             "Sigmoid": "inflection slope needs slope != 0",
             "Constant": "value needs a finite value"}
IMPLICATIONS = ops.format_words(ops.IMPLICATIONS, "fll")
AGGREGATIONS = ops.format_words(ops.AGGREGATIONS, "fll")
# WeightedAverage grouped by these is the center of area with that aggregation
GROUPING = {k: v for k, v in AGGREGATIONS.items() if v != Aggregation.SUM}
INTEGRAL = {rec.fll: d for d, rec in ops.DEFUZZIFIERS.items() if rec.family == "area"}
KNOWN_UNSUPPORTED_TERMS = ("Activated", "Aggregated")
SECTIONS = ("Engine", "InputVariable", "OutputVariable", "RuleBlock")
KEYS = {
    "Engine": {"description"},
    "InputVariable": {"description", "enabled", "range", "lock-range", "term"},
    "OutputVariable": {"description", "enabled", "range", "lock-range", "term", "aggregation",
                       "defuzzifier", "default", "lock-previous"},
    "RuleBlock": {"description", "enabled", "conjunction", "disjunction", "implication",
                  "activation", "rule"},
}
TOKEN = re.compile(r"\S+")


class _Line:
    """One `key: value` line; tokens of the value with their 1-based columns."""

    def __init__(self, number: int, text: str):
        self.number = number
        body = text.split("#", 1)[0]
        key, _, value = body.partition(":")
        self.key = key.strip()
        self.key_col = len(key) - len(key.lstrip()) + 1
        self.value_col = len(key) + 2
        self.value = value
        self.tokens = [(m.group(), self.value_col + m.start()) for m in TOKEN.finditer(value)]


class _FllReader:
    def __init__(self, text: str, path: str):
        self.rep = Reporter(path, text)
        self.got = Collected(self.rep, "imported")
        self.path = path
        self.section: str | None = None
        self.var: VarSpec | None = None
        # per RuleBlock its name and operators, per output its aggregation and defuzzifier:
        # kind -> (value, first line)
        self.blocks: list[tuple[str, dict[str, tuple[str, SourceLoc]]]] = []
        self.output_settings: dict[str, dict[str, tuple[str, SourceLoc]]] = {}
        self.rule_lines: list[tuple[int, _Line]] = []   # (block, line)
        self.rule_block: list[int] = []                 # the block of each rule read

    def loc(self, line: _Line, col: int) -> SourceLoc:
        return self.rep.loc(line.number, col)

    def read(self, text: str) -> Model:
        for number, raw in enumerate(source_lines(text), start=1):
            if raw.split("#", 1)[0].strip():
                self._line(_Line(number, raw))
        for block, line in self.rule_lines:   # after every variable, wherever the blocks stand
            self._parse_rule(block, line)
        self._inference()
        return self.got.model(self.path, text)

    def _line(self, line: _Line) -> None:
        first_value = line.tokens[0][0] if line.tokens else ""
        if line.key in SECTIONS:
            self.section = line.key
            self.var = None
            if line.key == "Engine" and first_value:
                self.got.name = re.sub(r"\W", "_", line.value.strip())
            elif line.key == "RuleBlock":
                self.blocks.append((first_value or f"block{len(self.blocks) + 1}", {}))
            elif line.key in ("InputVariable", "OutputVariable"):
                if not first_value:
                    self.rep.error(self.loc(line, line.value_col), "a variable needs a name")
                    return
                var = VarSpec(first_value, self.loc(line, line.tokens[0][1]))
                self.var = self.got.declare(var, line.key == "InputVariable")
            return
        if self.section is None:
            self.rep.error(self.loc(line, line.key_col),
                           f"`{line.key}` before any section: an FLL file must start "
                           "with `Engine:`")
            return
        if line.key not in KEYS[self.section]:
            self.rep.error(self.loc(line, line.key_col),
                           f"unknown key `{line.key}` in {self.section}: expected one of "
                           + ", ".join(sorted(KEYS[self.section])))
            return
        if self.section in ("InputVariable", "OutputVariable") and self.var is None:
            return  # its header was already reported
        getattr(self, "_" + line.key.replace("-", "_"))(line)

    # ------------------------------------------------------------------ variables
    def _description(self, line: _Line) -> None:
        if self.section == "Engine":
            self.got.title = line.value.strip()
        elif line.value.strip():
            self.got.notes.append(f"{self.section} description: {line.value.strip()}")

    def _enabled(self, line: _Line) -> None:
        if self._word(line) not in ("true", None):
            self.rep.error(self._first(line), f"a disabled {self.section} is not supported: "
                                              "remove it or enable it")

    def _range(self, line: _Line) -> None:
        values = self._numbers(line, 2, "range: LOW HIGH")
        if values is not None:
            self.var.lo, self.var.hi = values

    def _lock_range(self, line: _Line) -> None:
        if self._word(line) == "true":
            self.got.notes.append(f"`{self.var.name}` had lock-range: true; the model saturates "
                                  "outputs to their range but never clamps inputs")

    def _lock_previous(self, line: _Line) -> None:
        self.var.lock_previous = self._word(line) == "true"

    def _default(self, line: _Line) -> None:
        values = self._numbers(line, 1, "default: VALUE")
        if values is None:
            return
        value = values[0]
        self.var.default = nan_default(self.var, self.got.notes) if math.isnan(value) else value

    def _term(self, line: _Line) -> None:
        if len(line.tokens) < 2:
            self.rep.error(self._first(line), "a term reads `term: NAME Shape PARAMETERS...`")
            return
        (name, name_col), (kind, kind_col), *params = line.tokens
        if kind == "Function":
            start = kind_col - line.value_col + len(kind)
            term = function_term(name, line.value[start:].rstrip(), self.loc(line, name_col),
                                 self.loc(line, kind_col + len(kind)), self.rep)
            if term is not None:
                self.var.add(term, self.rep)
            return
        if kind in KNOWN_UNSUPPORTED_TERMS:     # said before its parameters
            fuzzylite_shape(kind, [], self.loc(line, kind_col), self.rep)
            return
        values = []
        for text, col in params:
            value = parse_number(text)
            if value is None:
                self.rep.error(self.loc(line, col), not_a_number(text))
                return
            values.append(value)
        made = fuzzylite_shape(kind, values, self.loc(line, kind_col), self.rep)
        if made is not None and name in self.var.term_names():
            # measured on pyfuzzylite's juggler.fll: the fuzzylite 6 CLI takes the first term of
            # a name, pyfuzzylite 8 the last; a rule base that means two things is refused
            self.rep.error(self.loc(line, name_col), f"term `{name}` is already defined for "
                                                     f"`{self.var.name}`: fuzzylite 6 would use "
                                                     "the first, pyfuzzylite 8 the last; rename "
                                                     "one")
        elif made is not None:
            term_kind, params, *coefficients = made
            self.var.add(TermSpec(name, term_kind, params, self.loc(line, name_col),
                                  *coefficients), self.rep)

    # ------------------------------------------------------------------ operators
    def _aggregation(self, line: _Line) -> None:
        self._setting("aggregation", line)

    def _defuzzifier(self, line: _Line) -> None:
        words = [t for t, _ in line.tokens]
        if not words:
            self.rep.error(self._first(line), "defuzzifier: NAME [resolution | type]")
            return
        if words[0] in INTEGRAL and len(words) > 1:
            self.got.notes.append(f"`{self.var.name}` {words[0]} resolution {words[1]}: the "
                                  "model integrates exactly (fuzzylite_compat reproduces the "
                                  "sampling)")
            words = words[:1]
        if words[0] in ("WeightedAverage", "WeightedSum") and len(words) > 1:
            # the type follows from the terms (Tsukamoto: monotonic ones), as fuzzylite's
            # Automatic: a stated type is taken as that
            allowed = ["TakagiSugeno", "Automatic", "Tsukamoto"]
            if words[1] not in allowed:
                self.rep.error(self.loc(line, line.tokens[1][1]),
                               f"{words[0]} {words[1]} is not supported: the model's weighted "
                               f"defuzzifiers are {', '.join(allowed)}")
                return
            words = words[:1]
        self._setting("defuzzifier", line, " ".join(words))

    def _conjunction(self, line: _Line) -> None:
        self._setting("conjunction", line)

    def _disjunction(self, line: _Line) -> None:
        self._setting("disjunction", line)

    def _implication(self, line: _Line) -> None:
        self._setting("implication", line)

    def _activation(self, line: _Line) -> None:
        if self._word(line) not in ("General", "none", None):
            self.rep.error(self._first(line), f"activation `{self._word(line)}` is not "
                                              "supported: every rule is evaluated (General)")

    def _setting(self, kind: str, line: _Line, value: str | None = None) -> None:
        """Remember an operator of the current rule block or output (the first one given)."""
        value = value if value is not None else (self._word(line) or "none")
        seen = self.blocks[-1][1] if self.section == "RuleBlock" else \
            self.output_settings.setdefault(self.var.name, {})
        seen.setdefault(kind, (value, self._first(line)))

    def _inference(self) -> None:
        """The rule blocks' operators and the outputs' defuzzifiers as the model's inference:
        one rule base when the blocks agree, else one per block (each concluding on its own
        outputs); an output whose choices differ from the first output's gets its own."""
        blocks = self.blocks or [("rules", {})]
        operators = [self._operators(settings, [r for r, b in zip(self.got.rules,
                                                                      self.rule_block) if b == k])
                     for k, (_, settings) in enumerate(blocks)]
        choices = {name: self._output_choice(var) for name, var in self.got.outputs.items()}
        self.got.set_inference([name for name, _ in blocks], operators, self.rule_block, choices)

    def _operators(self, settings: dict, rules: list) -> Inference:
        """A rule block's conjunction, disjunction and implication."""
        inf = Inference()
        for kind, table, field in (("conjunction", TNORMS, "and_"), ("disjunction", SNORMS, "or_"),
                                   ("implication", IMPLICATIONS, "implication")):
            if kind in settings and settings[kind][0] != "none":
                value, loc = settings[kind]
                if value not in table:
                    self.rep.error(loc, f"{kind} `{value}` is not supported; use one of "
                                        + ", ".join(table))
                else:
                    setattr(inf, field, table[value])
                    if value == "NormalizedSum":
                        self.got.notes.append("disjunction NormalizedSum taken as BoundedSum, "
                                              "min(1, a+b), as pyfuzzylite 8 computes it; "
                                              "fuzzylite 6 (C++) computes a+b")
            else:
                self._unset_operator_used(kind, rules)
        return inf

    def _output_choice(self, var) -> tuple[Aggregation, Defuzzifier]:
        """An output's aggregation and defuzzifier, reporting what the model lacks.  An output
        without these lines is reported at its header."""
        settings = self.output_settings.get(var.name, {})
        aggregation, agg_loc = settings.get("aggregation", ("none", var.loc))
        defuzz, loc = settings.get("defuzzifier", ("Centroid", var.loc))
        inf = Inference()
        if defuzz in INTEGRAL:
            inf.defuzzifier = INTEGRAL[defuzz]
            self._forbid_constants(var, defuzz)
            if aggregation not in AGGREGATIONS:
                self.rep.error(agg_loc, f"aggregation `{aggregation}` with {defuzz} is "
                                        "not supported: use " + ", ".join(AGGREGATIONS))
            else:
                inf.aggregation = AGGREGATIONS[aggregation]
        elif defuzz == "WeightedAverage" and aggregation in ("none", "UnboundedSum", *GROUPING):
            # Grouping by an s-norm is the center of area; by a sum, the per-rule weighted
            # average (whose result does not depend on the model's aggregation, left at its
            # default).
            inf.defuzzifier = (Defuzzifier.CENTER_OF_AREA if aggregation in GROUPING
                               else Defuzzifier.WEIGHTED_AVERAGE)
            inf.aggregation = GROUPING.get(aggregation, inf.aggregation)
            if tsukamoto_terms([var]):
                self._tsukamoto(inf, aggregation, Defuzzifier.TSUKAMOTO)
            else:
                self._require_constants(var, defuzz)
        elif defuzz == "WeightedSum" and aggregation in ("none", "UnboundedSum", *GROUPING):
            # grouped per term by an s-norm (pyfuzzylite 8; fuzzylite 6 sums over the rules,
            # tool_semantics), by a sum: the weighted sum over the rules
            inf.defuzzifier = (Defuzzifier.GROUPED_SUM if aggregation in GROUPING
                               else Defuzzifier.WEIGHTED_SUM)
            inf.aggregation = GROUPING.get(aggregation, inf.aggregation)
            if tsukamoto_terms([var]):
                self._tsukamoto(inf, aggregation, Defuzzifier.TSUKAMOTO_SUM)
            else:
                self._require_constants(var, defuzz)
        elif defuzz in ("WeightedAverage", "WeightedSum"):
            self.rep.error(agg_loc, f"{defuzz} with aggregation `{aggregation}` is not "
                                    "supported")
        else:
            self.rep.error(loc, f"defuzzifier `{defuzz}` is not supported; use one of "
                                + ", ".join([*INTEGRAL, "WeightedAverage", "WeightedSum"]))
        return inf.aggregation, inf.defuzzifier

    @staticmethod
    def _tsukamoto(inf: Inference, aggregation: str, method: Defuzzifier) -> None:
        """A weighted defuzzifier over monotonic terms (Ramp, Sigmoid, ...): Tsukamoto's,
        averaged or summed.  The model weighs every rule; the aggregation is kept (SUM for
        none/UnboundedSum) for pyfuzzylite 8, which groups the rules of a term with it before
        inverting (tool_semantics)."""
        inf.defuzzifier = method
        inf.aggregation = GROUPING.get(aggregation, Aggregation.SUM)

    def _unset_operator_used(self, kind: str, rules: list) -> None:
        """fuzzylite fails on a rule that needs an operator given as `none`: so do we."""
        connective = {"conjunction": Connective.AND, "disjunction": Connective.OR}.get(kind)
        for rule in rules:
            if connective in rule.connectives():
                self.rep.error(rule.loc, f"this rule needs a {kind}, but its rule block has "
                                         f"`{kind}: none`")
                return
        if kind != "implication":
            return
        # the outputs this block concludes (with one block: all of them)
        concluded = {name for rule in rules for name in rule.conclusions}
        for name, settings in self.output_settings.items():
            defuzz, loc = settings.get("defuzzifier", ("", None))
            if defuzz in INTEGRAL and (name in concluded or len(self.blocks) <= 1):
                self.rep.error(loc, f"{defuzz} needs an implication, but the rule block has "
                                    "`implication: none`")
                return

    def _forbid_constants(self, var, defuzz: str) -> None:
        for term in var.terms:
            if term.kind == TermKind.LINEAR:
                self.rep.error(term.loc, f"a Linear term needs WeightedAverage or "
                                         f"WeightedSum, not {defuzz}")
            elif term.kind == TermKind.SINGLETON:
                self.rep.error(term.loc, f"a Constant term under {defuzz} is a membership "
                                         "constant over the whole range in fuzzylite, a "
                                         "singleton in the model: use WeightedAverage")

    def _require_constants(self, var, defuzz: str, tsukamoto: str = "") -> None:
        """`tsukamoto`: the fuzzylite method over monotonic terms the model lacks for this
        defuzzifier (its Tsukamoto is a weighted average without grouping)."""
        for term in var.terms:
            if term.kind not in (TermKind.SINGLETON, TermKind.LINEAR, TermKind.FUNCTION):
                what = ("or monotonic ones (Tsukamoto); " f"`{term.name}` is neither"
                        if not tsukamoto else
                        f"(Takagi-Sugeno); over `{term.name}` it is fuzzylite's {tsukamoto}, "
                        "which the model does not have")
                self.rep.error(term.loc, f"{defuzz} needs Constant, Linear or Function terms "
                                         + what)

    # ------------------------------------------------------------------ rules
    def _rule(self, line: _Line) -> None:
        self.rule_lines.append((len(self.blocks) - 1, line))

    def _parse_rule(self, block: int, line: _Line) -> None:
        text = line.value
        start = len(text) - len(text.lstrip())
        offset = line.value_col + start
        loc = self.loc(line, offset)

        def loc_of(token) -> SourceLoc:
            return self.loc(line, offset + token.column - 1)

        try:
            tree = fcl_lark().parse(text.strip(), start="rule_text")
        except UnexpectedInput as exc:
            syntax_error(exc, self.rep, self.loc(line, offset + max(exc.column, 1) - 1))
            return
        for rule in rule_from_tree(tree, self.got, loc_of, HEDGES, f"{self.path}:{line.number}",
                                   loc):
            self.got.rules.append(rule)
            self.rule_block.append(block)

    # ------------------------------------------------------------------ helpers
    def _first(self, line: _Line) -> SourceLoc:
        return self.loc(line, line.tokens[0][1] if line.tokens else line.value_col)

    def _word(self, line: _Line) -> str | None:
        return line.tokens[0][0] if line.tokens else None

    def _numbers(self, line: _Line, count: int, usage: str) -> list[float] | None:
        values = [parse_number(t) for t, _ in line.tokens]
        for (text, col), value in zip(line.tokens, values):
            if value is None:
                self.rep.error(self.loc(line, col), f"{not_a_number(text)}: expected `{usage}`")
                return None
        if len(values) != count:
            self.rep.error(self._first(line), f"expected `{usage}`")
            return None
        return values

def fuzzylite_shape(kind: str, v: list[float], loc: SourceLoc, rep: Reporter):
    """A term written `Shape p1 p2 ...` as fuzzylite writes it (in FLL, and in its FCL) ->
    (TermKind, params[, linear coefficients]), or None after reporting why not."""
    if kind == "Linear":
        if not v or not all(map(math.isfinite, v)):
            rep.error(loc, "`Linear` takes finite coefficients, one per input and "
                           "optionally a constant")
            return None
        return TermKind.LINEAR, (0.0,) * 4, tuple(v)
    if kind == "Discrete":
        return discrete_or_none(v, loc, rep)
    arity = {"Triangle": 3, "Trapezoid": 4, "Rectangle": 2, "Ramp": 2, "Gaussian": 2,
             "Bell": 3, "Sigmoid": 2, "Constant": 1,
             **{name: PLAIN_SHAPES[k][0] for name, k in FLL_SHAPES.items()}}.get(kind)
    if arity is None:
        what = "is not supported" if kind in KNOWN_UNSUPPORTED_TERMS else "is unknown"
        rep.error(loc, f"term shape `{kind}` {what}: the model carries Triangle, "
                       "Trapezoid, Rectangle, Ramp, Gaussian, Bell, Sigmoid, "
                       + ", ".join(FLL_SHAPES) + ", Discrete, Constant, Linear")
        return None
    height_allowed = kind != "Constant"
    if len(v) not in (arity, arity + height_allowed) or len(v) == 0:
        rep.error(loc, f"`{kind}` takes {arity} parameters"
                       + (" and an optional height" if height_allowed else "")
                       + f", got {len(v)}")
        return None
    if len(v) > arity and v[arity] != 1.0:
        rep.error(loc, f"a term height of {v[arity]:g} is not supported: the model's "
                       "terms reach 1")
        return None
    v = v[:arity]
    if kind == "Binary" and math.isinf(v[1]):   # only the direction's side of start matters
        v = [v[0], v[0] + math.copysign(1.0, v[1])]
    made = {
        "Triangle": lambda: trapezoid_or_none(v[0], v[1], v[1], v[2]),
        "Trapezoid": lambda: trapezoid_or_none(*v),
        "Rectangle": lambda: trapezoid_or_none(v[0], v[0], v[1], v[1]),
        "Ramp": lambda: (trapezoid_or_none(v[0], v[1], math.inf, math.inf) if v[0] < v[1]
                         else trapezoid_or_none(-math.inf, -math.inf, v[1], v[0])
                         if v[0] > v[1] else None),
        "Gaussian": lambda: shape(TermKind.GAUSSIAN, *v) if v[1] > 0 else None,
        "Bell": lambda: shape(TermKind.BELL, *v) if v[1] > 0 and v[2] > 0 else None,
        "Sigmoid": lambda: shape(TermKind.SIGMOID, *v) if v[1] != 0 else None,
        "Constant": lambda: shape(TermKind.SINGLETON, *v) if math.isfinite(v[0]) else None,
        **{name: (lambda k=k: plain_shape_or_none(k, v)) for name, k in FLL_SHAPES.items()},
    }[kind]()
    if made is None:
        needs = FLL_NEEDS.get(kind) or (plain_needs(FLL_SHAPES[kind]) if kind in FLL_SHAPES
                                        else None)
        rep.error(loc, degenerate(kind, v, needs))
    return made


def read_fll(text: str, path: str = "<string>") -> Model:
    """An FLL engine as a Model; raises FuzzycError listing everything it cannot carry."""
    return _FllReader(text, path).read(text)


# ---------------------------------------------------------------------- export
FLL_HEDGES = {v: k for k, v in HEDGES.items()}
FLL_NAMES = {
    "and_": {v: k for k, v in TNORMS.items()},
    "or_": {v: k for k, v in ops.format_words(ops.S_NORMS, "fll", read=False).items()},
    "implication": {v: k for k, v in IMPLICATIONS.items()},
}
FLL_INTEGRAL = {v: k for k, v in INTEGRAL.items()}
# the written words only (NormalizedSum is read as BoundedSum, never written)
FLL_AGGREGATIONS = {v: k for k, v in ops.format_words(ops.AGGREGATIONS, "fll", read=False).items()}


def write_fll(model: Model, warnings: list[str] | None = None) -> str:
    """The model's rule blocks as FLL, one RuleBlock each, every output with its own
    aggregation and defuzzifier; what is left out is appended to `warnings`.
    Raises FuzzycError when a rule block itself cannot be written in FLL."""
    inputs, _ = file_variables(model)
    notes = left_out(model) + chain_warning(model, "FLL")
    problems = unsayable_names(model, "FLL")
    lines = [f"# {one_line(note)}" for note in model.notes]
    lines.append(f"Engine: {model_identifier(model)}")
    if model.title:
        lines.append(f"description: {one_line(model.title)}")
    for var in inputs:
        lines += _fll_variable("InputVariable", var, problems, is_input=True)
    rule_blocks = []
    for name, rb in zip(block_names(model), model.blocks):
        view = block_view(model, rb)
        problems += unsayable_hedges(view, FLL_HEDGES, "FLL") + compound_negations(view, "FLL")
        for o in range(len(rb.outputs)):
            (var,), aggregation, defuzzifier = _fll_defuzzifier(
                block_view(model, one_output(rb, o)), problems, notes)
            lines += _fll_variable("OutputVariable", linear_on(var, rb.inputs, inputs, problems),
                                   problems, is_input=False, n_inputs=len(inputs),
                                   extra=[f"aggregation: {aggregation}",
                                          f"defuzzifier: {defuzzifier}",
                                          f"default: {num(var.default)}",
                                          f"lock-previous: {str(var.lock_previous).lower()}"])
        inf = rb.inference
        rule_blocks += [f"RuleBlock: {name}", "  enabled: true"]
        rule_blocks += [f"  {key}: {FLL_NAMES[field][getattr(inf, field)]}"
                        for key, field in (("conjunction", "and_"), ("disjunction", "or_"),
                                           ("implication", "implication"))]
        rule_blocks.append("  activation: General")
        rule_blocks += ["  rule: " + rule_sentence(view, r, FLL_HEDGES, " and ", problems,
                                                      says_any=True)
                        for r in range(rb.n_rules)]
    return finish(model, "FLL", lines + rule_blocks, problems, notes, warnings)


def _fll_defuzzifier(model: Model, problems: list[str], notes: list[str]):
    """(output variables to write, aggregation, defuzzifier) in fuzzylite's words."""
    rb = model.rulebase
    inf = rb.inference
    method = inf.defuzzifier
    aggregation = FLL_AGGREGATIONS[inf.aggregation]
    singletons = all(all_singletons(v) for v in rb.outputs)
    if method in FLL_INTEGRAL and not (method == Defuzzifier.CENTROID and singletons):
        if any(np.any(v.kinds == TermKind.SINGLETON) for v in rb.outputs):
            problems.append(f"{method.name.lower()} over singleton terms has no FLL equivalent")
        notes.append(f"fuzzylite computes {FLL_INTEGRAL[method]} by sampling the range "
                     "(pyfuzzylite 8: 1000 midpoints, fuzzylite 6 C++: 100); fuzzyc integrates "
                     "exactly (see fuzzylite_compat.evaluate_sampled)")
        return rb.outputs, aggregation, FLL_INTEGRAL[method]
    if method in (Defuzzifier.TSUKAMOTO, Defuzzifier.TSUKAMOTO_SUM):
        notes.append("Tsukamoto: fuzzylite 6 and pyfuzzylite 8 invert some terms differently "
                     "(see tool_semantics)")
        grouped = aggregation if inf.aggregation not in (Aggregation.SUM, Aggregation.MAX) \
            else "none"
        word = "WeightedAverage" if method == Defuzzifier.TSUKAMOTO else "WeightedSum"
        return rb.outputs, grouped, f"{word} Tsukamoto"
    outputs, changed = peaks_instead(model, "FLL")
    notes.extend(changed)
    if method == Defuzzifier.WEIGHTED_SUM:
        return outputs, "none", "WeightedSum TakagiSugeno"
    if method == Defuzzifier.GROUPED_SUM:
        return outputs, aggregation, "WeightedSum TakagiSugeno"
    grouped = aggregation if (method != Defuzzifier.WEIGHTED_AVERAGE
                              and inf.aggregation != Aggregation.SUM) else "none"
    return outputs, grouped, "WeightedAverage TakagiSugeno"


def _fll_variable(section: str, var, problems: list[str], is_input: bool,
                  extra: list[str] = (), n_inputs: int = 0) -> list[str]:
    lines = [f"{section}: {var.name}", "  enabled: true",
             f"  range: {num(var.lo)} {num(var.hi)}", "  lock-range: false",
             *("  " + e for e in extra)]
    linear = linear_coefficients(var, n_inputs) if not is_input else None
    for t, (name, kind, p) in enumerate(zip(var.names, var.kinds, var.params)):
        if kind == TermKind.LINEAR:
            row = linear[t]   # fuzzylite writes the constant last
            lines.append(f"  term: {name} Linear " + " ".join(num(c) for c in (*row[1:], row[0])))
            continue
        if kind == TermKind.DISCRETE:
            lines.append(f"  term: {name} Discrete " + " ".join(map(num, var.term_numbers(t))))
            continue
        if kind == TermKind.FUNCTION:
            lines.append(f"  term: {name} Function {var.formulas[t].infix()}")
            continue
        term = fll_term(TermKind(int(kind)), p, is_input)
        if term is None:
            problems.append(f"term `{name}` of `{var.name}` ({TermKind(int(kind)).name.lower()} "
                            f"{', '.join(num(x) for x in p)}) has no FLL shape")
        else:
            lines.append(f"  term: {name} {term}")
    return lines


def fll_term(kind: TermKind, p, is_input: bool) -> str | None:
    a, b, c, d = (float(x) for x in p)
    if kind == TermKind.TRAPEZOID:
        if a == b == -math.inf and math.isfinite(c) and c < d < math.inf:
            return f"Ramp {num(d)} {num(c)}"
        if c == d == math.inf and -math.inf < a < b and math.isfinite(b):
            return f"Ramp {num(a)} {num(b)}"
        if a == b and c == d and a < d:
            return f"Rectangle {num(a)} {num(d)}"
        if b == c:
            return f"Triangle {num(a)} {num(b)} {num(d)}"
        return f"Trapezoid {num(a)} {num(b)} {num(c)} {num(d)}"
    if kind == TermKind.SINGLETON:
        return None if is_input else f"Constant {num(a)}"
    record = SHAPES[kind]           # its FLL name, and as many numbers as its .fz word
    if record.fll is None or not record.words or record.words[0].arity is None:
        return None                 # not a row of numbers (linear, points, formulas)
    return " ".join([record.fll, *(num(x) for x in (a, b, c, d)[:record.words[0].arity])])
