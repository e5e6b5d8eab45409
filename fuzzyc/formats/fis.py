"""MATLAB/Octave Fuzzy Logic Toolbox text files (.fis): import and export.

The format is line-oriented (`[Section]` headers, `Key=value` lines, numeric rule rows), so it is
read line by line with a regular expression per line kind, every value keeping its column.
Mapping (exact unless said): trimf, trapmf -> TRAPEZOID; gaussmf [sigma c] -> GAUSSIAN (c, sigma);
gbellmf [a b c] -> BELL (c, a, b); sigmf [a c] -> SIGMOID (c, a); smf, zmf, pimf -> SSHAPE,
ZSHAPE, PISHAPE; constant -> SINGLETON; linear [c1 .. cn c0] -> LINEAR (sugeno outputs).
min/prod, max/probor, implication min/prod, aggregation max/sum/probor; centroid, bisector, mom,
wtaver, wtsum.  MATLAB evaluates Mamdani outputs on 101 points of the range; the model
integrates exactly.  Rules: `i1 i2, o1 (w) : c` with 0 = any, a negative index = NOT,
c = 1 (and) or 2 (or); a fraction on an input index is the Octave toolkit's hedge
(`t.05` somewhat, `t.2` very, `t.3` extremely, `t.4` very very: membership^0.5, ^2, ^3, ^4);
on an output index it is kept as said (CondOp.CONCLUDED: the Octave toolkit's strength^(1/p)
in the exact semantics, fuzzylite's carried hedge under its semantics; see fuzzyc.semantics.model).
The Octave toolkit's and fuzzylite's further norms (einstein_product, hamacher_sum, ...) and fuzzylite's
membership functions (rampmf, rectmf, concavemf, cosinemf, spikemf; dsigmf, psigmf, gauss2mf
as fuzzylite's SigmoidDifference, SigmoidProduct, GaussianProduct) are read too.
Comments: `%` to the end of the line, and lines starting with `#`.
A negated consequent (`-t` on an output) is the Octave toolkit's: in a Mamdani system the
rule concludes a further term `not_t` (`not_very_t` ...), the complement 1 - mu^p as a Function
term (formats.complement); in a Sugeno system the rule's program ends in its CONCLUDED step and
NOT, the height 1 - strength^(1/p) (under --semantics octave only where the rule fires, as
eval_rules_sugeno.m computes it).
A weight on a row with a hedged or negated consequent weighs the strength before the
consequent's steps (a CondOp.WEIGHT step), as both tools do.
Not carried, reported: other MF types (discretemf, custom functions).  Type tsukamoto
(fuzzylite's: wtaver over monotonic terms) is the model's Tsukamoto defuzzifier; type hybrid
(fuzzylite's: a defuzzifier per output) gives the outputs of constant terms the weighted
average (`_FisReader._hybrid`).
When no rule fires, MATLAB's evalfis sets an output to the middle of its range (with a
warning): the imported output's default is that middle, so both give the same number.

Export (`write_fis`) is the exact inverse of that mapping, with these choices:
- Mamdani for centroid, bisector and mean of maximum over area terms; Sugeno for the weighted
  average/sum, whose constant terms are the output terms' peaks (`export.peaks_instead`), and
  for center of area (and any method over all-singleton outputs), which is MATLAB's wtaver only
  when no two rules conclude the same term or the aggregation is a sum: the model's max over the
  rules concluding one term has no FIS word, so such a rule base is refused.  Sugeno files get
  ImpMethod='prod' and AggMethod='sum', MATLAB's Sugeno defaults (its manual: a Sugeno system's
  implication is a product and its aggregation includes every singleton); fuzzyc's weighted
  defuzzifiers do not depend on them.
- Shoulders (infinite break points) are written as trapmf flat to the end of the range
  ([lo lo c d], [a b hi hi]): the same membership on the range, 0 instead of 1 beyond it.
- MATLAB evaluates Mamdani outputs on 101 points of the range; fuzzyc integrates exactly, so
  MATLAB's numbers differ by that sampling error (said in a warning).  The round-trip tests
  compare fuzzyc on the re-imported file, not MATLAB.
- Hedges are written as the reader reads them (`.05` somewhat, `.2` very, `.3` extremely,
  `.4` very very; fuzzylite reads `.3` as its S-curve: a warning), and the rules the reader
  made of a row with hedged consequents as that row again (a row whose first conclusion is
  plain as two rows, the same numbers in both readings).
- Refused: seldom and sharply (FIS has no fraction for them), spike/cosine/concave terms,
  singleton inputs, rules without a clause or a conclusion, an and/or operator MATLAB lacks that a rule needs, singleton
  terms beside area terms of a Mamdani output, bounded-sum aggregation (MATLAB's AggMethod is
  max, sum, probor or a custom function: writing one of the first three would give other
  numbers without a word, a custom function would need a .m file beside the .fis, so it is
  refused).  A rule mixing `and` and `or` cannot occur (the
  model has one connective per rule, as the file does).
"""
from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np

from ..language.builder import RuleSpec
from ..language.conditions import Cond, premise
from ..errors import Reporter, source_lines
from ..escape import name_problems
from ..semantics.model import (Aggregation, CondOp, Connective, Defuzzifier, Hedge, Implication, Model,
                     SourceLoc, TermKind, Variable)
from ..engine.membership import linear_coefficients
from ..semantics import operators as ops
from ..semantics.shapes import SHAPES, TRAPEZOID_NEEDS, TRIANGLE_NEEDS
from ..language.numbers import parse_number
from .common import (Collected, TermSpec, VarSpec, degenerate, plain_shape_or_none, shape,
                     trapezoid_or_none, tsukamoto_terms)
from .blocks import one_rule_base
from .export import (finish, left_out, num, own_output_choices, peaks_instead,
                     unsayable_functions, unsayable_hedges)
from .fll import fuzzylite_shape
from .functions import function_term
from .complement import complement_formula

# ASCII: \d and \w would take other scripts' digits (`[Input１]`, `５`), which int() reads
SECTION = re.compile(r"\s*\[(\w+?)(\d*)\]\s*$", re.ASCII)
KEY_VALUE = re.compile(r"\s*(\w+)\s*=\s*(.*?)\s*$", re.ASCII)
FIS_NAME = re.compile(r"[^'%\x00-\x1f\x7f]*")   # quoted in '...'; % starts a comment
MF = re.compile(r"'([^']*)'\s*:\s*'([^']*)'\s*,\s*\[([^\]]*)\]\s*$")
RULE = re.compile(r"\s*([-\d.\s]+?)\s*,\s*([-\d.\s]+?)\s*"
                  r"\(\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*\)\s*:\s*(\d+)\s*$",
                  re.ASCII)
# The MATLAB words (written), and the Octave toolkit's and fuzzylite's words for further
# operators (read only: export writes the MATLAB words, which every reader knows): the
# operator registry's.
_KEYS = (("AndMethod", "and_", ops.T_NORMS), ("OrMethod", "or_", ops.S_NORMS),
         ("ImpMethod", "implication", ops.IMPLICATIONS),
         ("AggMethod", "aggregation", ops.AGGREGATIONS),
         ("DefuzzMethod", "defuzzifier", ops.DEFUZZIFIERS))
SETTINGS = {key: (field, ops.format_words(table, "fis", read=False))
            for key, field, table in _KEYS}
READ_ALSO = {key: words for key, _, table in _KEYS
             if (words := {w: k for k, rec in table.items() for w in rec.also_in("fis")})}
# The Octave toolkit's hedges: a rule index `t.h` is term t with its membership raised to the
# power round(100 h) / 10 (`1.05` somewhat, `1.2` very, `1.3` extremely, `1.4` very very), as
# the hedges that make that power, nearest the term first (fuzzylite reads them so too).
FIS_HEDGES = {0.0: (), 0.5: (Hedge.SOMEWHAT,), 2.0: (Hedge.VERY,), 3.0: (Hedge.EXTREMELY,),
              4.0: (Hedge.VERY, Hedge.VERY)}
FIS_FRACTIONS = {hedges: f"{exponent / 10:.2f}"[1:].rstrip("0") if hedges else ""
                 for exponent, hedges in FIS_HEDGES.items()}     # written back: `.05`, `.2`
HEDGE_POWER = {Hedge.SOMEWHAT: 0.5, Hedge.VERY: 2.0, Hedge.EXTREMELY: 3.0}   # FIS_HEDGES'
FIS_HEDGE_WORDS = {hedges[0]: text for hedges, text in FIS_FRACTIONS.items() if len(hedges) == 1}
# what each MATLAB shape's numbers must satisfy, in its own parameter order
FIS_NEEDS = {"trimf": f"[a b c] needs {TRIANGLE_NEEDS}",
             "trapmf": f"[a b c d] needs {TRAPEZOID_NEEDS}",
             "gaussmf": "[sigma c] needs sigma > 0", "gbellmf": "[a b c] needs a > 0 and b > 0",
             "sigmf": "[a c] needs a != 0", "constant": "[c] needs a finite c",
             "smf": "[a b] needs a < b", "zmf": "[a b] needs a < b",
             "pimf": "[a b c d] needs a < b and c < d"}
# fuzzylite's membership functions in FIS -> (its FLL word, FIS parameters -> FLL's order)
FUZZYLITE_MFS = {"rampmf": ("Ramp", lambda v: v), "rectmf": ("Rectangle", lambda v: v),
                 "concavemf": ("Concave", lambda v: v), "cosinemf": ("Cosine", lambda v: v),
                 "spikemf": ("Spike", lambda v: v), "discretemf": ("Discrete", lambda v: v),
                 "dsigmf": ("SigmoidDifference", lambda v: _reordered(v, (1, 0, 2, 3))),
                 "psigmf": ("SigmoidProduct", lambda v: _reordered(v, (1, 0, 2, 3))),
                 "gauss2mf": ("GaussianProduct", lambda v: _reordered(v, (1, 0, 3, 2)))}


def _reordered(values: list, order: tuple[int, ...]) -> list:
    """`values` in FLL's order (a height after them kept); too few as they are, so that
    fuzzylite_shape reports the count at the term (indexing them was an IndexError)."""
    if len(values) < len(order):
        return values
    return [values[i] for i in order] + values[len(order):]
SYSTEM_KEYS = {"Name", "Type", "Version", "NumInputs", "NumOutputs", "NumRules", *SETTINGS}
VARIABLE_KEYS = {"Name", "Range", "NumMFs"}


class _FisReader:
    def __init__(self, text: str, path: str):
        self.rep = Reporter(path, text)
        self.got = Collected(self.rep, "imported")
        self.path = path
        self.section: str | None = None
        self.var: VarSpec | None = None
        self.variables: list[tuple[bool, VarSpec]] = []   # in file order, for rule columns
        self.type = "mamdani"
        self.type_loc = None
        self.pending_rules: list[tuple[int, str]] = []
        self.complements: dict[tuple[str, int, float], int] = {}   # (output, term, power)

    def read(self, text: str) -> Model:
        for number, line in enumerate(source_lines(text.lstrip("\ufeff")), start=1):
            # `%` starts a comment (MATLAB); a line starting with `#` is one too (fuzzylite and
            # the Octave toolkit write their headers so); `#` inside a line stays text.
            body = "" if line.lstrip().startswith("#") else line.split("%", 1)[0]
            if body.strip():
                self._line(number, body)
        for is_input, var in self.variables:
            self.got.declare(var, is_input)
            if not is_input and var.lo is not None:
                var.default = 0.5 * (var.lo + var.hi)   # evalfis: no rule fired -> mid-range
        for number, body in self.pending_rules:
            self._rule(number, body)
        self._check_sugeno()
        return self.got.model(self.path, text)

    def _check_sugeno(self) -> None:
        weighted = self.got.inference.defuzzifier in (Defuzzifier.WEIGHTED_AVERAGE,
                                                      Defuzzifier.WEIGHTED_SUM)
        if self.type == "hybrid":
            self._hybrid(weighted)
            return
        if self.type == "tsukamoto":      # fuzzylite's: wtaver over monotonic terms
            if self.got.inference.defuzzifier != Defuzzifier.WEIGHTED_AVERAGE or \
                    not tsukamoto_terms(self.got.outputs.values()):
                self.rep.error(self.rep.loc(1, 1), "a tsukamoto system needs wtaver and "
                                                   "monotonic output terms")
            self.got.inference.defuzzifier = Defuzzifier.TSUKAMOTO
            return
        if weighted != (self.type == "sugeno"):
            methods = "wtaver or wtsum" if self.type == "sugeno" else \
                "centroid, bisector, mom, som or lom"
            self.rep.error(self.rep.loc(1, 1), f"a {self.type} system cannot use "
                                               f"{self.got.inference.defuzzifier.name.lower()}; "
                                               f"use DefuzzMethod {methods}")
        for var in self.got.outputs.values():
            for term in var.terms:
                # a Function term is a value (sugeno) or a membership of x (mamdani)
                if term.kind != TermKind.FUNCTION and \
                        (term.kind in (TermKind.SINGLETON, TermKind.LINEAR)) != \
                        (self.type == "sugeno"):
                    self.rep.error(term.loc, f"`{term.name}`: constant output terms belong to "
                                             "sugeno systems, and only they")

    def _hybrid(self, weighted: bool) -> None:
        """fuzzylite's `hybrid` FIS (its FisExporter, for an engine whose outputs have their
        own defuzzifiers): DefuzzMethod for the outputs of area terms, the weighted average
        (fuzzylite's WeightedAverage TakagiSugeno) for the outputs whose terms are all
        `constant`, as the engine's .fll and .fcl say.  fuzzylite 6 itself reads the file
        back with DefuzzMethod for every output, a Constant term then a membership flat over
        the range; `fuzzylite flat` (tool_semantics.file_settings) gives that under its
        semantics."""
        if weighted:
            self.rep.error(self.type_loc, "type `hybrid` needs the DefuzzMethod of its Mamdani "
                                          "outputs (centroid, bisector, mom, som or lom); "
                                          "write type sugeno for weighted averages")
        for var in self.got.outputs.values():
            kinds = {term.kind for term in var.terms}
            if TermKind.LINEAR in kinds:
                term = next(t for t in var.terms if t.kind == TermKind.LINEAR)
                self.rep.error(term.loc, f"`{term.name}`: a linear term in a hybrid FIS is a "
                                         "membership of the inputs over the whole range in "
                                         "fuzzylite, which fuzzyc does not reproduce; use the "
                                         "engine's .fll or .fcl")
            elif kinds == {TermKind.SINGLETON}:
                self.got.output_choices[var.name] = (self.got.inference.aggregation,
                                                     Defuzzifier.WEIGHTED_AVERAGE)
            elif TermKind.SINGLETON in kinds:
                term = next(t for t in var.terms if t.kind == TermKind.SINGLETON)
                self.rep.error(term.loc, f"`{term.name}`: an output of a hybrid FIS needs "
                                         "constant terms only or none")

    def _line(self, number: int, body: str) -> None:
        section = SECTION.match(body)
        if section:
            kind = section.group(1)
            if kind not in ("System", "Input", "Output", "Rules"):
                self.rep.error(self.rep.loc(number, 1), f"unknown section [{kind}]; use "
                                                           "[System], [InputN], [OutputN] or "
                                                           "[Rules]")
                kind = None
            self.section = kind
            if kind in ("Input", "Output"):
                self.var = VarSpec(f"{kind.lower()}{section.group(2)}", self.rep.loc(number, 1))
                self.variables.append((kind == "Input", self.var))
            return
        if self.section is None:
            self.rep.error(self.rep.loc(number, 1), "text before the first [Section]; start "
                                                       "the file with [System]")
        elif self.section == "Rules":
            self.pending_rules.append((number, body))
        else:
            match = KEY_VALUE.match(body)
            if match is None:
                self.rep.error(self.rep.loc(number, 1), "this line of a section is not a setting: "
                                                           "write `Key=value`")
                return
            key, value = match.groups()
            loc = self.rep.loc(number, match.start(2) + 1)
            if self.section == "System":
                self._system(key, value, loc, self.rep.loc(number, match.start(1) + 1))
            else:
                self._variable(key, value, loc, self.rep.loc(number, match.start(1) + 1))

    def _system(self, key: str, value: str, loc: SourceLoc, key_loc: SourceLoc) -> None:
        if key not in SYSTEM_KEYS:
            self.rep.error(key_loc, f"unknown key `{key}` in [System]; known: "
                                    + ", ".join(sorted(SYSTEM_KEYS)))
        elif key == "Name":
            self.got.name = re.sub(r"\W", "_", _unquote(value))
        elif key == "Type":
            self.type = _unquote(value).lower()
            self.type_loc = loc
            if self.type not in ("mamdani", "sugeno", "tsukamoto", "hybrid"):
                self.rep.error(loc, f"type `{self.type}` is not supported: mamdani, sugeno, "
                                    "tsukamoto or hybrid (fuzzylite's)")
        elif key in SETTINGS:
            field, table = SETTINGS[key]
            table = {**table, **READ_ALSO.get(key, {})}
            word = _unquote(value)
            if word not in table:
                self.rep.error(loc, f"{key} `{word}` is not supported; use one of "
                                    + ", ".join(table))
            else:
                setattr(self.got.inference, field, table[word])

    def _variable(self, key: str, value: str, loc: SourceLoc, key_loc: SourceLoc) -> None:
        var = self.var
        if key == "Name":
            var.name = _unquote(value)
        elif key == "Range":
            numbers = _numbers(value)
            if numbers is None or len(numbers) != 2:
                self.rep.error(loc, "expected `Range=[low high]`")
            else:
                var.lo, var.hi = numbers
        elif re.fullmatch(r"MF\d+", key, re.ASCII):
            self._mf(value, loc)
        elif key not in VARIABLE_KEYS:
            self.rep.error(key_loc, f"unknown key `{key}` in [{self.section}]")

    def _mf(self, value: str, loc: SourceLoc) -> None:
        match = MF.match(value)
        if match and match.group(2) == "function":      # fuzzylite's: a formula in [...]
            start = replace(loc, col=loc.col + match.start(3))
            term = function_term(match.group(1), match.group(3).rstrip(), loc, start, self.rep)
            if term is not None:
                self.var.add(term, self.rep)
            return
        numbers = _numbers(f"[{match.group(3)}]") if match else None
        if match is None or numbers is None:
            self.rep.error(loc, "this membership function is not written as the format has "
                                    "it: write MFn='name':'type',[parameters]")
            return
        name, kind = match.group(1), match.group(2)
        n_inputs = sum(is_input for is_input, _ in self.variables)   # inputs come first
        arity = {"trimf": 3, "trapmf": 4, "gaussmf": 2, "gbellmf": 3, "sigmf": 2, "constant": 1,
                 "smf": 2, "zmf": 2, "pimf": 4, "linear": n_inputs + 1}
        if kind in FUZZYLITE_MFS:
            word, order = FUZZYLITE_MFS[kind]
            made = fuzzylite_shape(word, order(numbers), loc, self.rep)
            if made is not None:
                kind, params, *more = made
                self.var.add(TermSpec(name, kind, params, loc, *more), self.rep)
            return
        if kind not in arity:
            self.rep.error(loc, f"membership function `{kind}` is not supported: the model "
                                "carries " + ", ".join([*arity, *FUZZYLITE_MFS]))
            return
        v = numbers
        if kind == "linear":     # [c1 .. cn c0], as MATLAB writes it
            if len(v) != arity[kind] or not all(map(math.isfinite, v)):
                self.rep.error(loc, f"`linear` takes {arity[kind]} finite coefficients (one "
                                    "per input, then the constant)")
            else:
                self.var.add(TermSpec(name, TermKind.LINEAR, (0.0,) * 4, loc, tuple(v)),
                             self.rep)
            return
        if len(v) != arity[kind]:
            self.rep.error(loc, f"`{kind}` takes {arity[kind]} parameters, got {len(v)}")
            return
        made = {"trimf": lambda: trapezoid_or_none(v[0], v[1], v[1], v[2]),
                "trapmf": lambda: trapezoid_or_none(*v),
                "gaussmf": lambda: shape(TermKind.GAUSSIAN, v[1], v[0]) if v[0] > 0 else None,
                "gbellmf": lambda: shape(TermKind.BELL, v[2], v[0], v[1]) if v[0] > 0 and v[1] > 0
                else None,
                "sigmf": lambda: shape(TermKind.SIGMOID, v[1], v[0]) if v[0] != 0 else None,
                "constant": lambda: shape(TermKind.SINGLETON, v[0]),
                # strict, as the Octave toolkit's are_mf_params (MATLAB puts a degenerate
                # smf's step at the mean, inclusive: not the model's step, so refused)
                "smf": lambda: plain_shape_or_none(TermKind.SSHAPE, v) if v[0] < v[1] else None,
                "zmf": lambda: plain_shape_or_none(TermKind.ZSHAPE, v) if v[0] < v[1] else None,
                "pimf": lambda: plain_shape_or_none(TermKind.PISHAPE, v)
                if v[0] < v[1] and v[2] < v[3] else None}[kind]()
        if made is None:
            self.rep.error(loc, degenerate(kind, v, FIS_NEEDS[kind], "[]"))
        else:
            self.var.add(TermSpec(name, *made, loc=loc), self.rep)

    def _rule(self, number: int, body: str) -> None:
        loc = self.rep.loc(number, len(body) - len(body.lstrip()) + 1)
        match = RULE.match(body)
        inputs = [v for is_input, v in self.variables if is_input]
        outputs = [v for is_input, v in self.variables if not is_input]
        if match is None:
            self.rep.error(loc, "expected a rule row `in1 in2 ..., out1 ... (weight) : 1|2`")
            return
        ins, outs = match.group(1).split(), match.group(2).split()
        if len(ins) != len(inputs) or len(outs) != len(outputs):
            self.rep.error(loc, f"a rule row needs {len(inputs)} input and {len(outputs)} output "
                                f"indices, got {len(ins)} and {len(outs)}")
            return
        try:
            split = [_index_and_hedge(t) for t in ins + outs]
        except ValueError as exc:
            self.rep.error(loc, str(exc))
            return
        codes = [code for code, _ in split]
        if not all(self._in_range(var, abs(code), loc) for var, code in zip(
                inputs + outputs, codes) if code != 0):
            return
        if self.type == "mamdani":      # `-t`: the complement set 1 - mu^p, a further term
            for k, (var, (code, hedges)) in enumerate(zip(outputs, split[len(ins):])):
                if code < 0:
                    made = self._complement(var, -code - 1, hedges, loc)
                    if made is None:
                        return
                    split[len(ins) + k] = (made + 1, ())
            codes = [code for code, _ in split]
        weight = float(match.group(3))
        connective = int(match.group(4))
        if not 0.0 <= weight <= 1.0 or connective not in (1, 2):
            self.rep.error(loc, "the weight lies in [0, 1] and the connective is 1 (and) or 2 (or)")
            return
        conclusions = {var.name: code - 1 for var, code in zip(outputs, codes[len(ins):]) if code}
        if not conclusions:
            self.rep.error(loc, "a rule needs at least one output index")
            return
        origin = f"{self.path}:{number}"
        if any(hedges for _, hedges in split[len(ins):]) or \
                any(len(hedges) > 1 for _, hedges in split[:len(ins)]) or \
                any(code < 0 for code in codes[len(ins):]):
            if not any(_is_any(t) for t in ins):
                self._hedged_rule(split, weight, connective, loc, origin)
            else:
                self.rep.error(loc, "`any` (0.99) in a row with a hedged or negated consequent "
                                    "or `.4` is not supported")
            return
        clauses = {var.name: (abs(code) - 1, code < 0, hedges[0] if hedges else Hedge.NONE)
                   for var, (code, hedges) in zip(inputs, split[:len(ins)]) if code != 0}
        if any(_is_any(t) for t in ins) and (connective == 2 or not clauses):
            clauses = {}    # `x is any`: true, so an or-rule (or a rule of it alone) fires 1
        elif not clauses:     # fuzzylite writes a chained rule so: it reads an output
            # read as fuzzylite reads it back (its Laundry.fis): a rule that never fires
            self.got.notes.append(f"rule at line {number} has no input index (fuzzylite's "
                                  "chained engine written as FIS, which cannot say a rule "
                                  "reading an output): it never fires, as in fuzzylite; the "
                                  ".fll or .fcl keeps the chain")
            weight = 0.0
        self.got.rules.append(RuleSpec(clauses,
                                       Connective.AND if connective == 1 else Connective.OR,
                                       conclusions, weight, loc, origin))

    def _hedged_rule(self, split: list[tuple[int, tuple[Hedge, ...]]], weight: float,
                     connective: int, loc: SourceLoc, origin: str) -> None:
        """A row with hedges on its consequents (or `.4`, very very, on an input): one rule per
        concluded output, its condition ending in the CondOp.CONCLUDED steps of the row's
        conclusions up to that output (the model's reading in fuzzyc.semantics.model, fuzzylite's in
        tool_semantics); outputs whose steps are the same share a rule."""
        inputs = [v for is_input, v in self.variables if is_input]
        outputs = [v for is_input, v in self.variables if not is_input]
        parts = []
        for var, (code, hedges) in zip(inputs, split):
            if code != 0:
                cond = Cond("is", leaf=(var.name, (abs(code) - 1, False, Hedge.NONE)))
                for hedge in hedges:            # the membership's power, then `not`
                    cond = Cond("hedge", [cond], hedge=hedge)
                parts.append(Cond("not", [cond]) if code < 0 else cond)
        if not parts:
            self.rep.error(loc, "a rule needs at least one input index")
            return
        condition = Cond("and" if connective == 1 else "or", parts)
        if weight != 1.0 and any(hedges or code < 0 for code, hedges in split[len(inputs):]):
            # both tools hedge (negate) the weighted strength: (w s)^(1/p) in the Octave
            # toolkit (eval_firing_strength.m weighs, eval_rules_sugeno.m hedges), h(w s) in
            # fuzzylite: the weight is a CondOp.WEIGHT step under the conclusion's steps
            condition, weight = Cond("weight", [condition], weight=weight), 1.0
        said: list[tuple[Hedge, bool]] = []     # (hedge, own) steps so far
        rules: dict[tuple, dict[str, int]] = {}
        for var, (code, hedges) in zip(outputs, split[len(inputs):]):
            if code == 0:
                continue
            # a negated (Sugeno) consequent: the height 1 - strength^(1/p) (eval_rules_sugeno.m),
            # its own CONCLUDED step (Hedge.NONE without a hedge) then NOT
            own = tuple((h, True) for h in hedges) or (((Hedge.NONE, True),) if code < 0 else ())
            steps = tuple((h, False) for h, _ in said) + own + ((None, True),) * (code < 0)
            rules.setdefault(steps, {})[var.name] = abs(code) - 1
            said += [(h, False) for h in hedges]
        for steps, conclusions in rules.items():
            cond = condition
            for hedge, own in steps:
                cond = Cond("not", [cond]) if hedge is None else \
                    Cond("concluded" if own else "carried", [cond], hedge=hedge)
            clauses, connective_, program = premise(cond)
            self.got.rules.append(RuleSpec(clauses, connective_, conclusions, weight, loc, origin,
                                           program))

    def _complement(self, var: VarSpec, t: int, hedges: tuple[Hedge, ...],
                    loc: SourceLoc) -> int | None:
        """The index of `var`'s term `not_NAME` (`not_very_NAME` ...): 1 - mu^p of its term t,
        the set a negated Mamdani consequent concludes (formats.complement), added once; None
        after reporting a term no formula is written for."""
        term = var.terms[t]
        power = 1.0
        for hedge in hedges:
            power *= HEDGE_POWER[hedge]
        words = "_".join(h.name.lower() for h in hedges)
        if (var.name, t, power) in self.complements:
            return self.complements[var.name, t, power]
        name = f"not_{words + '_' if words else ''}{term.name}"
        while name in var.term_names():
            name += "_"
        text = complement_formula(term.kind, term.params, power)
        if text is None:
            self.rep.error(loc, f"a negated consequent of `{term.name}` "
                                f"({term.kind.name.lower()}): its complement is written for the "
                                "FIS membership functions only")
            return None
        made = function_term(name, text, term.loc, term.loc, self.rep)
        if made is None:
            return None
        var.add(made, self.rep)
        self.complements[var.name, t, power] = len(var.terms) - 1
        return len(var.terms) - 1

    def _in_range(self, var: VarSpec, index: int, loc: SourceLoc) -> bool:
        if index > len(var.terms):
            self.rep.error(loc, f"`{var.name}` has {len(var.terms)} terms, no term {index}")
            return False
        return True


def _is_any(text: str) -> bool:
    """fuzzylite writes `x is any` as the index 0.99 (and reads it back so)."""
    return abs(abs(float(text)) - 0.99) < 1e-9


def _index_and_hedge(text: str) -> tuple[int, tuple[Hedge, ...]]:
    """A rule index as the Octave toolkit reads it: `-2.2` -> (-2, (VERY,)) (see FIS_HEDGES)."""
    if not re.fullmatch(r"-?(?:\d+\.?\d*|\.\d+)", text, re.ASCII):
        raise ValueError(f"rule index `{text}` is not a number (a term index, `-` negates, "
                         "a fraction is a hedge)")
    value = float(text)
    index = int(abs(value))
    exponent = round(100 * (abs(value) - index)) / 10 if index else 0.0
    if exponent not in FIS_HEDGES:
        raise ValueError(f"rule index `{text}`: a hedge exponent of {exponent:g} is not "
                         "supported: the model carries .05 (somewhat), .2 (very), .3 (extremely), "
                         ".4 (very very)")
    return (-index if value < 0 else index), FIS_HEDGES[exponent]


def _unquote(value: str) -> str:
    return value.strip().strip("'")


def _numbers(value: str) -> list[float] | None:
    match = re.fullmatch(r"\s*\[([^\]]*)\]\s*", value)
    if match is None:
        return None
    values = [parse_number(t) for t in match.group(1).replace(",", " ").split()]
    return values if all(v is not None and math.isfinite(v) for v in values) else None


def read_fis(text: str, path: str = "<string>") -> Model:
    """A MATLAB .fis system as a Model; raises FuzzycError listing what it cannot carry."""
    return _FisReader(text, path).read(text)


# ---------------------------------------------------------------------- export
FIS_WORDS = {field: {v: k for k, v in table.items()} for field, table in SETTINGS.values()}
AREA_METHODS = ops.members(ops.DEFUZZIFIERS, lambda rec: rec.family == "area")
# assumption: MATLAB's documented default number of points evalfis samples a Mamdani output
# range on (NumSamplePoints); not from a paper, used only to say so in a warning.
MATLAB_POINTS = 101
# (TermKind, MATLAB name, the model's params -> MATLAB's parameter order): the reader inverted
# (the shape registry's FIS names and parameter orders: gaussmf [sigma c], gbellmf [a b c],
# sigmf [a c], smf, zmf, pimf as the model's)
FIS_SHAPES = {kind: (shape.fis, shape.fis_params) for kind, shape in SHAPES.items()
              if shape.fis_params is not None}


def write_fis(model: Model, warnings: list[str] | None = None) -> str:
    """The model's rule base as a MATLAB/Octave .fis file; what is left out or evaluated
    differently by MATLAB is appended to `warnings`.  Raises FuzzycError when the rule base
    cannot be said in FIS (see the module docstring for the mapping)."""
    model = one_rule_base(model, "FIS")     # one rule list: blocks merged where exact
    rb = model.rulebase
    notes = left_out(model)
    problems = (unsayable_hedges(model, FIS_HEDGE_WORDS, "FIS") + own_output_choices(model, "FIS")
                + unsayable_functions(model, "FIS", formulas=True, lock=False))
    rows = _fis_rows(rb, problems)
    if np.any(rb.hedges == Hedge.EXTREMELY) or any(
            np.any(p[:, 3] == Hedge.EXTREMELY) for p in rb.conditions.values()):
        notes.append("`extremely` is written `.3`, which the Octave toolkit reads as the "
                     "model does (x^3; the cube root of the strength on a consequent) and "
                     "fuzzylite as its S-curve")
    kind, outputs, methods = _fis_system(model, problems, notes)
    lines = [f"% {' '.join(text.split())}" for text in (model.title, *model.notes) if text]
    lines += ["[System]", f"Name={_quote(model.name, problems)}", f"Type='{kind}'",
              "Version=2.0", f"NumInputs={len(rb.inputs)}", f"NumOutputs={len(outputs)}",
              f"NumRules={len(rows)}",
              *(f"{key}='{word}'" for key, word in methods), ""]
    for section, variables in (("Input", rb.inputs), ("Output", outputs)):
        for n, var in enumerate(variables, start=1):
            lines += [f"[{section}{n}]", f"Name={_quote(var.name, problems)}",
                      f"Range=[{num(var.lo)} {num(var.hi)}]", f"NumMFs={var.n_terms}",
                      *_fis_terms(var, section == "Input", len(rb.inputs), problems, notes), ""]
            if section == "Output":
                _fis_default(var, notes)
    lines.append("[Rules]")
    lines += rows
    return finish(model, "FIS", lines, problems, notes, warnings)


def _fis_system(model: Model, problems: list[str], notes: list[str]):
    """(type, output variables to write, [(key, word)] of the five methods)."""
    rb = model.rulebase
    inf = rb.inference
    method = inf.defuzzifier
    singletons = [bool(np.all(v.kinds == TermKind.SINGLETON)) for v in rb.outputs]
    operators = [("AndMethod", _fis_operator(rb, "and_", Connective.AND, "min", problems, notes)),
                 ("OrMethod", _fis_operator(rb, "or_", Connective.OR, "max", problems, notes))]
    if method in (Defuzzifier.TSUKAMOTO, Defuzzifier.TSUKAMOTO_SUM):
        problems.append("MATLAB's FIS has no Tsukamoto system (fuzzylite's `tsukamoto` type is "
                        "read, not written): write FLL")
    if method == Defuzzifier.GROUPED_SUM:
        problems.append("MATLAB's wtsum sums over the rules; the weighted sum grouped per term "
                        "(pyfuzzylite's WeightedSum with an aggregation) has no FIS word: write "
                        "FLL")
    if method in AREA_METHODS and not any(singletons):
        for v in rb.outputs:
            for name in np.asarray(v.names)[v.kinds == TermKind.SINGLETON]:
                problems.append(f"singleton term `{name}` of `{v.name}` under "
                                f"{method.name.lower()}: MATLAB's Mamdani outputs have no "
                                "constant terms (and a singleton has no area in fuzzyc)")
        notes.append(f"MATLAB evaluates Mamdani outputs on {MATLAB_POINTS} points of the range "
                     f"({FIS_WORDS['defuzzifier'][method]} of the sampled aggregate); fuzzyc "
                     "integrates exactly: MATLAB's numbers differ by that sampling error")
        return "mamdani", rb.outputs, [
            *operators, ("ImpMethod", _fis_method("implication", inf.implication, problems)),
            ("AggMethod", _fis_method("aggregation", inf.aggregation, problems)),
            ("DefuzzMethod", FIS_WORDS["defuzzifier"][method])]
    if method in AREA_METHODS and not all(singletons):
        problems.append(f"{method.name.lower()} over outputs of which some are all singletons "
                        "(a peak ratio in fuzzyc) and some are not: one FIS is Mamdani or "
                        "Sugeno for all its outputs")
    if method not in (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM):
        _check_peak_ratio(model, problems, notes)
    outputs, changed = peaks_instead(model, "FIS")
    notes.extend(changed)
    if (inf.implication, inf.aggregation) != (Implication.PRODUCT, Aggregation.SUM) and \
            method in (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM):
        notes.append(f"implication {inf.implication.name.lower()} and aggregation "
                     f"{inf.aggregation.name.lower()} are written as prod and sum, MATLAB's "
                     "Sugeno defaults (the weighted "
                     f"{'sum' if method == Defuzzifier.WEIGHTED_SUM else 'average'} "
                     "does not depend on them)")
    word = "wtsum" if method == Defuzzifier.WEIGHTED_SUM else "wtaver"
    return "sugeno", outputs, [*operators, ("ImpMethod", "prod"), ("AggMethod", "sum"),
                               ("DefuzzMethod", word)]


def _fis_method(field: str, value, problems: list[str]) -> str:
    """MATLAB's ImpMethod/AggMethod word; one MATLAB lacks (the bounded sum, the Einstein
    norms...) is refused."""
    words = FIS_WORDS[field]
    if value not in words:
        problems.append(f"{field} {value.name.lower()} has no FIS word (MATLAB has "
                        f"{', '.join(words.values())} or a custom function): FIS cannot say it")
        return next(iter(words.values()))
    return words[value]


def _check_peak_ratio(model: Model, problems: list[str], notes: list[str]) -> None:
    """Center of area (or an area method over singletons) = sum_j z_j alpha_j / sum_j alpha_j
    with alpha_j the aggregation of the rules concluding term j; MATLAB's wtaver sums per rule.
    The same when the aggregation is a sum, or when no two rules conclude one term."""
    rb = model.rulebase
    what = rb.inference.defuzzifier.name.lower()
    if rb.inference.aggregation == Aggregation.SUM:
        notes.append(f"{what} with sum aggregation is written as Sugeno wtaver over the "
                     "terms' peaks (the same numbers)")
        return
    shared = []
    for o, v in enumerate(rb.outputs):
        counts = np.bincount(rb.consequents[:, o][rb.consequents[:, o] >= 0],
                             minlength=v.n_terms)
        shared += [f"`{v.names[j]}` of `{v.name}` ({counts[j]} rules)"
                   for j in np.flatnonzero(counts > 1)]
    if shared:
        more = f" and {len(shared) - 3} more" if len(shared) > 3 else ""
        agg = rb.inference.aggregation
        how = "takes the strongest of" if agg == Aggregation.MAX else "combines"
        problems.append(f"{what} with {agg.name.lower()} aggregation {how} the rules that "
                        f"conclude the same term ({', '.join(shared[:3])}{more}); MATLAB's "
                        "wtaver (Sugeno) sums over rules and its Mamdani outputs have no "
                        "peak-based defuzzifier: FIS cannot say it")
    else:
        notes.append(f"{what} with {rb.inference.aggregation.name.lower()} aggregation is "
                     "written as Sugeno wtaver over the "
                     "terms' peaks: the same numbers, as no two rules conclude the same term")


def _fis_operator(rb, field: str, connective: Connective, fallback: str,
                  problems: list[str], notes: list[str]) -> str:
    """MATLAB's word for the and/or operator; one it lacks is refused when a rule with two
    clauses needs it, else written as the fallback with a warning."""
    value = getattr(rb.inference, field)
    words = FIS_WORDS[field]
    if value in words:
        return words[value]
    key = "AndMethod" if connective == Connective.AND else "OrMethod"
    used = (rb.connective == connective) & ((rb.antecedents >= 0).sum(axis=1) > 1)
    if np.any(used):
        problems.append(f"{key} {value.name.lower()} (used by rule "
                        f"{int(np.flatnonzero(used)[0]) + 1}) has no MATLAB word (MATLAB has "
                        f"{', '.join(words.values())})")
    else:
        notes.append(f"{key}: the model's {value.name.lower()} is used by no rule with two "
                     f"clauses; written as {fallback}")
    return fallback


def _fis_terms(var: Variable, is_input: bool, n_inputs: int, problems: list[str],
               notes: list[str]) -> list[str]:
    lines = []
    linear = None if is_input else linear_coefficients(var, n_inputs)
    for t, (name, kind, p) in enumerate(zip(var.names, var.kinds, var.params)):
        kind = TermKind(int(kind))
        a, b, c, d = (float(x) for x in p)
        if kind == TermKind.TRAPEZOID:
            word, values = _fis_trapezoid(var, name, (a, b, c, d), problems, notes)
        elif kind == TermKind.SINGLETON and not is_input:
            word, values = "constant", (a,)
        elif kind == TermKind.LINEAR:   # MATLAB writes the constant last
            word, values = "linear", (*linear[t, 1:], linear[t, 0])
        elif kind == TermKind.FUNCTION:     # fuzzylite's; MATLAB and Octave have none
            lines.append(f"MF{t + 1}={_quote(name, problems)}:'function',"
                         f"[{var.formulas[t].infix()}]")
            notes.append(f"term `{name}` of `{var.name}` is written `function`, fuzzylite's "
                         "word: MATLAB and the Octave toolkit have no such function")
            continue
        elif kind == TermKind.DISCRETE:
            word, values = "discretemf", var.term_numbers(t)
            notes.append(f"term `{name}` of `{var.name}` is written `discretemf`, fuzzylite's "
                         "word: MATLAB and the Octave toolkit have no such function")
        elif kind in (TermKind.SSHAPE, TermKind.ZSHAPE, TermKind.PISHAPE) and (
                a == b or (kind == TermKind.PISHAPE and c == d)):
            # a step: the Octave toolkit refuses smf/zmf/pimf with equal break points, MATLAB
            # puts a degenerate smf's step at the mean, inclusive (the model's is exclusive)
            problems.append(f"term `{name}` of `{var.name}` (`{kind.name.lower()}` with equal "
                            "break points) is a step that FIS cannot say: the Octave toolkit "
                            "refuses it; write it with distinct break points")
            continue
        elif kind in FIS_SHAPES:
            word, order = FIS_SHAPES[kind]
            values = order(a, b, c, d)
        else:
            problems.append(f"term `{name}` of `{var.name}` ({kind.name.lower()}) has no FIS "
                            "membership function")
            continue
        lines.append(f"MF{t + 1}={_quote(name, problems)}:'{word}',"
                     f"[{' '.join(num(x) for x in values)}]")
    return lines


def _fis_trapezoid(var: Variable, name: str, p: tuple, problems: list[str],
                   notes: list[str]) -> tuple[str, tuple]:
    a, b, c, d = p
    if a == b == -math.inf:
        a = b = min(var.lo, c)
    if c == d == math.inf:
        c = d = max(var.hi, b)
    # A vertical edge at or beyond the range's end leans outward by the range's width: the same
    # membership on the range, and the Octave toolkit refuses vertical edges (a = b, c = d).
    if a == b <= var.lo:
        a = b - (var.hi - var.lo)
    if c == d >= var.hi:
        d = c + (var.hi - var.lo)
    word, values = ("trimf", (a, b, d)) if b == c else ("trapmf", (a, b, c, d))
    if not all(map(math.isfinite, (a, b, c, d))):
        problems.append(f"term `{name}` of `{var.name}` ({', '.join(map(num, p))}) has no FIS "
                        "membership function")
    elif (a, b, c, d) != p:
        notes.append(f"`{name}` of `{var.name}` is written as {word} "
                     f"[{' '.join(map(num, values))}] (FIS has no infinite break points, the "
                     "Octave toolkit no vertical edges): the same on "
                     f"[{num(var.lo)}, {num(var.hi)}], not beyond it")
    return word, values


def _fis_default(var: Variable, notes: list[str]) -> None:
    middle = 0.5 * (var.lo + var.hi)
    if var.default != middle:
        notes.append(f"`{var.name}`'s default {num(var.default)} (when no rule fires): FIS has "
                     f"none; MATLAB gives the middle of the range, {num(middle)}")


def _fis_rows(rb, problems: list[str]) -> list[str]:
    """The rule rows: a flat rule is one row; the rules the reader made of a row with hedged
    consequents (consecutive, the same condition, each one's earlier-conclusion steps the
    hedges said before it) are that row again; any other clause program is refused."""
    rows, nested, r = [], [], 0
    while r < rb.n_rules:
        if r not in rb.conditions:
            rows.append(_fis_rule(rb, r, problems))
            r += 1
            continue
        first = _program_row(rb, r)
        if first is None or not all(own for own, _ in first[2]):   # a row starts plain
            nested.append(r)
            r += 1
            continue
        ins, connective, steps = first
        outs = {o: _index(int(t) + 1, steps) for o, t in enumerate(rb.consequents[r]) if t >= 0}
        said = [h for own, h in steps if own]
        r += 1
        while r < rb.n_rules and r in rb.conditions and rb.weights[r] == rb.weights[r - 1]:
            more = _program_row(rb, r)
            if more is None or more[:2] != (ins, connective) or \
                    not said or [h for own, h in more[2] if not own] != said or \
                    min(np.flatnonzero(rb.consequents[r] >= 0)) <= max(outs):
                break
            outs |= {o: _index(int(t) + 1, [s for s in more[2] if s[0]])
                     for o, t in enumerate(rb.consequents[r]) if t >= 0}
            said += [h for own, h in more[2] if own]
            r += 1
        row = [outs.get(o, "0") for o in range(len(rb.outputs))]
        rows.append(f"{' '.join(ins)}, {' '.join(row)} ({num(rb.weights[r - 1])}) : "
                    f"{connective}")
    if nested:
        more = f" and {len(nested) - 1} more" if len(nested) > 1 else ""
        problems.append(f"rule {nested[0] + 1} `{rb.describe_rule(nested[0])}`{more} has a "
                        "nested condition; a FIS rule row is one connective over one clause "
                        "per input")
    return rows


def _program_row(rb, r: int) -> tuple[list[str], int, list[tuple[bool, int]]] | None:
    """(input indices as text, connective 1|2, [(own, hedge)] CONCLUDED steps) of rule r's
    clause program when it is a FIS row: clauses (each with a FIS hedge, then maybe `not`)
    joined by one connective, then the steps; else None."""
    ins, connective, steps = ["0"] * len(rb.inputs), None, []
    program = rb.conditions[r].tolist()
    k = 0
    while k < len(program):
        op, i, t, h = program[k]
        k += 1
        if op == CondOp.CONCLUDED:
            steps.append((bool(t), h))
        elif steps:
            return None
        elif op == CondOp.CLAUSE:
            hedges = [h] if h else []
            while k < len(program) and program[k][0] == CondOp.HEDGE:
                hedges.append(program[k][3])
                k += 1
            negated = k < len(program) and program[k][0] == CondOp.NOT
            k += negated
            if t < 0 or ins[i] != "0" or tuple(hedges) not in FIS_FRACTIONS:
                return None
            ins[i] = _index(-(t + 1) if negated else t + 1, [(True, h) for h in hedges])
        elif op in (CondOp.AND, CondOp.OR) and connective in (None, op):
            connective = op
        else:
            return None
    return ins, 2 if connective == CondOp.OR else 1, steps


def _index(code: int, steps) -> str:
    """A rule index with the fraction of its own hedges (`-2` and very: `-2.2`; a hedge FIS
    has no fraction for is refused by unsayable_hedges)."""
    return f"{code}{FIS_FRACTIONS.get(tuple(h for own, h in steps if own), '')}"


def _fis_rule(rb, r: int, problems: list[str]) -> str:
    """`i1 i2, o1 (w) : c`: 1-based term indices, 0 = any, negative = NOT, a fraction the
    hedge; c 1 = and, 2 = or."""
    ins = ["0" if t < 0 else _index(-(t + 1) if neg else t + 1, [(True, h)] if h else [])
           for t, neg, h in zip(rb.antecedents[r].tolist(), rb.negated[r].tolist(),
                                rb.hedges[r].tolist())]
    outs = [t + 1 if t >= 0 else 0 for t in rb.consequents[r].tolist()]
    if all(i == "0" for i in ins) or not any(outs):
        problems.append(f"rule {r + 1} has no "
                        f"{'clause' if all(i == '0' for i in ins) else 'conclusion'}, "
                        "which a FIS rule row cannot say")
    if not 0.0 <= rb.weights[r] <= 1.0:
        problems.append(f"rule {r + 1}'s weight {num(rb.weights[r])} lies outside [0, 1]")
    connective = 2 if rb.connective[r] == Connective.OR else 1
    return (f"{' '.join(ins)}, {' '.join(map(str, outs))} "
            f"({num(rb.weights[r])}) : {connective}")


def _quote(name: str, problems: list[str]) -> str:
    problems += name_problems([name], "FIS", FIS_NAME, "any text without ', % and line breaks "
                                                       "or other control characters")
    return f"'{name}'"
