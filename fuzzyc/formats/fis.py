"""MATLAB/Octave Fuzzy Logic Toolbox text files (.fis): import.

The format is line-oriented (`[Section]` headers, `Key=value` lines, numeric rule rows), so it is
read line by line with a regular expression per line kind, every value keeping its column.
Mapping (exact unless said): trimf, trapmf -> TRAPEZOID; gaussmf [sigma c] -> GAUSSIAN (c, sigma);
gbellmf [a b c] -> BELL (c, a, b); sigmf [a c] -> SIGMOID (c, a); smf, zmf, pimf -> SSHAPE,
ZSHAPE, PISHAPE; constant -> SINGLETON; linear [c1 .. cn c0] -> LINEAR (sugeno outputs).
min/prod, max/probor, implication min/prod, aggregation max/sum; centroid, bisector, mom,
wtaver, wtsum.  MATLAB evaluates Mamdani outputs on 101 points of the range; the model
integrates exactly.  Rules: `i1 i2, o1 (w) : c` with 0 = any, a negative index = NOT,
c = 1 (and) or 2 (or).  Not carried, reported: other MF types (dsigmf, psigmf, gauss2mf),
som/lom, probor aggregation, custom functions, negated consequents.
"""
from __future__ import annotations

import math
import re

from ..builder import RuleSpec
from ..errors import Reporter
from ..model import (Aggregation, Connective, Defuzzifier, Hedge, Implication, Model, SNorm,
                     SourceLoc, TermKind, TNorm)
from .common import Collected, TermSpec, VarSpec, plain_shape_or_none, shape, trapezoid_or_none

SECTION = re.compile(r"\s*\[(\w+?)(\d*)\]\s*$")
KEY_VALUE = re.compile(r"\s*(\w+)\s*=\s*(.*?)\s*$")
MF = re.compile(r"'([^']*)'\s*:\s*'([^']*)'\s*,\s*\[([^\]]*)\]\s*$")
RULE = re.compile(r"\s*([-\d.\s]+?)\s*,\s*([-\d.\s]+?)\s*\(\s*([-+\d.eE]+)\s*\)\s*:\s*(\d+)\s*$")
SETTINGS = {
    "AndMethod": ("and_", {"min": TNorm.MIN, "prod": TNorm.PRODUCT}),
    "OrMethod": ("or_", {"max": SNorm.MAX, "probor": SNorm.PROBSUM}),
    "ImpMethod": ("implication", {"min": Implication.MIN, "prod": Implication.PRODUCT}),
    "AggMethod": ("aggregation", {"max": Aggregation.MAX, "sum": Aggregation.SUM}),
    "DefuzzMethod": ("defuzzifier", {"centroid": Defuzzifier.CENTROID,
                                     "bisector": Defuzzifier.BISECTOR,
                                     "mom": Defuzzifier.MEAN_OF_MAXIMUM,
                                     "wtaver": Defuzzifier.WEIGHTED_AVERAGE,
                                     "wtsum": Defuzzifier.WEIGHTED_SUM}),
}
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
        self.pending_rules: list[tuple[int, str]] = []

    def read(self, text: str) -> Model:
        for number, line in enumerate(text.splitlines(), start=1):
            body = line.split("%", 1)[0]
            if body.strip():
                self._line(number, body)
        for is_input, var in self.variables:
            self.got.declare(var, is_input)
        for number, body in self.pending_rules:
            self._rule(number, body)
        self._check_sugeno()
        return self.got.model(self.path, text)

    def _check_sugeno(self) -> None:
        weighted = self.got.inference.defuzzifier in (Defuzzifier.WEIGHTED_AVERAGE,
                                                      Defuzzifier.WEIGHTED_SUM)
        if weighted != (self.type == "sugeno"):
            self.rep.error(self.rep.loc(1, 1), f"a {self.type} system cannot use "
                                               f"{self.got.inference.defuzzifier.name.lower()}")
        for var in self.got.outputs.values():
            for term in var.terms:
                if (term.kind in (TermKind.SINGLETON, TermKind.LINEAR)) != \
                        (self.type == "sugeno"):
                    self.rep.error(term.loc, f"`{term.name}`: constant output terms belong to "
                                             "sugeno systems, and only they")

    def _line(self, number: int, body: str) -> None:
        section = SECTION.match(body)
        if section:
            kind = section.group(1)
            if kind not in ("System", "Input", "Output", "Rules"):
                self.rep.error(self.rep.loc(number, 1), f"unknown section [{kind}]")
                kind = None
            self.section = kind
            if kind in ("Input", "Output"):
                self.var = VarSpec(f"{kind.lower()}{section.group(2)}", self.rep.loc(number, 1))
                self.variables.append((kind == "Input", self.var))
            return
        if self.section is None:
            self.rep.error(self.rep.loc(number, 1), "text before the first [Section]")
        elif self.section == "Rules":
            self.pending_rules.append((number, body))
        else:
            match = KEY_VALUE.match(body)
            if match is None:
                self.rep.error(self.rep.loc(number, 1), "expected `Key=value`")
                return
            key, value = match.groups()
            loc = self.rep.loc(number, match.start(2) + 1)
            if self.section == "System":
                self._system(key, value, loc, self.rep.loc(number, match.start(1) + 1))
            else:
                self._variable(key, value, loc, self.rep.loc(number, match.start(1) + 1))

    def _system(self, key: str, value: str, loc: SourceLoc, key_loc: SourceLoc) -> None:
        if key not in SYSTEM_KEYS:
            self.rep.error(key_loc, f"unknown key `{key}` in [System]")
        elif key == "Name":
            self.got.name = re.sub(r"\W", "_", _unquote(value))
        elif key == "Type":
            self.type = _unquote(value).lower()
            if self.type not in ("mamdani", "sugeno"):
                self.rep.error(loc, f"type `{self.type}` is not supported: mamdani or sugeno")
        elif key in SETTINGS:
            field, table = SETTINGS[key]
            word = _unquote(value)
            if word not in table:
                self.rep.error(loc, f"{key} `{word}` is not supported: the model has "
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
        elif re.fullmatch(r"MF\d+", key):
            self._mf(value, loc)
        elif key not in VARIABLE_KEYS:
            self.rep.error(key_loc, f"unknown key `{key}` in [{self.section}]")

    def _mf(self, value: str, loc: SourceLoc) -> None:
        match = MF.match(value)
        numbers = _numbers(f"[{match.group(3)}]") if match else None
        if match is None or numbers is None:
            self.rep.error(loc, "expected MFn='name':'type',[parameters]")
            return
        name, kind = match.group(1), match.group(2)
        n_inputs = sum(is_input for is_input, _ in self.variables)   # inputs come first
        arity = {"trimf": 3, "trapmf": 4, "gaussmf": 2, "gbellmf": 3, "sigmf": 2, "constant": 1,
                 "smf": 2, "zmf": 2, "pimf": 4, "linear": n_inputs + 1}
        if kind not in arity:
            self.rep.error(loc, f"membership function `{kind}` is not supported: the model "
                                "carries " + ", ".join(arity))
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
                "smf": lambda: plain_shape_or_none(TermKind.SSHAPE, v),
                "zmf": lambda: plain_shape_or_none(TermKind.ZSHAPE, v),
                "pimf": lambda: plain_shape_or_none(TermKind.PISHAPE, v)}[kind]()
        if made is None:
            self.rep.error(loc, f"degenerate {kind} [{' '.join(f'{p:g}' for p in v)}]")
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
            codes = [int(t) for t in ins + outs]
        except ValueError:
            self.rep.error(loc, "fractional indices (hedges) are not supported: whole numbers only")
            return
        clauses, conclusions = {}, {}
        for var, code in zip(inputs, codes[:len(ins)]):
            if code != 0:
                clauses[var.name] = (abs(code) - 1, code < 0, Hedge.NONE)
        for var, code in zip(outputs, codes[len(ins):]):
            if code < 0:
                self.rep.error(loc, f"a negated consequent (`{code}` for {var.name}) is not "
                                    "supported")
                return
            if code != 0:
                conclusions[var.name] = code - 1
        if not all(self._in_range(var, abs(code), loc) for var, code in zip(
                inputs + outputs, codes) if code != 0):
            return
        weight = float(match.group(3))
        connective = int(match.group(4))
        if not 0.0 <= weight <= 1.0 or connective not in (1, 2):
            self.rep.error(loc, "the weight lies in [0, 1] and the connective is 1 (and) or 2 (or)")
            return
        if not clauses or not conclusions:
            self.rep.error(loc, "a rule needs at least one input and one output index")
            return
        self.got.rules.append(RuleSpec(clauses, Connective.AND if connective == 1 else Connective.OR,
                                    conclusions, weight, loc, f"{self.path}:{number}"))

    def _in_range(self, var: VarSpec, index: int, loc: SourceLoc) -> bool:
        if index > len(var.terms):
            self.rep.error(loc, f"`{var.name}` has {len(var.terms)} terms, no term {index}")
            return False
        return True


def _unquote(value: str) -> str:
    return value.strip().strip("'")


def _numbers(value: str) -> list[float] | None:
    match = re.fullmatch(r"\s*\[([^\]]*)\]\s*", value)
    if match is None:
        return None
    try:
        values = [float(t) for t in match.group(1).replace(",", " ").split()]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


def read_fis(text: str, path: str = "<string>") -> Model:
    """A MATLAB .fis system as a Model; raises FuzzycError listing what it cannot carry."""
    return _FisReader(text, path).read(text)
