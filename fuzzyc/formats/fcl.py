"""IEC 61131-7 FCL function blocks: import (lark grammar `fuzzyc/language/grammar/fcl.lark`) and export.

FCL is block-structured and free-form (statements end with `;`, comments `(* *)`), so it gets a
real grammar.  Mapping (exact unless said):
  point-list terms that form a triangle, trapezoid or shoulder -> TRAPEZOID (IEC: a term keeps
  its first/last point's value beyond them, so (0,1) (4,0) is a left shoulder); a number ->
  SINGLETON; jFuzzyLogic's TRIAN, TRAPE, GAUSS, GBELL, SIGM -> TRAPEZOID, GAUSSIAN, BELL, SIGMOID.
  AND MIN/PROD/BDIF, OR MAX/ASUM/BSUM, ACT MIN/PROD, ACCU MAX and BSUM (IEC's bounded sum,
  min(1, a+b)), and jFuzzyLogic's SUM (unbounded) and PROBOR (a+b-ab, IEC's ASUM, which IEC has
  for OR only).
  METHOD COG -> CENTROID, COGS -> CENTER_OF_AREA (the centre of gravity of singletons, which the
  model computes over the terms' peaks), COA -> BISECTOR (IEC's "centre of area" halves the
  area), MM -> MEAN_OF_MAXIMUM, LM / RM -> SMALLEST_ / LARGEST_OF_MAXIMUM.
fuzzylite's FCL: terms written as in FLL (`TERM low := Triangle 0 0.25 0.5;`, see
  fll.fuzzylite_shape), `DEFAULT := nan` (as FLL's `default: nan`), the norms EPROD, DPROD,
  HPROD, NMIN, ESUM, DSUM, HSUM, NMAX, NSUM, as ACT and ACCU too; METHOD COGS without ACCU is
  fuzzylite's WeightedAverage over the rules (WEIGHTED_AVERAGE; Linear terms allowed; over
  monotonic terms TSUKAMOTO), with an ACCU the centre of the singletons grouped by that
  accumulation (CENTER_OF_AREA).
  Hedges in rules: fuzzylite's (very, somewhat, seldom, extremely; see fll.HEDGES).
fuzzylite's `TERM f := Function FORMULA;` and `DEFAULT := nan | NC` (lock-previous) as in FLL.
Not carried, reported: other point lists,
  COGS over terms other than singletons, Linear and Function ones (fuzzylite's Tsukamoto).
fuzzylite's dialect also: METHOD COGSS (WeightedSum), `LOCK : PREVIOUS, RANGE` in DEFUZZIFY
  (lock-previous; the range clip under fuzzylite's semantics), `inf` / `-inf` as numbers.
Several RULEBLOCKs are merged when their operators agree.  Of several FUNCTION_BLOCKs one is
read, chosen by name (`FILE.fcl::NAME` wherever a rule file is named; see `read_fcl`);
`check_fcl` checks every block, and a block without outputs (a membership demo).
jFuzzyLogic's dialect (docs/formats.md, "jFuzzyLogic's FCL"): a block using a construct only
it has takes its defaults (ACCU SUM, AND/OR as a pair, no DEFAULT as nan); variables without
RANGE take its estimated universe; COSINE, FUNCTION terms (Takagi-Sugeno values, COGF), a
degenerate TRIAN as a singleton, GAUSS2, DSIGM where s1 >= s2; parameters naming variables,
other DSIGMs and SINGLETONS refused where they stand.
"""
from __future__ import annotations

import math
from dataclasses import replace

from lark import Token, Tree
from lark.exceptions import UnexpectedInput

from ..errors import Reporter
from ..escape import one_line
from ..semantics.model import (Aggregation, Connective, Defuzzifier, Inference, Model,
                     SourceLoc, TermKind)
from .common import (Collected, TermSpec, VarSpec, degenerate, discrete_or_none, nan_default,
                     shape, trapezoid_or_none, tsukamoto_terms)
from .blocks import block_names, block_view, chain_warning, file_variables, one_output
from ..semantics.shapes import TRAPEZOID_NEEDS, TRIANGLE_NEEDS
from .export import (all_singletons, finish, left_out, model_identifier, num, peaks_instead,
                     rule_sentence, unsayable_hedges, unsayable_names)
from .fll import HEDGES, fll_term, fuzzylite_shape
from ..semantics import operators as ops
from .functions import function_term
from .rules import fcl_lark, rule_from_tree, syntax_error

# The operator words: the operator registry's (IEC's, fuzzylite's where IEC has none)
OPERATORS = {
    "and_op": ("AND", "and_", ops.format_words(ops.T_NORMS, "fcl", read=False)),
    "or_op": ("OR", "or_", ops.format_words(ops.S_NORMS, "fcl", read=False)),
    "accu": ("ACCU", "aggregation", ops.format_words(ops.AGGREGATIONS, "fcl", read=False)),
    # ACT takes the AND words (fuzzylite writes EPROD, ...): implications are t-norms
    "act": ("ACT", "implication", ops.format_words(ops.IMPLICATIONS, "fcl", read=False)),
}
# fuzzylite's other words for what the model has (read only; export writes the IEC words)
ALIASES = {key: {word.upper(): rec.fcl for rec in table.values()
                  for word in rec.also_in("fcl")}
           for key, table in (("OR", ops.S_NORMS), ("ACCU", ops.AGGREGATIONS))}
METHODS = ops.format_words(ops.DEFUZZIFIERS, "fcl", read=False)
# what each jFuzzyLogic shape's numbers must satisfy, in its own parameter order
FCL_NEEDS = {"TRIAN": f"a b c needs {TRIANGLE_NEEDS} (or a = b = c: a singleton)",
             "TRAPE": f"a b c d needs {TRAPEZOID_NEEDS} (or all equal: a singleton)",
             "GAUSS": "mean deviation needs deviation > 0",
             "GBELL": "a b mean needs a > 0 and b > 0", "SIGM": "gain centre needs gain != 0",
             "COSINE": "net_max offset needs net_max > 0",
             "GAUSS2": "meanl sdl meanr sdr needs sdl > 0, sdr > 0 and meanl <= meanr"}


class _FclReader:
    def __init__(self, text: str, path: str):
        self.rep = Reporter(path, text)
        self.got = Collected(self.rep, "imported")
        self.path = path
        self.declared: dict[str, bool] = {}       # VAR_INPUT / VAR_OUTPUT name -> is input
        # per RULEBLOCK its name and AND/OR/ACT/ACCU, per output its METHOD/ACCU:
        # key -> (word, first place)
        self.block_settings: list[tuple[str, dict[str, tuple[str, SourceLoc]]]] = []
        self.output_settings: dict[str, dict[str, tuple[str, SourceLoc]]] = {}
        self.rule_block: list[int] = []           # the block of each rule read
        # jFuzzyLogic: each variable's universe as jFuzzyLogic estimates it from each term
        # (None where a term gives none), for a variable declared without RANGE
        self.universe: dict[str, list[tuple[float, float] | None]] = {}
        # jFuzzyLogic's FUNCTION terms (Sugeno values) per output: their places
        self.jfl_functions: dict[str, list[SourceLoc]] = {}
        # the first construct only jFuzzyLogic's dialect has (its word and place): the block
        # then takes jFuzzyLogic's defaults (ACCU SUM; AND and OR set as a pair)
        self.jfl: tuple[str, SourceLoc] | None = None
        self.defaults: set[str] = set()           # the outputs with a DEFAULT

    def _jfl_seen(self, word: str, loc: SourceLoc) -> None:
        self.jfl = self.jfl or (word, loc)

    def loc(self, token: Token) -> SourceLoc:
        return self.rep.loc(token.line, token.column)

    def read(self, text: str, wanted: str | None = None) -> Model:
        try:
            tree = fcl_lark().parse(text, start="start")
        except UnexpectedInput as exc:
            syntax_error(exc, self.rep, self.rep.loc(exc.line, exc.column))
            self.rep.raise_if_any()
        block = self._select(tree.children, wanted)
        self.rep.raise_if_any()
        name = _block_name(block)
        if name is not None:
            self.got.name = name.value
        items = [c for c in block.children if isinstance(c, Tree)]
        for kind in ("var_input", "var_output", "fuzzify", "defuzzify", "ruleblock"):
            for item in items:
                if item.data == kind:
                    getattr(self, "_" + kind)(item)
        self._inference()
        self._universes()
        for name, var in self.got.outputs.items() if self.jfl is not None else ():
            if name not in self.defaults:
                # jFuzzyLogic: no DEFAULT is NaN where no rule fires (fuzzylite's `nan`)
                var.default = nan_default(var, self.got.notes)
        # The model remembers which block it is, in the syntax that loads it again.
        return self.got.model(self.path if wanted is None else f"{self.path}::{wanted}", text)

    def memberships(self, text: str, wanted: str | None) -> list[VarSpec]:
        """The chosen block read as `read` does, for a block that declares inputs and no output
        (a membership demo, as jFuzzyLogic's examples have): its declarations and terms
        checked, the inputs returned; nothing to evaluate."""
        tree = fcl_lark().parse(text, start="start")
        block = self._select(tree.children, wanted)
        self.rep.raise_if_any()
        items = [c for c in block.children if isinstance(c, Tree)]
        for kind in ("var_input", "var_output", "fuzzify", "defuzzify", "ruleblock"):
            for item in items:
                if item.data == kind:
                    getattr(self, "_" + kind)(item)
        self._universes()
        self.got.check_ranges()
        if not self.got.inputs:
            self.rep.error(self.rep.loc(1, 1), "the block declares no input variable")
        self.rep.raise_if_any()
        return list(self.got.inputs.values())

    def _where(self, tree: Tree) -> SourceLoc:
        return self.rep.loc(tree.meta.line, tree.meta.column)

    # ------------------------------------------------------------------ function blocks
    def _select(self, blocks: list[Tree], wanted: str | None) -> Tree | None:
        """The block named `wanted`, or the only one; errors name every block and its place."""
        named = self._block_table(blocks)
        if wanted is None:
            if len(blocks) > 1:
                self.rep.error(self._where(blocks[1]), f"{len(blocks)} FUNCTION_BLOCKs in this "
                               f"file and none chosen: name one as `{self.path}::NAME`; "
                               + _listing(named))
            return blocks[0]
        if wanted not in named:
            self.rep.error(None, f"no FUNCTION_BLOCK `{wanted}` in {self.path}: "
                                 + _listing(named))
            return None
        return next(b for b in blocks if _block_name(b) == wanted)

    def _block_table(self, blocks: list[Tree]) -> dict[str, SourceLoc]:
        """Block name -> place; a repeated name, or a nameless block among several, is an
        error (either would make `FILE.fcl::NAME` ambiguous), whichever block is chosen."""
        named: dict[str, SourceLoc] = {}
        for block in blocks:
            token = _block_name(block)
            if token is None:
                if len(blocks) > 1:
                    self.rep.error(self._where(block), "this FUNCTION_BLOCK has no name: in a "
                                   "file with several, each needs one to be chosen as "
                                   "`FILE.fcl::NAME`")
            elif token.value in named:
                self.rep.error(self.loc(token), f"FUNCTION_BLOCK `{token}` again (first at "
                               f"{named[token.value]}): block names must differ")
            else:
                named[token.value] = self.loc(token)
        return named

    # ------------------------------------------------------------------ declarations
    def _var_input(self, tree: Tree) -> None:
        self._declare(tree, is_input=True)

    def _var_output(self, tree: Tree) -> None:
        self._declare(tree, is_input=False)

    def _declare(self, tree: Tree, is_input: bool) -> None:
        for decl in tree.children:
            name, type_, *rng = decl.children
            if type_.value.upper() != "REAL":
                self.rep.error(self.loc(type_), f"`{name}` is {type_}: fuzzy variables are "
                                                  "REAL; declare it REAL")
            var = self.got.declare(VarSpec(name.value, self.loc(name)), is_input)
            self.declared[name.value] = is_input
            for item in rng:
                if item.data == "jfl_range":
                    self._jfl_seen("RANGE after the declaration", self._where(item))
                    item = item.children[0]
                var.lo, var.hi = self._interval(item.children[0])

    def _variable(self, name: Token, is_input: bool) -> VarSpec | None:
        table = self.got.inputs if is_input else self.got.outputs
        if name.value not in table:
            section = "VAR_INPUT" if is_input else "VAR_OUTPUT"
            self.rep.error(self.loc(name), f"`{name}` is not declared in {section}; declare it "
                                           "there")
            return None
        return table[name.value]

    def _fuzzify(self, tree: Tree) -> None:
        self._terms(tree, is_input=True)

    def _defuzzify(self, tree: Tree) -> None:
        var = self._terms(tree, is_input=False)
        if var is None:
            return
        for item in tree.children[1:]:
            if item.data == "method":
                if item.children[0].value.upper() == "COGF":
                    self._jfl_seen("COGF", self.loc(item.children[0]))
                self._choose(self.output_settings.setdefault(var.name, {}), "METHOD",
                             item.children[0])
            elif item.data == "default":
                self.defaults.add(var.name)
                value = item.children[0]
                # NC, or `nan | NC`: keep the last output (fuzzylite's lock-previous)
                var.lock_previous = isinstance(item.children[-1], Token) and \
                    item.children[-1].type == "NC"
                if isinstance(value, Token):
                    var.default = nan_default(var, self.got.notes)
                else:
                    var.default = float(value.children[0])
            elif item.data == "accu":
                self._choose(self.output_settings.setdefault(var.name, {}), "ACCU",
                             item.children[0])
            elif item.data == "lock":
                self._lock(var, item.children)

    def _lock(self, var: VarSpec, words: list[Token]) -> None:
        """fuzzylite's `LOCK : PREVIOUS, RANGE`: PREVIOUS keeps the last output where no rule
        fires (lock-previous); RANGE clips the output to its range, which fuzzylite's
        semantics read from the file (tool_semantics.FileSettings)."""
        for word in words:
            if word.value.upper() == "PREVIOUS":
                var.lock_previous = True
            elif word.value.upper() != "RANGE":
                self.rep.error(self.loc(word), f"LOCK {word.value}: fuzzylite locks PREVIOUS "
                                               "and RANGE")

    def _terms(self, tree: Tree, is_input: bool) -> VarSpec | None:
        name, *items = tree.children
        var = self._variable(name, is_input)
        if var is None:
            return None
        for item in items:
            if item.data == "term":
                term_name, body = item.children
                if body.data == "formula":
                    self._formula(var, term_name, body.children[0])
                    continue
                if body.data == "jfl_formula":
                    self._jfl_formula(var, is_input, term_name, body.children[0])
                    continue
                if body.data == "named_shape" and len(body.children) == 1 and \
                        body.children[0].value in self.declared:
                    self._variable_singleton(var, is_input, term_name, body.children[0])
                    continue
                self._term_universe = None
                made = self._shape(body)
                self.universe.setdefault(var.name, []).append(self._term_universe)
                if made is not None:
                    kind, params, *coefficients = made
                    var.add(TermSpec(term_name.value, kind, params, self.loc(term_name),
                                     *coefficients), self.rep)
            elif item.data == "range_item":
                var.lo, var.hi = self._interval(item.children[0])
        return var

    def _formula(self, var: VarSpec, name: Token, token: Token) -> None:
        """`TERM name := Function FORMULA;` (fuzzylite's FCL)."""
        text = token.value[len("Function"):]
        start = replace(self.loc(token), col=self.loc(token).col + len("Function"))
        term = function_term(name.value, text.rstrip(), self.loc(name), start, self.rep)
        if term is not None:
            var.add(term, self.rep)

    def _interval(self, tree: Tree) -> tuple[float, float]:
        return tuple(float(n.children[0]) for n in tree.children)

    def _numbers(self, atoms: list, what: str) -> list[float] | None:
        """The parameters as numbers; one that names a variable (jFuzzyLogic's Value of type
        VAR_REFERENCE: the term moves with that variable's value at every evaluation) is
        refused where it stands: a term of the model has a fixed shape."""
        values = []
        for atom in atoms:
            if atom.data == "var_ref":
                token = atom.children[0]
                if token.value not in self.declared:        # `1_0`: a number's slip
                    self.rep.error(self.loc(token), f"unexpected `{token}`: expected a number "
                                   "(or, in jFuzzyLogic's dialect, a declared variable)")
                    return None
                self.rep.error(self.loc(token), f"{what} parameter `{token}` names a variable: "
                               "jFuzzyLogic moves the term with that variable's value at every "
                               "evaluation; a fuzzyc term has a fixed shape, so this has no "
                               "meaning here (write the number)")
                return None
            values.append(float(atom.children[0]))
        return values

    def _shape(self, body: Tree):
        loc = self._where(body)
        if body.data == "singleton":
            value = float(body.children[0].children[0])
            self._term_universe = (value, value)
            return shape(TermKind.SINGLETON, value)
        if body.data == "named_shape":
            word, *numbers = body.children
            return fuzzylite_shape(word.value, [float(n.children[0]) for n in numbers], loc,
                                   self.rep)
        if body.data == "singletons":
            self.rep.error(loc, "SINGLETONS (jFuzzyLogic's generic singleton, several points "
                                "in one term) is not read: a fuzzyc term is one singleton; "
                                "write one TERM per point")
            return None
        if body.data == "function":
            word, *atoms = body.children
            self._jfl_seen(word.value.upper(), self.loc(word))
            v = self._numbers(atoms, word.value.upper())
            return None if v is None else self._function(word.value.upper(), v, loc)
        points = []
        for p in body.children:
            xy = self._numbers(p.children, "point")
            if xy is None:
                return None
            points.append(tuple(xy))
        if points:      # jFuzzyLogic's universe of a point list: its first and last x
            self._term_universe = (points[0][0], points[-1][0])
        if len(points) > 1 and len({x for x, _ in points}) == 1 and \
                [y for _, y in points] in ([0.0, 1.0, 0.0], [0.0, 1.0], [1.0, 0.0]):
            return shape(TermKind.SINGLETON, points[0][0])      # a spike of width 0
        # a triangle, trapezoid or shoulder stays one (the engine integrates those exactly)
        return _points_to_trapezoid(points) or discrete_or_none(
            [v for point in points for v in point], loc, self.rep)

    def _function(self, word: str, v: list[float], loc: SourceLoc):
        arity = {"TRIAN": 3, "TRAPE": 4, "GAUSS": 2, "GBELL": 3, "SIGM": 2, "COSINE": 2,
                 "DSIGM": 4, "GAUSS2": 4}[word]
        if len(v) != arity:
            self.rep.error(loc, f"{word} takes {arity} numbers, got {len(v)}")
            return None
        if word == "DSIGM" and not (v[0] == v[2] != 0 and (v[0] > 0) == (v[1] <= v[3])):
            # s1 >= s2 everywhere only for equal gains with the first sigmoid ahead
            self.rep.error(loc, "DSIGM is read where s1 >= s2 everywhere (equal gains, the "
                                "first centre first for a positive gain): jFuzzyLogic's "
                                "difference of sigmoids is max(0, s1 - s2), fuzzyc's "
                                "|s1 - s2|, another shape where s2 > s1")
            return None
        # jFuzzyLogic's universe of each shape (MembershipFunction*.estimateUniverse)
        self._term_universe = {
            "TRIAN": lambda: (v[0], v[2]), "TRAPE": lambda: (v[0], v[3]),
            "GAUSS": lambda: (v[0] - 4 * v[1], v[0] + 4 * v[1]),
            "GBELL": lambda: _bell_universe(*v),
            "SIGM": lambda: (v[1] - 9 / abs(v[0]), v[1] + 9 / abs(v[0])) if v[0] != 0 else None,
            "COSINE": lambda: (v[1] - v[0], v[1] + v[0]),
            "GAUSS2": lambda: (v[0] - 4 * v[1], v[2] + 4 * v[3]),
            # DifferenceSigmoidal.estimateUniverse: the wider of the two sigmoids' spans
            "DSIGM": lambda: (min(v[1] - 9 / abs(v[0]), v[3] - 9 / abs(v[2])),
                              max(v[1] + 9 / abs(v[0]), v[3] + 9 / abs(v[2])))}[word]()
        if word == "TRIAN" and v[0] == v[1] == v[2] or word == "TRAPE" and len(set(v)) == 1:
            # jFuzzyLogic: 1 at the peak itself (`in == mid`), 0 elsewhere: a singleton
            return shape(TermKind.SINGLETON, v[0])
        made = {"TRIAN": lambda: trapezoid_or_none(v[0], v[1], v[1], v[2]),
                "TRAPE": lambda: trapezoid_or_none(*v),
                "GAUSS": lambda: shape(TermKind.GAUSSIAN, *v) if v[1] > 0 else None,
                # jFuzzyLogic: GBELL a b mean (width, slope, centre); SIGM gain centre
                "GBELL": lambda: shape(TermKind.BELL, v[2], v[0], v[1]) if v[0] > 0 and v[1] > 0
                else None,
                "SIGM": lambda: shape(TermKind.SIGMOID, v[1], v[0]) if v[0] != 0 else None,
                # jFuzzyLogic: COSINE net_max offset, (1 + cos(pi (x - offset) / net_max)) / 2
                # on offset -+ net_max: the cosine of centre offset, width 2 net_max
                "COSINE": lambda: shape(TermKind.COSINE, v[1], 2 * v[0]) if v[0] > 0 else None,
                # jFuzzyLogic: GAUSS2 meanl sdl meanr sdr, a Gaussian left of meanl, 1 between,
                # a Gaussian right of meanr (meanl <= meanr): the Gaussian product's shape
                "GAUSS2": lambda: shape(TermKind.GAUSSIAN_PRODUCT, *v)
                if v[1] > 0 and v[3] > 0 and v[0] <= v[2] else None,
                # DSIGM a1 c1 a2 c2 (s1 >= s2 here): the sigmoid difference (c1, a1, a2, c2)
                "DSIGM": lambda: shape(TermKind.SIGMOID_DIFFERENCE, v[1], v[0], v[2], v[3]),
                }[word]()
        if made is None:
            self.rep.error(loc, degenerate(word, v, FCL_NEEDS.get(word)))
        return made

    def _variable_singleton(self, var: VarSpec, is_input: bool, name: Token,
                            ref: Token) -> None:
        """jFuzzyLogic's `TERM t := x;`: a singleton at variable x's value.  On an output
        that is a Takagi-Sugeno value (the function term `x`, read by COGS/COGF); on an
        input a membership that moves with another variable, which the model has not."""
        if is_input:
            self.rep.error(self.loc(ref), f"term `{name}` is a singleton at variable `{ref}`'s "
                           "value: jFuzzyLogic moves it with that value; an input's terms have "
                           "fixed shapes in fuzzyc, so this has no meaning here")
            return
        self._jfl_formula(var, is_input, name, ref, text=f"FUNCTION {ref.value}",
                          offset=-len("FUNCTION "))

    def _jfl_formula(self, var: VarSpec, is_input: bool, name: Token, token: Token,
                     text: str | None = None, offset: int = 0) -> None:
        """jFuzzyLogic's `TERM t := FUNCTION expr;`: a singleton at the value of expr, an
        arithmetic of numbers and input variables (+ - * / ^ %, exp ln sin cos tan abs); a
        Takagi-Sugeno consequent (METHOD COGS or COGF).  Read as a fuzzyc Function term over
        the inputs, its text rewritten with jFuzzyLogic's precedence made explicit."""
        text = token.value if text is None else text
        loc = self.loc(token)
        self._jfl_seen("FUNCTION" if text.upper().startswith("FUNCTION ") and
                       token.value.upper().startswith("FUNCTION") else "a term naming a variable",
                       loc)
        if is_input:
            self.rep.error(loc, f"term `{name}` is a FUNCTION: in jFuzzyLogic a singleton at a "
                                "computed place, a Takagi-Sugeno consequent; an input has no "
                                "such term")
            return
        body = text[len("FUNCTION"):]
        try:
            formula = _JflExpression(body, set(self.got.inputs), set(self.got.outputs)).parse()
        except _JflError as exc:
            at = _offset_loc(loc, text, len("FUNCTION") + exc.offset + offset)
            self.rep.error(at, f"FUNCTION of term `{name}`: {exc}")
            return
        term = function_term(name.value, formula, self.loc(name), loc, self.rep)
        if term is not None:
            var.add(term, self.rep)
            self.jfl_functions.setdefault(var.name, []).append(self.loc(name))
        self.universe.setdefault(var.name, []).append(None)

    def _universes(self) -> None:
        """A variable declared without RANGE takes the universe jFuzzyLogic estimates
        (Variable.estimateUniverse): the smallest and largest of its terms' own universes
        (TRIAN a..c, TRAPE a..d, a point list its first..last x, a singleton its place,
        GAUSS mean -+ 4 stdev, GBELL mean -+ 999^(1/2b) a, SIGM t0 -+ 9/|gain|, COSINE
        offset -+ net_max).  Where a term gives none (fuzzylite's shapes, functions), the
        terms' break points as before (Collected.check_ranges)."""
        for name, var in (*self.got.inputs.items(), *self.got.outputs.items()):
            spans = self.universe.get(name, [])
            if var.lo is None and name in self.jfl_functions:
                self.rep.error(var.loc, f"`{name}` has no RANGE and FUNCTION terms: jFuzzyLogic "
                                        "estimates no universe for them and does not clip a "
                                        "COGF output; a fuzzyc output saturates to its range: "
                                        "declare a RANGE")
                var.lo, var.hi = 0.0, 1.0         # said once, here
                continue
            if var.lo is not None or not spans or None in spans:
                continue
            # a single point (one singleton) passes for a Takagi-Sugeno output only
            # (Collected.check_ranges: an empty range is refused elsewhere)
            var.lo = min(s[0] for s in spans)
            var.hi = max(s[1] for s in spans)
            self.got.notes.append(f"`{name}` has no RANGE: took [{var.lo:g}, {var.hi:g}], the "
                                  "universe jFuzzyLogic estimates from its terms")

    # ------------------------------------------------------------------ rules
    def _ruleblock(self, tree: Tree) -> None:
        name = next((c.value for c in tree.children if isinstance(c, Token)),
                    f"block{len(self.block_settings) + 1}")
        settings: dict[str, tuple[str, SourceLoc]] = {}
        self.block_settings.append((name, settings))
        for item in tree.children:
            if isinstance(item, Token):
                continue
            if item.data == "rule":
                number, text = item.children
                loc = self.loc(number)
                for rule in rule_from_tree(text, self.got, self.loc, HEDGES,
                                           f"{self.path} RULE {number}", loc):
                    self.got.rules.append(rule)
                    self.rule_block.append(len(self.block_settings) - 1)
            else:
                self._choose(settings, OPERATORS[item.data][0], item.children[0])

    def _choose(self, seen: dict, key: str, word: Token) -> None:
        """One word per key in a RULEBLOCK or DEFUZZIFY (the first; another is an error)."""
        value = word.value.upper()
        value = ALIASES.get(key, {}).get(value, value)
        if key in seen and seen[key][0] != value:
            first, where = seen[key]
            self.rep.error(self.loc(word), f"{key} {value} differs from {first} at line "
                                           f"{where.line} in the same block")
            return
        seen.setdefault(key, (value, self.loc(word)))

    def _inference(self) -> None:
        """Each RULEBLOCK's AND/OR/ACT, each output's METHOD and ACCU (ACCU in DEFUZZIFY, as
        fuzzylite writes it, or in the RULEBLOCK concluding the output, as IEC 61131-7 does)."""
        blocks = self.block_settings or [("rules", {})]
        block_of = {out: k for rule, k in zip(self.got.rules, self.rule_block)
                    for out in rule.conclusions}
        choices = {name: self._output_choice(var, blocks[block_of.get(name, 0)][1])
                   for name, var in self.got.outputs.items()}
        operators = [self._operators(settings, [r for r, b in zip(self.got.rules,
                                                                  self.rule_block) if b == k],
                                     [choices[o] for o, b in block_of.items() if b == k])
                     for k, (_, settings) in enumerate(blocks)]
        self.got.set_inference([name for name, _ in blocks], operators, self.rule_block, choices)

    def _operators(self, settings: dict, rules: list, outputs: list) -> Inference:
        """A RULEBLOCK's AND, OR and ACT; a note for each it needs and lacks."""
        inf = Inference()
        if self.jfl is not None:
            settings = self._jfl_pair(settings)
        used = set().union(*(r.connectives() for r in rules))
        integral = any(d not in (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.TSUKAMOTO,
                                 Defuzzifier.TSUKAMOTO_SUM, Defuzzifier.CENTER_OF_AREA)
                       for _, d in outputs)
        needed = {"AND": Connective.AND in used, "OR": Connective.OR in used, "ACT": integral}
        for key, field, table in (OPERATORS["and_op"], OPERATORS["or_op"], OPERATORS["act"]):
            if key in settings:
                value, loc = settings[key]
                if value not in table:
                    self.rep.error(loc, f"{key} {value} is not supported; use one of "
                                        + ", ".join(table))
                else:
                    setattr(inf, field, table[value])
            elif needed[key]:
                default = next(k for k, v in table.items() if v == getattr(inf, field))
                self.got.notes.append(f"{key} not given: {default} assumed")
        return inf

    def _jfl_pair(self, settings: dict) -> dict:
        """jFuzzyLogic (RuleBlock.fclTree) sets AND and OR together, as a De Morgan pair (MIN
        MAX, PROD ASUM, BDIF BSUM, DMIN DMAX, NIPMIN NIPMAX, HAMACHER EINSTEIN): the later of
        the two lines sets both.  Its words for the drastic, nilpotent and Hamacher norms are
        read as fuzzylite's (DPROD DSUM, NMIN NMAX, HPROD ESUM)."""
        pairs = [("MIN", "MAX"), ("PROD", "ASUM"), ("BDIF", "BSUM"), ("DPROD", "DSUM"),
                 ("NMIN", "NMAX"), ("HPROD", "ESUM")]
        words = {"DMIN": "DPROD", "DMAX": "DSUM", "NIPMIN": "NMIN", "NIPMAX": "NMAX",
                 "HAMACHER": "HPROD", "EINSTEIN": "ESUM"}
        given = {key: (words.get(settings[key][0], settings[key][0]), settings[key][1])
                 for key in ("AND", "OR") if key in settings}
        if not given:
            return settings
        key, (word, loc) = max(given.items(), key=lambda kv: (kv[1][1].line, kv[1][1].col))
        pair = next((p for p in pairs if p[key == "OR"] == word), None)
        if pair is None:
            return {**settings, **given}
        other = "OR" if key == "AND" else "AND"
        derived = pair[key == "AND"]
        if other in given and given[other][0] != derived:
            self.got.notes.append(f"{other} {given[other][0]} at line {given[other][1].line} "
                                  f"is replaced by {derived}: jFuzzyLogic's {key} {word} at line "
                                  f"{loc.line} sets both (a De Morgan pair)")
        elif other not in given:
            self.got.notes.append(f"{other} not given: {derived}, the pair of {key} {word} "
                                  f"(jFuzzyLogic's dialect: {self.jfl[0]} at line "
                                  f"{self.jfl[1].line})")
        return {**settings, key: (word, loc), other: (derived, loc)}

    def _output_choice(self, var: VarSpec, block: dict) -> tuple[Aggregation, Defuzzifier]:
        """An output's aggregation and defuzzifier: its METHOD, and its ACCU or its block's.
        COGS without ACCU is fuzzylite's weighted average over the rules (Tsukamoto's method
        over monotonic terms); with ACCU, the center of area over singletons."""
        inf = Inference()
        settings = self.output_settings.get(var.name, {})
        accu = settings.get("ACCU") or block.get("ACCU")
        if "ACCU" in settings and "ACCU" in block and settings["ACCU"][0] != block["ACCU"][0]:
            self.rep.error(block["ACCU"][1], f"ACCU {block['ACCU'][0]} differs from "
                                             f"{settings['ACCU'][0]} given for `{var.name}` at "
                                             f"line {settings['ACCU'][1].line}")
        method, loc = settings.get("METHOD", ("COG", var.loc))
        if "METHOD" not in settings:
            self.got.notes.append(f"METHOD not given for `{var.name}`: COG assumed")
        if method == "COGF":
            # jFuzzyLogic's centre of gravity of functions: sum x acc / sum acc over the
            # singletons its FUNCTION terms evaluate to, as COGS over singletons
            method = "COGS"
        elif var.name in self.jfl_functions and method not in ("COGS", "COGSS"):
            for where in self.jfl_functions[var.name]:
                self.rep.error(where, f"a FUNCTION term (a singleton at a computed place) needs "
                                      f"METHOD COGF or COGS; `{var.name}` has {method}")
        if accu is not None and accu[0] not in OPERATORS["accu"][2]:
            self.rep.error(accu[1], f"ACCU {accu[0]} is not supported: the model has "
                                    + ", ".join(OPERATORS["accu"][2]))
        elif accu is not None:
            inf.aggregation = OPERATORS["accu"][2][accu[0]]
        elif self.jfl is not None:
            # jFuzzyLogic's default accumulation (RuleBlock.fclTree) is the unbounded SUM
            inf.aggregation = Aggregation.SUM
            if method not in ("COGS", "COGSS", "COGF"):
                self.got.notes.append(f"ACCU not given for `{var.name}`: SUM, jFuzzyLogic's "
                                      f"default (its dialect: {self.jfl[0]} at line "
                                      f"{self.jfl[1].line})")
        elif method not in ("COGS", "COGSS"):    # weighted: the rules, not a fuzzy set
            self.got.notes.append(f"ACCU not given for `{var.name}`: MAX assumed (IEC "
                                  "61131-7 and fuzzylite; jFuzzyLogic's files, recognised by "
                                  "its constructs, take SUM)")
        if method not in METHODS:
            self.rep.error(loc, f"METHOD {method} is not supported: the model has "
                                + ", ".join(METHODS))
            return inf.aggregation, inf.defuzzifier
        defuzzifier = METHODS[method]
        if method in ("COGS", "COGSS") and tsukamoto_terms([var]):
            # fuzzylite's Tsukamoto over Ramp, ...: fuzzylite 6 weighs every rule, whatever ACCU
            defuzzifier = Defuzzifier.TSUKAMOTO if method == "COGS" else \
                Defuzzifier.TSUKAMOTO_SUM
        elif method == "COGS" and accu is None:
            defuzzifier = Defuzzifier.WEIGHTED_AVERAGE        # over the rules
            self._require_singletons(var, TermKind.LINEAR, TermKind.FUNCTION)
        elif method == "COGS":        # grouped per term: linear and function terms too
            self._require_singletons(var, TermKind.LINEAR, TermKind.FUNCTION)
        elif method == "COGSS":       # fuzzylite's WeightedSum: over the rules, whatever ACCU
            self._require_singletons(var, TermKind.LINEAR, TermKind.FUNCTION, method="COGSS")
        return inf.aggregation, defuzzifier

    def _require_singletons(self, var: VarSpec, *also: TermKind, method: str = "COGS",
                            tsukamoto: str = "") -> None:
        """COGS over anything but singletons (and Linear terms, where allowed) is Tsukamoto's
        method in fuzzylite, which the model carries as a weighted average without ACCU only
        (`tsukamoto` names the method it lacks where it is not that one)."""
        for term in var.terms:
            if term.kind != TermKind.SINGLETON and term.kind not in also:
                kinds = " or Linear/Function" if also else ""
                what = (f"or monotonic ones (Tsukamoto); `{term.name}` is neither"
                        if not tsukamoto else
                        f"(Takagi-Sugeno); over `{term.name}` it is fuzzylite's {tsukamoto}, "
                        "which the model does not have")
                self.rep.error(term.loc, f"{method} needs singleton{kinds} terms {what}")


def _bell_universe(a: float, b: float, mean: float) -> tuple[float, float] | None:
    """jFuzzyLogic's GBELL universe, mean -+ 999^(1/2b) a (where the bell is 0.001); None
    where that is no finite number (b <= 0, a huge power)."""
    if not b > 0:
        return None
    try:
        delta = math.pow(999.0, 1.0 / (2.0 * b)) * a
    except OverflowError:
        return None
    return (mean - delta, mean + delta) if math.isfinite(delta) else None


class _JflError(ValueError):
    def __init__(self, message: str, offset: int):
        super().__init__(message)
        self.offset = offset


class _JflExpression:
    """jFuzzyLogic's FUNCTION grammar (Fcl.g: fun_pm, fun_md, fun_mp, fun_atom): + - over
    * / over ^ % (left to right, one level), atoms a number, a variable, or exp ln log sin cos
    tan abs of a parenthesised expression; written back fully parenthesised in fuzzyc's
    formula syntax (`%` as fmod: Java's remainder keeps the dividend's sign; ln as log)."""
    FUNCTIONS = {"exp": "exp", "ln": "log", "sin": "sin", "cos": "cos", "tan": "tan",
                 "abs": "abs"}

    def __init__(self, text: str, inputs: set[str], outputs: set[str]):
        import re
        self.text, self.inputs, self.outputs = text, inputs, outputs
        self.tokens = [(m.group(), m.start()) for m in re.finditer(
            r"[0-9]+(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?|[A-Za-z_][A-Za-z0-9_]*|\S", text)]
        self.at = 0

    def _peek(self) -> str | None:
        return self.tokens[self.at][0] if self.at < len(self.tokens) else None

    def _offset(self) -> int:
        return self.tokens[self.at][1] if self.at < len(self.tokens) else len(self.text)

    def _take(self) -> str:
        self.at += 1
        return self.tokens[self.at - 1][0]

    def parse(self) -> str:
        from ..engine.formula import MAX_DEPTH, MAX_TEXT
        if not self.tokens:
            raise _JflError("it needs an expression", 0)
        if len(self.text) > MAX_TEXT:
            raise _JflError(f"longer than {MAX_TEXT} characters", 0)
        depth = 0
        for token, offset in self.tokens:      # the parser recurses per bracket: bounded
            depth += (token == "(") - (token == ")")
            if depth > MAX_DEPTH:
                raise _JflError(f"brackets nested deeper than {MAX_DEPTH}", offset)
        out = self._level(0)
        if self._peek() is not None:
            raise _JflError(f"unexpected `{self._peek()}`", self._offset())
        return out

    LEVELS = (("+", "-"), ("*", "/"), ("^", "%"))

    def _level(self, k: int) -> str:
        if k == len(self.LEVELS):
            return self._atom()
        out = self._level(k + 1)
        while self._peek() in self.LEVELS[k]:
            op = self._take()
            right = self._level(k + 1)
            out = f"fmod({out}, {right})" if op == "%" else f"({out} {op} {right})"
        return out

    def _atom(self) -> str:
        word, offset = self._peek(), self._offset()
        if word is None:
            raise _JflError("the expression ends early", offset)
        self._take()
        if word == "-":                      # a signed number (jFuzzyLogic's REAL)
            return f"(-{self._atom()})"
        if word == "(":
            return self._closed(self._level(0))
        if word[0].isdigit():
            return word
        if word.lower() in self.FUNCTIONS and self._peek() == "(":
            self._take()
            return f"{self.FUNCTIONS[word.lower()]}{self._closed(self._level(0))}"
        if word.lower() == "log" and self._peek() == "(":
            raise _JflError("jFuzzyLogic's `log` is not read (its base is not documented): "
                            "write ln(...) or divide by ln(10)", offset)
        if word in self.inputs:
            return word
        if word in self.outputs:
            raise _JflError(f"`{word}` is an output: jFuzzyLogic refuses it in a FUNCTION "
                            "(a race between outputs); use inputs", offset)
        raise _JflError(f"`{word}` is not an input variable", offset)

    def _closed(self, inner: str) -> str:
        if self._peek() != ")":
            raise _JflError("`)` expected", self._offset())
        self._take()
        return f"({inner})"


def _offset_loc(loc: SourceLoc, text: str, offset: int) -> SourceLoc:
    """The place `offset` characters into `text`, which starts at `loc`."""
    before = text[:max(offset, 0)]
    lines = before.count("\n")
    if lines:
        return replace(loc, line=loc.line + lines, col=len(before) - before.rfind("\n"))
    return replace(loc, col=loc.col + len(before))


def _block_name(block: Tree) -> Token | None:
    return next((c for c in block.children if isinstance(c, Token)), None)


def _listing(named: dict[str, SourceLoc]) -> str:
    if not named:
        return "its only FUNCTION_BLOCK has no name (load the file without `::NAME`)"
    return "the blocks are " + ", ".join(f"`{n}` at {loc}" for n, loc in named.items())


def _points_to_trapezoid(points: list[tuple[float, float]]):
    """A point list of 0/1 values rising once and falling once, as the equal trapezoid."""
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    if any(y not in (0.0, 1.0) for y in ys) or xs != sorted(xs) or 1.0 not in ys:
        return None
    first = ys.index(1.0)
    last = len(ys) - 1 - ys[::-1].index(1.0)
    if any(y != 1.0 for y in ys[first:last + 1]):
        return None  # a dip inside the top
    # Beyond the first/last point a term keeps that point's value: a 1 there makes a shoulder.
    a, b = (xs[first - 1], xs[first]) if first > 0 else (-math.inf, -math.inf)
    c, d = (xs[last], xs[last + 1]) if last + 1 < len(xs) else (math.inf, math.inf)
    if first == 0 and last == len(xs) - 1:
        return None  # 1 everywhere
    return trapezoid_or_none(a, b, c, d)


def read_fcl(text: str, path: str = "<string>", block: str | None = None) -> Model:
    """The FCL function block named `block` (or the file's only one) as a Model; raises
    FuzzycError listing what it cannot carry.

    The whole file is parsed, so a syntax error in any block is reported, and so are a repeated
    block name and, in a file with several blocks, a nameless one.  The semantic checks
    (declarations, terms, rules, operators) run on the chosen block only: a block that is not
    chosen may hold what the model cannot carry."""
    return _FclReader(text, path).read(text.lstrip("\ufeff"), block)


def fcl_block_names(text: str, path: str = "<string>") -> list[str | None]:
    """The names of the file's FUNCTION_BLOCKs in order (None for a nameless one); a syntax
    error anywhere is raised, located."""
    reader = _FclReader(text, path)
    try:
        tree = fcl_lark().parse(text.lstrip("\ufeff"), start="start")
    except UnexpectedInput as exc:
        syntax_error(exc, reader.rep, reader.rep.loc(exc.line, exc.column))
        reader.rep.raise_if_any()
    return [None if t is None else t.value for t in map(_block_name, tree.children)]


def check_fcl(text: str, path: str = "<string>") -> list[tuple[str, object]]:
    """Every FUNCTION_BLOCK of the file checked (jFuzzyLogic's files may hold several):
    (`FILE.fcl::NAME`, its Model or, for a block with inputs and no outputs, the list of its
    input VarSpecs: a membership demo) per block; FuzzycError with every block's diagnostics."""
    from ..errors import FuzzycError
    from ..language.limits import check_model
    names = fcl_block_names(text, path)
    refs = [None] if len(names) == 1 else names
    if len(names) > 1 and None in names:        # the reader says where, naming the others
        read_fcl(text, path)
    out, diagnostics = [], []
    for name in refs:
        label = path if name is None else f"{path}::{name}"
        try:
            model = read_fcl(text, path, name)
            check_model(model)
            out.append((label, model))
        except FuzzycError as exc:
            if [d.message.startswith("the file declares no output variable")
                    for d in exc.diagnostics] == [True]:
                out.append((label, _FclReader(text, path).memberships(
                    text.lstrip("\ufeff"), name)))
            else:
                diagnostics += exc.diagnostics
    if diagnostics:
        raise FuzzycError(diagnostics)
    return out


# ---------------------------------------------------------------------- export
FCL_OPERATOR_WORDS = {field: (key, {v: k for k, v in words.items()})
                      for key, field, words in OPERATORS.values()}
# Where IEC 61131-7 has no word, export writes fuzzylite's (its CLI reads them back; it rejects
# jFuzzyLogic's GAUSS/GBELL/SIGM and PROBOR, measured), which fuzzyc reads as well
FUZZYLITE = "fuzzylite's FCL, not IEC 61131-7 (jFuzzyLogic writes it otherwise)"
FUZZYLITE_ACCU = {Aggregation.SUM: "SUM (unbounded)", Aggregation.PROBSUM: "ASUM (a+b-ab)"}
FCL_OPERATOR_WORDS["aggregation"][1][Aggregation.PROBSUM] = "ASUM"


# what may follow RULEBLOCK where its name stands (FCL's keywords are case-insensitive)
RULEBLOCK_WORDS = frozenset({"rule", "and", "or", "act", "accu", "end_ruleblock"})


def write_fcl(model: Model, warnings: list[str] | None = None) -> str:
    """The model's rule blocks as one FCL function block, one RULEBLOCK each with its own
    AND/OR/ACT, every output with its own METHOD and ACCU; what is left out or written with a
    fuzzylite extension is appended to `warnings`.  Raises FuzzycError when a rule block
    cannot be said in FCL (weighted sum, hedges)."""
    inputs, _ = file_variables(model)
    notes = left_out(model) + chain_warning(model, "FCL")
    problems = unsayable_names(model, "FCL")
    fuzzify = [line for var in inputs
               for line in (f"FUZZIFY {var.name}", *_fcl_terms(var, problems, notes),
                            f"  RANGE := ({num(var.lo)} .. {num(var.hi)});", "END_FUZZIFY", "")]
    outputs, defuzzify, ruleblocks = [], [], []
    for name, rb in zip(block_names(model, RULEBLOCK_WORDS), model.blocks):
        view = block_view(model, rb)
        problems += unsayable_hedges(view, {}, "FCL")
        for o in range(len(rb.outputs)):
            single = block_view(model, one_output(rb, o))
            (var,), method = _fcl_method(single, problems, notes)
            outputs.append(var)
            defuzzify += _fcl_defuzzify(var, method, single.rulebase.inference, problems, notes)
        operators = [_fcl_operator(field, getattr(rb.inference, field), problems)
                     for field in ("and_", "or_", "implication")]
        ruleblocks += [f"RULEBLOCK {name}", *operators]
        ruleblocks += [f"  RULE {r + 1} : {rule_sentence(view, r, {}, ' and ', problems, True)};"
                       for r in range(rb.n_rules)]
        ruleblocks += ["END_RULEBLOCK", ""]
    # `//` comments, not IEC's (* *): the fuzzylite 6 CLI rejects (* *) (measured), and
    # fuzzylite and jFuzzyLogic both read `//`; each text on its one line.
    comments = [f"// {one_line(text)}" for text in (model.title, *model.notes) if text]
    lines = [*comments, f"FUNCTION_BLOCK {model_identifier(model)}", ""]
    for section, variables in (("VAR_INPUT", inputs), ("VAR_OUTPUT", outputs)):
        lines += [section, *(f"  {v.name} : REAL;" for v in variables), "END_VAR", ""]
    lines += [*fuzzify, *defuzzify, *ruleblocks, "END_FUNCTION_BLOCK"]
    return finish(model, "FCL", lines, problems, notes, warnings)


def _fcl_defuzzify(var, method: str, inf: Inference, problems: list[str],
                   notes: list[str]) -> list[str]:
    """An output's DEFUZZIFY block.  A weighted average is COGS without ACCU (fuzzylite's
    reading, and fuzzyc's: see the module docstring); the center of area is COGS with the ACCU
    that groups each term's rules.  ACCU stands here, where fuzzylite 6 reads it (it rejects
    ACCU in a RULEBLOCK, measured); IEC 61131-7 and jFuzzyLogic put it in the RULEBLOCK;
    fuzzyc reads both."""
    accu = None if inf.defuzzifier == Defuzzifier.WEIGHTED_AVERAGE else inf.aggregation
    if accu in FUZZYLITE_ACCU:
        notes.append(f"ACCU {FUZZYLITE_ACCU[accu]} is {FUZZYLITE}")
    if method == "MM":
        notes.append(f"METHOD MM is {FUZZYLITE}")
    accu_line = [] if accu is None else [_fcl_operator("aggregation", accu, problems)]
    return [f"DEFUZZIFY {var.name}", *_fcl_terms(var, problems, notes),
            f"  METHOD : {method};", *accu_line,
            f"  DEFAULT := {num(var.default)}{' | NC' * var.lock_previous};",
            f"  RANGE := ({num(var.lo)} .. {num(var.hi)});", "END_DEFUZZIFY", ""]


def _fcl_operator(field: str, value, problems: list[str]) -> str:
    key, words = FCL_OPERATOR_WORDS[field]
    if value not in words:
        problems.append(f"{key} {value.name.lower()} has no FCL word (FCL has "
                        f"{', '.join(words.values())})")
    return f"  {key} : {words.get(value, '?')};"


def _fcl_method(model: Model, problems: list[str], notes: list[str]):
    rb = model.rulebase
    method = rb.inference.defuzzifier
    singletons = all(all_singletons(v) for v in rb.outputs)
    if method == Defuzzifier.WEIGHTED_SUM:
        problems.append("FCL has no weighted-sum defuzzifier: write FLL")
    if method == Defuzzifier.GROUPED_SUM:
        problems.append("FCL has no weighted sum grouped per term (fuzzylite 6 reads COGSS "
                        "with ACCU as the sum over the rules): write FLL")
    if method in (Defuzzifier.TSUKAMOTO, Defuzzifier.TSUKAMOTO_SUM):
        problems.append("FCL has no Tsukamoto defuzzifier (fuzzylite's dialect reads COGS over "
                        "ramps so, jFuzzyLogic does not): write FLL")
    if method in (Defuzzifier.CENTER_OF_AREA, Defuzzifier.WEIGHTED_AVERAGE) or (
            method == Defuzzifier.CENTROID and singletons):
        outputs, changed = peaks_instead(model, "FCL")
        notes.extend(changed)
        return outputs, "COGS"
    # the registry's METHOD word (LM, RM too); COG for what FCL has no word for
    return rb.outputs, ops.DEFUZZIFIERS[method].fcl or "COG"


def _fcl_terms(var, problems: list[str], notes: list[str]) -> list[str]:
    lines = []
    for t, (name, kind, p) in enumerate(zip(var.names, var.kinds, var.params)):
        a, b, c, d = (float(x) for x in p)
        kind = TermKind(int(kind))
        if kind == TermKind.FUNCTION:
            body = f"Function {var.formulas[t].infix()}"      # fuzzylite's dialect
        elif kind == TermKind.DISCRETE:
            body = " ".join(f"({num(x)}, {num(y)})" for x, y in var.points[t])
        elif kind == TermKind.TRAPEZOID:
            points = [(a, 0), (b, 1), (c, 1), (d, 0)]
            if b == c:
                del points[2]
            body = " ".join(f"({num(x)}, {y})" for x, y in points if math.isfinite(x))
            if not all(math.isfinite(x) for x in (b, c)) and not (
                    (a == b == -math.inf) ^ (c == d == math.inf)):
                problems.append(f"term `{name}` of `{var.name}` has no FCL point list")
        elif kind == TermKind.SINGLETON:
            body = num(a)
        elif kind == TermKind.LINEAR or fll_term(kind, p, True) is None:
            problems.append(f"term `{name}` of `{var.name}` ({kind.name.lower()}) has no FCL "
                            "shape")
            continue
        else:
            body = fll_term(kind, p, True)
            notes.append(f"term `{name}` of `{var.name}` is written `{body.split()[0]}`, "
                         f"{FUZZYLITE}")
        lines.append(f"  TERM {name} := {body};")
    return lines
