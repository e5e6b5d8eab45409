"""What the importers share: variables and rules collected from a file -> the Model that the .fz
front end would build for the same rule base (raw inputs feeding the rule base directly, one
DIRECT output per rule-base output, rules with the same premise merged as the builder does).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import sympy

from ..language.builder import RuleSpec, assemble_rulebase, merge_rules
from ..errors import Reporter, suggest
from ..engine.formula import Formula
from ..engine.membership import monotonic
from ..semantics.shape_functions import discrete_problem
from ..semantics.shapes import plain_words
from ..semantics.model import (Aggregation, CondOp, Defuzzifier, Inference, Model, Output, OutputKind, Signal,
                     SourceLoc, TermKind, Variable, chain_output_names)

INF = math.inf
# .fz needs the signal-chain output named apart from the rule-base output: `y_out`, or `y_out2`
# when the file has a `y_out` of its own (model.chain_output_names)
OUTPUT_SUFFIX = "_out"


@dataclass
class TermSpec:
    name: str
    kind: TermKind
    params: tuple[float, float, float, float]
    loc: SourceLoc | None = None
    # LINEAR only: as fuzzylite and MATLAB write them, one per input then the constant (which
    # fuzzylite lets out); resolved once the number of inputs is known.
    coefficients: tuple[float, ...] | None = None
    points: tuple[tuple[float, float], ...] | None = None     # DISCRETE only
    formula: Formula | None = None                            # FUNCTION only
    formula_loc: SourceLoc | None = None                      # where its text starts


@dataclass
class VarSpec:
    """A linguistic variable as read from a file, before it becomes a `Variable`."""
    name: str
    loc: SourceLoc | None
    lo: float | None = None
    hi: float | None = None
    terms: list[TermSpec] = field(default_factory=list)
    default: float = 0.0
    lock_previous: bool = False

    def term_names(self) -> list[str]:
        return [t.name for t in self.terms]

    def add(self, term: TermSpec, rep: Reporter) -> None:
        if term.name in self.term_names():
            rep.error(term.loc, f"term `{term.name}` is already defined for `{self.name}`; "
                                "rename one of them")
        else:
            self.terms.append(term)

    def term_index(self, name: str, loc: SourceLoc | None, rep: Reporter) -> int | None:
        if name in self.term_names():
            return self.term_names().index(name)
        rep.error(loc, f"`{self.name}` has no term `{name}`: {suggest(name, self.term_names())}")
        return None

    def range_from_terms(self) -> tuple[float, float] | None:
        """The span of the terms' finite break points: for formats where a range is optional."""
        points = [p for t in self.terms
                  for p in (t.params if t.kind == TermKind.TRAPEZOID else
                            [x for x, _ in t.points] if t.kind == TermKind.DISCRETE else
                            () if t.kind in (TermKind.LINEAR, TermKind.FUNCTION) else
                            t.params[:1])
                  if math.isfinite(p)]
        return (min(points), max(points)) if points and min(points) < max(points) else None


def nan_default(var: VarSpec, notes: list[str]) -> float:
    """fuzzylite's `default: nan` (NaN when no rule fires) as a number the model can carry: 0,
    or the range's low end when 0 is outside the range; said in `notes`.  The fuzzylite
    semantics (tool_semantics) give NaN there again."""
    lo, hi = var.lo, var.hi
    value = 0.0 if lo is None or lo <= 0.0 <= hi else lo
    notes.append(f"`{var.name}` default nan (NaN when no rule fires): the model needs a "
                 f"number, took {value:g}")
    return value


def shape(kind: TermKind, *params: float) -> tuple[TermKind, tuple[float, float, float, float]]:
    padded = tuple(float(p) for p in params) + (0.0,) * (4 - len(params))
    return kind, padded


# The shapes every format writes as NAME p1 p2 ... in the model's own parameter order, with
# the condition that keeps them well defined (the shape registry's plain words).
PLAIN_SHAPES = {shape.kind: (word.arity, word.valid) for shape, word in plain_words().values()}
# what each plain shape's parameters must satisfy, from its .fz usage ("pishape(a, b, c, d)
# with a < b and c < d" -> ("a b c d", "a < b and c < d")); the importers' order is the same
PLAIN_NEEDS = {shape.kind: (word.usage.split("(", 1)[1].split(")", 1)[0].replace(",", ""),
                            word.usage.split(" with ", 1)[1])
               for shape, word in plain_words().values() if " with " in word.usage}


def degenerate(word: str, values, needs: str | None, brackets: str = "()") -> str:
    """An importer's message for a shape whose numbers make no membership function, with
    what they must satisfy in the tool's own words: `degenerate Triangle (3 2 1): Triangle
    a b c needs a <= b <= c with a < c` (FIS writes its numbers in [])."""
    shown = brackets[0] + " ".join(f"{p:g}" for p in values) + brackets[1]
    return f"degenerate {word} {shown}" + (f": {word} {needs}" if needs else "")


def plain_needs(kind: TermKind) -> str | None:
    """`a b c d needs a < b and c < d` for a plain shape, None where its usage says none."""
    if kind not in PLAIN_NEEDS:
        return None
    params, condition = PLAIN_NEEDS[kind]
    return f"{params} needs {condition}"


def plain_shape_or_none(kind: TermKind, values: list[float]):
    """One of PLAIN_SHAPES from its parameters, or None when they are degenerate."""
    arity, valid = PLAIN_SHAPES[kind]
    if len(values) == arity and all(map(math.isfinite, values)) and valid(values):
        return shape(kind, *values)
    return None


def linear_row(coefficients: tuple[float, ...], n_inputs: int) -> np.ndarray | None:
    """fuzzylite/MATLAB order (c1..cI [c0]) -> the model's (c0, c1..cI), or None if the count
    does not fit the inputs."""
    if len(coefficients) not in (n_inputs, n_inputs + 1):
        return None
    constant = coefficients[n_inputs] if len(coefficients) > n_inputs else 0.0
    return np.array([constant, *coefficients[:n_inputs]], dtype=float)


def trapezoid_or_none(a: float, b: float, c: float, d: float):
    """A trapezoid (a <= b <= c <= d, a < d; infinite ends make shoulders), or None."""
    if a <= b <= c <= d and a < d:
        return shape(TermKind.TRAPEZOID, a, b, c, d)
    return None


def discrete_or_none(values: list[float], loc: SourceLoc | None, rep: Reporter):
    """A DISCRETE term from x1 y1 x2 y2 ..., as the importers' shape tuple, or None after
    reporting why not."""
    problem = discrete_problem(values)
    if problem:
        rep.error(loc, problem)
        return None
    return TermKind.DISCRETE, (0.0,) * 4, None, tuple(zip(values[0::2], values[1::2]))


def tsukamoto_terms(variables) -> bool:
    """Whether every term of these output variables is monotonic (and some is more than a
    singleton): what fuzzylite's weighted average then computes is Tsukamoto's method."""
    terms = [t for var in variables for t in var.terms]
    return any(t.kind != TermKind.SINGLETON for t in terms) and \
        all(monotonic(t.kind, t.params) for t in terms)


@dataclass
class Collected:
    """Everything an importer read; `model()` turns it into the Model."""
    rep: Reporter
    name: str
    title: str = ""
    inputs: dict[str, VarSpec] = field(default_factory=dict)
    outputs: dict[str, VarSpec] = field(default_factory=dict)
    rules: list[RuleSpec] = field(default_factory=list)
    inference: Inference = field(default_factory=Inference)
    notes: list[str] = field(default_factory=list)
    output_choices: dict[str, tuple[Aggregation, Defuzzifier]] = field(default_factory=dict)
    # several rule blocks (name, inference, rules), each concluding on its own outputs; None:
    # one rule base of `rules` with `inference`
    blocks: list[tuple[str, Inference, list[RuleSpec]]] | None = None

    def declare(self, var: VarSpec, is_input: bool) -> VarSpec:
        if var.name in self.inputs or var.name in self.outputs:
            self.rep.error(var.loc, f"variable `{var.name}` is declared twice; "
                                    "rename one of them")
            return var
        (self.inputs if is_input else self.outputs)[var.name] = var
        return var

    def check_ranges(self) -> None:
        for var in (*self.inputs.values(), *self.outputs.values()):
            if var.lo is None:
                span = var.range_from_terms()
                if span is None:
                    self.rep.error(var.loc, f"`{var.name}` has no range and its terms do not "
                                            "give one: declare a range")
                    continue
                var.lo, var.hi = span
                self.notes.append(f"`{var.name}` had no range: took [{span[0]:g}, {span[1]:g}] "
                                  "from its terms' break points")
            elif var.lo == var.hi and var.terms and all(
                    t.kind in (TermKind.LINEAR, TermKind.SINGLETON) for t in var.terms) \
                    and var.name in self.outputs and math.isfinite(var.lo):
                # MATLAB's Sugeno outputs may say [0 0]: their range is never used there
                self.notes.append(f"`{var.name}` has the empty range [{var.lo:g}, {var.hi:g}]: "
                                  "its Takagi-Sugeno values are not clamped to it by the rule "
                                  "base, but the controller output saturates to it")
            elif not (math.isfinite(var.lo) and math.isfinite(var.hi) and var.lo < var.hi):
                self.rep.error(var.loc, f"`{var.name}` needs a finite range lo < hi, got "
                                        f"[{var.lo:g}, {var.hi:g}]")
            if not var.terms:   # legal in fuzzylite and MATLAB: read by linear consequents
                self.notes.append(f"`{var.name}` has no terms")

    def model(self, path: str, text: str) -> Model:
        self.check_ranges()
        self._check_linear_terms()
        # a controller of nothing: every command would trip over it (said only when nothing
        # else is wrong: a broken declaration is not a missing one)
        missing = [kind for kind, declared in (("input", self.inputs), ("output", self.outputs))
                   if not declared]
        for kind in missing if not self.rep.diagnostics else []:
            self.rep.error(self.rep.loc(1, 1), f"the file declares no {kind} variable; "
                                                  "declare one")
        self.rep.raise_if_any()
        n_inputs = len(self.inputs)
        inputs = [_variable(v, True, n_inputs) for v in self.inputs.values()]
        outputs = [_variable(v, False, n_inputs) for v in self.outputs.values()]
        blocks, parts = [], self._chained(self.blocks or [("", self.inference, self.rules)])
        self.rep.raise_if_any()
        owner = {}      # an output no rule concludes stays with the first block (its default)
        for k, (_, _, rules) in enumerate(parts):
            owner.update({out: k for r in rules for out in r.conclusions if out not in owner})
        by_name = {v.name: v for v in outputs}
        for k, (name, inference, rules) in enumerate(parts):
            mine = [v for v in outputs if owner.get(v.name, 0) == k]
            # every block reads every input (a linear term's coefficients run over them all),
            # then the outputs of earlier blocks its rules read
            read = [replace(by_name[n], learnable=None) for n in by_name if n in _reads(rules)]
            rb = assemble_rulebase(inputs + read, mine, merge_rules(rules), inference)
            rb.name = name
            rb.output_choices = {v.name: self.output_choices[v.name] for v in mine
                                 if v.name in self.output_choices}
            blocks.append(rb)
        from .functions import check_reads       # functions builds on TermSpec, from here
        for rb in blocks:
            check_reads(rb, {**self.inputs, **self.outputs}, self.rep, self.inputs)
        self.rep.raise_if_any()
        return Model(
            name=self.name, blocks=blocks, title=self.title or f"imported from {path}",
            signals=[Signal(v.name, v.lo, v.hi, loc=v.loc) for v in inputs],
            outputs=[Output(out, OutputKind.DIRECT, sympy.Symbol(v.name),
                            v.lo, v.hi, init=v.lo, loc=v.loc)
                     for out, v in zip(chain_output_names([v.name for v in outputs],
                                                          [*self.inputs, *self.outputs]),
                                       outputs)],
            source_path=path, source_text=text, notes=list(self.notes))


    def set_inference(self, names: list[str], operators: list[Inference], rule_block: list[int],
                      choices: dict[str, tuple[Aggregation, Defuzzifier]]) -> None:
        """The rule blocks' operators (`rule_block`: each rule's block) and the outputs'
        (aggregation, defuzzifier) as the model's inference: one rule base when the blocks
        agree, else one per block, each concluding on its own outputs; an output whose choices
        differ from the first output's gets its own (`output_choices`)."""
        first = next(iter(choices.values()), (Inference().aggregation, Inference().defuzzifier))
        self.output_choices = {name: c for name, c in choices.items() if c != first}
        self.inference = replace(operators[0], aggregation=first[0], defuzzifier=first[1])
        if all(op == operators[0] for op in operators):
            return
        owner: dict[str, int] = {}
        for rule, k in zip(self.rules, rule_block):
            for name in rule.conclusions:
                if owner.setdefault(name, k) != k:
                    self.rep.error(rule.loc, f"`{name}` is concluded in rule blocks "
                                             f"`{names[owner[name]]}` and `{names[k]}`, whose "
                                             "operators differ: the model aggregates an output "
                                             "within one block")
        self.blocks = [(name, replace(op, aggregation=first[0], defuzzifier=first[1]),
                        [r for r, b in zip(self.rules, rule_block) if b == k])
                       for k, (name, op) in enumerate(zip(names, operators))]

    def _chained(self, parts: list) -> list:
        """The rule blocks with the rules that read outputs moved to blocks after those
        concluding them (fuzzylite's chained engines: one block, rules in order): a rule's stage
        is one past the stages of the outputs it reads, and an output's stage that of its
        latest rule, so every output is written by one block, read by later ones only."""
        rules = [(k, r) for k, (_, _, rs) in enumerate(parts) for r in rs]
        if not any(_reads([r]) & set(self.outputs) for _, r in rules):
            return parts
        for n, (_, rule) in enumerate(rules):
            early = [r for _, r in rules[:n] if _reads([r]) & set(rule.conclusions)]
            if early:
                read = sorted(_reads(early[:1]) & set(rule.conclusions))[0]
                self.rep.error(early[0].loc, f"this rule reads `{read}` before the rule at "
                                             f"{rule.loc} concludes it: the model reads an "
                                             "output once every rule concluding it has fired "
                                             "(fuzzylite would read it half aggregated)")
                return parts
        stage: dict[int, int] = {}
        output_stage: dict[str, int] = {}
        for n, (_, rule) in enumerate(rules):
            stage[n] = max([output_stage.get(o, 0) for o in rule.conclusions] +
                           [output_stage[o] + 1 for o in _reads([rule]) if o in output_stage],
                           default=0)
            for o in rule.conclusions:
                if output_stage.get(o, stage[n]) < stage[n]:
                    self.rep.error(rule.loc, f"`{o}` is concluded by rules of different stages "
                                             "of a chain (this one reads outputs): conclude it "
                                             "in one block")
                output_stage[o] = stage[n]
        out = []
        for s in range(max(stage.values()) + 1):
            for k, (name, inference, _) in enumerate(parts):
                mine = [r for n, (b, r) in enumerate(rules) if b == k and stage[n] == s]
                if mine or s == 0:
                    out.append((f"{name or 'rules'}{'_' + str(s + 1) if s else ''}", inference,
                                mine))
        return out

    def _check_linear_terms(self) -> None:
        n_inputs = len(self.inputs)
        for var in self.inputs.values():
            for term in var.terms:
                if term.kind == TermKind.LINEAR:
                    self.rep.error(term.loc, f"a Linear term is a Takagi-Sugeno consequent: "
                                             f"input `{var.name}` cannot have one")
        for var in self.outputs.values():
            for term in var.terms:
                if term.kind == TermKind.LINEAR and \
                        linear_row(term.coefficients, n_inputs) is None:
                    self.rep.error(term.loc, f"Linear `{term.name}` has "
                                             f"{len(term.coefficients)} coefficients: give one "
                                             f"per input ({n_inputs}) and optionally a constant")


def _reads(rules: list[RuleSpec]) -> set[str]:
    """The variables these rules' conditions read."""
    return {name for r in rules
            for name in (r.clauses if r.program is None else
                         [step[1] for step in r.program if step[0] == CondOp.CLAUSE])}


def _variable(v: VarSpec, is_input: bool, n_inputs: int) -> Variable:
    """The model's Variable; linear rows that do not fit the (T, 4) params go to coefficients."""
    n = len(v.terms)
    params = np.array([t.params for t in v.terms], dtype=float).reshape(n, 4)
    coefficients = {}
    points = {t: np.array(term.points, dtype=float) for t, term in enumerate(v.terms)
              if term.kind == TermKind.DISCRETE}
    for t, term in enumerate(v.terms):
        if term.kind == TermKind.LINEAR:
            row = linear_row(term.coefficients, n_inputs)
            if len(row) <= 4:
                params[t, :len(row)] = row
            else:
                coefficients[t] = row
    return Variable(
        name=v.name, lo=float(v.lo), hi=float(v.hi), names=v.term_names(),
        kinds=np.array([int(t.kind) for t in v.terms], dtype=np.int64), params=params,
        default=float(v.default), learnable=None if is_input else np.zeros(n, dtype=bool),
        loc=v.loc, term_locs=[t.loc for t in v.terms], coefficients=coefficients or None,
        points=points or None, lock_previous=v.lock_previous,
        formulas={t: term.formula for t, term in enumerate(v.terms)
                  if term.kind == TermKind.FUNCTION} or None)
