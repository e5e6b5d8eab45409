"""The model (IR): the one representation every front end produces and every back end reads.

It is deliberately plain: per variable the term kinds and parameters as arrays, the rules as
integer matrices, the inference choices as enums, the signal chain as a flat program of sympy
expressions. Nothing here evaluates anything; `fuzzyc.engine.inference` defines what a model *means*.

Semantics in one place (the engine implements exactly this; every back end is tested against it):

Membership of a term at x (params padded to 4 with 0):
  TRAPEZOID (a, b, c, d):  rise = 1 if x >= b, (x-a)/(b-a) if a < x < b, else 0
                            fall = 1 if x <= c, (d-x)/(d-c) if c < x < d, else 0
                            mu = min(rise, fall).  A triangle is (a, b, b, c).  A shoulder uses
                            a = b = -inf (left, 1 below c) or c = d = +inf (right, 1 above b).
  GAUSSIAN  (mean, sigma):  exp(-(x-mean)^2 / (2 sigma^2))
  BELL      (center, width, slope): 1 / (1 + |(x-center)/width|^(2 slope))   (MATLAB gbellmf)
  SIGMOID   (center, slope): 1 / (1 + exp(-slope (x-center)))
  SINGLETON (value):        1 if x == value else 0; as an output term, a point mass at value.
  SSHAPE    (s, e):  0 if x <= s; 2((x-s)/(e-s))^2 if x <= (s+e)/2; 1 - 2((x-e)/(e-s))^2 if x < e;
                     else 1.  ZSHAPE (s, e) = the mirror: 1 if x <= s; 1 - 2((x-s)/(e-s))^2 if
                     x < (s+e)/2; 2((x-e)/(e-s))^2 if x < e; else 0.  (MATLAB smf / zmf.)
  PISHAPE   (a, b, c, d):  SSHAPE(a, b)(x) * ZSHAPE(c, d)(x)   (MATLAB pimf)
  SPIKE     (center, width):  exp(-|10 (x-center) / width|)
  COSINE    (center, width):  (1 + cos(2 pi (x-center) / width)) / 2 if |x-center| <= width/2,
                     else 0
  CONCAVE   (i, e):  i <= e: (e-i)/(2e-i-x) if x < e else 1;  i > e: (i-e)/(i-2e+x) if x > e
                     else 1   (fuzzylite's inflection/end concave edge)
  SIGMOID_DIFFERENCE (left, rising, falling, right): |sig(left, rising) - sig(right, falling)|
                     with sig(c, s) = 1 / (1 + exp(-s (x-c)))   (fuzzylite; MATLAB dsigmf)
  SIGMOID_PRODUCT (left, rising, falling, right): sig(left, rising) * sig(right, falling)
                     (fuzzylite; MATLAB psigmf)
  GAUSSIAN_PRODUCT (mean_a, sigma_a, mean_b, sigma_b): g_a * g_b, g_a = GAUSSIAN(mean_a,
                     sigma_a) if x < mean_a else 1, g_b = GAUSSIAN(mean_b, sigma_b) if x > mean_b
                     else 1   (fuzzylite; MATLAB gauss2mf)
  BINARY    (start, direction): 1 if (direction > start and x >= start) or (direction < start
                     and x <= start), else 0   (fuzzylite)
  SEMI_ELLIPSE (start, end): sqrt(r^2 - (x-c)^2) / r on [s, e] (s = min, e = max of the two,
                     r = (e-s)/2, c = s + r), else 0   (fuzzylite 7+)
  ARC       (start, end): a quarter circle centred at (end, 0) rising from start to end:
                     r = end - start; sqrt(r^2 - (x-end)^2) / |r| between start and end, 1 beyond
                     end, 0 before start   (fuzzylite 7+)
  DISCRETE  points (x_1, y_1) .. (x_K, y_K), x ascending, in Variable.points[term] (params
                     unused): linear between the points, y_1 before x_1, y_K after x_K (fuzzylite's
                     Discrete, MATLAB discretemf, an IEC 61131-7 FCL point list).
  LINEAR    (c0, c1, c2, c3): an output term only, for WEIGHTED_AVERAGE / WEIGHTED_SUM
                     (first-order Takagi-Sugeno): z = c0 + sum_i c_{i+1} x_i over the rule base's
                     inputs in order; with more than 3 inputs the row is in
                     Variable.coefficients[term] (c0, c1, ..., c_I) and params are ignored.
                     As a membership it is 0 everywhere (it has no shape).  It reads the
                     inputs clamped to their ranges (a local linear model of the range: past
                     it the nearest edge holds, so z is finite for every input).
  FUNCTION  a formula (Variable.formulas[term], fuzzyc.engine.formula: a parse tree, params unused):
                     fuzzylite's Function.  On an input, or an output under an integral
                     defuzzifier, its membership at x is the formula of x alone (a
                     non-finite value is membership 0).  On a Takagi-Sugeno output
                     (WEIGHTED_AVERAGE / WEIGHTED_SUM) its value z is the formula of the rule
                     base's inputs and of the outputs before it (their values in the same
                     evaluation: fuzzylite defuzzifies its outputs in order); where z is not
                     finite (0/0) the term has no value: its rules count as not fired, as a
                     LINEAR term at a NaN input.
  NaN input: every term of that variable has mu = 0 (so rules that need it do not fire), and a
                     LINEAR term with a non-zero coefficient on it has no value: the rules
                     concluding it count as not fired (so an output whose rules all need it
                     gives its default, like every rule base kind).
Hedges on a clause: VERY mu^2, SOMEWHAT sqrt(mu), EXTREMELY mu^3, SELDOM sqrt(mu/2) if
  mu <= 1/2 else 1 - sqrt((1-mu)/2), SHARPLY (contrast intensification, fuzzylite's `extremely`)
  2 mu^2 if mu <= 1/2 else 1 - 2 (1-mu)^2; applied before NOT (1-mu).
Rule activation: the clauses that are not wildcards (-1) combined with the rule's connective
  (AND: the t-norm, OR: the s-norm, folded left to right in input order; a rule of wildcards
  only fires 1), times the rule weight; an activation below ACTIVATION_FLOOR (1e-12) is 0: the
  rule does not fire (see ACTIVATION_FLOOR: so an output whose rules all fire below it takes
  its default, in the engine and in every back end).
  A rule with a nested condition (RuleBase.conditions[r], a postfix clause program) fires the
  program's value instead, times the weight (the same ACTIVATION_FLOOR): CLAUSE pushes the
  hedged membership of one input's term (term -1: the truth 1 of `is any`); NOT replaces the top
  v by 1 - v; AND pops b, a and pushes T(a, b); OR pushes S(a, b); HEDGE replaces the top v by
  the hedge of v (a hedge on a compound condition, or on a clause already hedged: fuzzylite's
  `very very x`, and its hedged conclusions, read as rules whose condition is hedged);
  CONCLUDED is a hedge a FIS row says on a conclusion (`t.h` on an output index; the reader
  gives each concluded output a rule of its own ending in the CONCLUDED steps of the row's
  conclusions up to it): its own (term column 1) replaces v by v^(1/p), p the hedge's
  exponent, the earlier ones (term column 0) leave v alone.  That is the Octave
  fuzzy-logic-toolkit's definition (eval_rules_sugeno.m: height = strength^(1/hedge) per rule
  and output), the FIS format's owner here: MATLAB's FIS has no consequent hedges.
  fuzzylite's reading (`--semantics fuzzylite`) differs: tool_semantics.  An n-ary and/or
  folds left to right in written order.
T-norms T(a, b): MIN min; PRODUCT ab; BOUNDED_DIFFERENCE max(0, a+b-1); DRASTIC_PRODUCT
  min(a, b) if max(a, b) = 1 else 0; EINSTEIN_PRODUCT ab / (2 - (a+b-ab)); HAMACHER_PRODUCT
  ab / (a+b-ab) (0 at a = b = 0); NILPOTENT_MIN min(a, b) if a+b > 1 else 0.
S-norms S(a, b): MAX max; PROBSUM a+b-ab; BOUNDED_SUM min(1, a+b) (= fuzzylite 8's normalized
  sum (a+b)/max(1, a+b)); DRASTIC_SUM max(a, b) if min(a, b) = 0 else 1; EINSTEIN_SUM
  (a+b)/(1+ab); HAMACHER_SUM (a+b-2ab)/(1-ab) (1 at ab = 1); NILPOTENT_MAX max(a, b) if a+b < 1
  else 1; UNBOUNDED_SUM a+b (fuzzylite's UnboundedSum; no s-norm: an OR may exceed 1, and the
  implication then reads that activation as it is).
Aggregated output membership of output o at u in [lo, hi]:
  M(u) = AGG over rules r with consequent[r, o] = j >= 0 of IMP(act_r, mu_j(u)).
  AGG: MAX max; SUM the plain (unbounded) sum; PROBSUM 1 - prod_r (1 - m_r); BOUNDED_SUM
  min(1, sum_r m_r) (the s-norms of the same names folded over the rules, in any order).
Defuzzifiers (an output where no rule with a consequent on it has act > 0 gives its default):
  CENTROID   int u M(u) du / int M(u) du over [lo, hi], exact on piecewise-linear terms (also
             under PROBSUM, where M is piecewise polynomial; see fuzzyc.engine.defuzz).  If the
             output's terms are all singletons, the masses alpha_j = AGG of act_r over rules
             concluding j give sum(alpha_j v_j)/sum(alpha_j).
  BISECTOR   the u splitting int M in two equal halves (exact on piecewise-linear terms).
  MEAN_OF_MAXIMUM  the mean of the set where M is largest (to rounding: where M >= top
             (1 - 1e-12), relative to the top; fuzzyc.engine.defuzz.FLAT_TOLERANCE).
  SMALLEST_OF_MAXIMUM, LARGEST_OF_MAXIMUM  the smallest / largest u of that set.
  CENTER_OF_AREA   paper eq. 2: sum_j alpha_j peak_j / sum_j alpha_j, alpha_j = AGG of act_r over
             rules concluding term j; peak = (b+c)/2 of a trapezoid, the mean, centre, or value.
  WEIGHTED_AVERAGE  sum_r act_r z_r / sum_r act_r  (Takagi-Sugeno; z_r = peak of the consequent,
             or the LINEAR term's value at the rule base's inputs, or the FUNCTION term's)
  WEIGHTED_SUM      sum_r act_r z_r  (the neuro-fuzzy controller's output; may leave [lo, hi]).
  GROUPED_SUM       sum_j alpha_j z_j, alpha_j as for CENTER_OF_AREA (pyfuzzylite 8's WeightedSum
             with an aggregation; with SUM it is WEIGHTED_SUM).
Per output o the aggregation and defuzzifier are RuleBase.inference_of(o): the rule base's, or
  the output's own (RuleBase.output_choices).
Rule blocks: a Model holds rule blocks (RuleBase) in evaluation order.  Each sample, after the
  steps of the signal chain, block k evaluates its rules on the current values of its inputs
  (signals, steps, or outputs of blocks before k: a chain) and writes its outputs, which later
  blocks and the controller outputs read.  An output is written by one block only.
Rule-base outputs are not clamped; the signal chain's outputs saturate (see Output).
Held outputs (Variable.lock_previous, fuzzylite's lock-previous): where none of its rules fires
  (with a value), the output keeps the value it had the last time one did, its default before
  that: state of a sequence of evaluations (the controller, per loop; `Held` in fuzzyc.engine.held_outputs),
  which a stateless evaluation refuses by name.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, field, replace
from enum import IntEnum
from typing import Any

import numpy as np
import sympy

from ..engine.formula import Formula


class TermKind(IntEnum):
    TRAPEZOID = 0
    GAUSSIAN = 1
    BELL = 2
    SIGMOID = 3
    SINGLETON = 4
    SSHAPE = 5
    ZSHAPE = 6
    PISHAPE = 7
    SPIKE = 8
    COSINE = 9
    CONCAVE = 10
    LINEAR = 11
    SIGMOID_DIFFERENCE = 12
    SIGMOID_PRODUCT = 13
    GAUSSIAN_PRODUCT = 14
    BINARY = 15
    SEMI_ELLIPSE = 16
    ARC = 17
    DISCRETE = 18
    FUNCTION = 19


class Hedge(IntEnum):
    NONE = 0
    VERY = 1
    SOMEWHAT = 2
    EXTREMELY = 3
    SELDOM = 4
    SHARPLY = 5


class Connective(IntEnum):
    AND = 0
    OR = 1


class CondOp(IntEnum):
    """The steps of a rule's clause program (see RuleBase.conditions)."""
    CLAUSE = 0    # push the truth of (input, term, hedge)
    NOT = 1
    AND = 2
    OR = 3
    HEDGE = 4     # the hedge (4th column) applied to the top value
    CONCLUDED = 5  # a hedge said on a conclusion (FIS `t.h` on an output): term column 1 for
    #                the rule's own conclusion, 0 for an earlier one of the same FIS row
    WEIGHT = 6     # the top value times a rule weight (fuzzylite weighs the activation before
    #                the hedges of a conclusion act on it): the weight's float64 bits in the
    #                term column (`weight_bits`, `weight_of`); such a rule's own weight is 1


def weight_bits(weight: float) -> int:
    """A CondOp.WEIGHT step's term column: the weight's float64 bits as an int64 (exact)."""
    return int(np.array([weight], dtype=np.float64).view(np.int64)[0])


def weight_of(bits: int) -> float:
    """The weight a CondOp.WEIGHT step's term column holds."""
    return float(np.array([bits], dtype=np.int64).view(np.float64)[0])


class TNorm(IntEnum):
    MIN = 0
    PRODUCT = 1
    BOUNDED_DIFFERENCE = 2
    DRASTIC_PRODUCT = 3
    EINSTEIN_PRODUCT = 4
    HAMACHER_PRODUCT = 5
    NILPOTENT_MIN = 6


class SNorm(IntEnum):
    MAX = 0
    PROBSUM = 1
    BOUNDED_SUM = 2
    DRASTIC_SUM = 3
    EINSTEIN_SUM = 4
    HAMACHER_SUM = 5
    NILPOTENT_MAX = 6
    # a + b, unbounded (fuzzylite's UnboundedSum as a disjunction): no s-norm (1 does not
    # absorb), so an OR rule's activation may exceed 1; no C or proof back end takes it
    UNBOUNDED_SUM = 7


# An implication is a t-norm of the rule's activation and the term's membership: the same enum
# (one record per member in fuzzyc.semantics.operators).  The engine integrates MIN and PRODUCT
# exactly, the others on its sampled grid (defuzz.py).
Implication = TNorm


class Aggregation(IntEnum):
    MAX = 0
    SUM = 1
    PROBSUM = 2        # 1 - prod(1 - m): the s-norm PROBSUM over the rules
    BOUNDED_SUM = 3    # min(1, sum m): the s-norm BOUNDED_SUM over the rules
    # further s-norms folded over the rules (fuzzylite's); integrated on the sampled grid
    DRASTIC_SUM = 4
    EINSTEIN_SUM = 5
    HAMACHER_SUM = 6
    NILPOTENT_MAX = 7


def aggregation_snorm(aggregation: Aggregation) -> SNorm | None:
    """The s-norm an aggregation folds over the rules (None for SUM, which is no s-norm)."""
    name = {Aggregation.PROBSUM: "PROBSUM"}.get(aggregation, aggregation.name)
    return SNorm[name] if name in SNorm.__members__ else None


class Defuzzifier(IntEnum):
    CENTROID = 0
    BISECTOR = 1
    MEAN_OF_MAXIMUM = 2
    CENTER_OF_AREA = 3
    WEIGHTED_AVERAGE = 4
    WEIGHTED_SUM = 5
    # Tsukamoto: each firing rule's value is where its monotonic output term equals the rule's
    # activation, z_r = mu^-1(act_r) clipped to the output's range (a sigmoid is 1 only at
    # infinity); y = sum act_r z_r / sum act_r (fuzzylite's reading of a WeightedAverage over
    # Ramp, Sigmoid, SShape, ZShape, Concave terms).  Singletons: z_r = v.
    TSUKAMOTO = 6
    # the smallest / largest u where M is largest (fuzzylite's SmallestOfMaximum and
    # LargestOfMaximum, IEC 61131-7's LM and RM, MATLAB's som and lom)
    SMALLEST_OF_MAXIMUM = 7
    LARGEST_OF_MAXIMUM = 8
    # sum_j alpha_j z_j, alpha_j = AGG of act_r over the rules concluding term j: the weighted
    # sum grouped per term as CENTER_OF_AREA groups the weighted average (pyfuzzylite 8's
    # WeightedSum with an aggregation; fuzzylite 6 sums over the rules: WEIGHTED_SUM)
    GROUPED_SUM = 9
    # sum_r act_r z_r over the firing rules, z_r as for TSUKAMOTO (no division; the default
    # where none fires): fuzzylite's WeightedSum over monotonic terms
    TSUKAMOTO_SUM = 10


PIECEWISE_LINEAR = (TermKind.TRAPEZOID, TermKind.SINGLETON)
ACTIVATION_FLOOR = 1e-12
"""The smallest rule activation that fires: a rule whose activation (after its weight) is
below it does not fire, so an output whose rules all fire below it takes its default.

This is the one statement of what a vanishing activation means; the engine (`norms.firing`)
and every back end follow it: the float/double C headers test it (`fired`, its literal
written from this constant), the lookup table samples the engine, and in the fixed-point
headers it is below resolution (their smallest activation is one LSB, 2^-15 for q15 and 2^-28
for q31: an activation below half an LSB is already 0 there).
Why 1e-12 and not a tinier number: a rule firing at 1e-18 carries no information, yet alone
it decided the output (its term instead of the default), and a shape clipped that low is
below the rounding of its own break points (5 + 1e-18 * 4 == 5), so where the engine and the
C round them differently their centroids, bisectors and means of maximum disagreed by units.
At 1e-12 a clip point a + h (b - a) keeps apart from a while the term is wider than about
1/4500 of |a| (h (b - a) > one ulp of a), and every area, moment and square of a level is a
normal float (1e-24 > 1.2e-38).  Far outside an input's range memberships get tiny, e.g.
1e-122, which float cannot hold: the floor makes the float header and the engine say the
same thing there, usually "no rule fires".  Other tools differ (fuzzylite compares with a
tolerance of 1e-6, `fuzzylite_compat.FL_EPSILON`); `--semantics` keeps their readings."""


def set_entries(owner: Any, name: str, index: Any, value: Any) -> None:
    """owner.<name>[index] = value on a copy that is then assigned (`rb.weights`,
    `var.params`...): the engine makes the arrays of a rule base it has compiled read-only
    (`fuzzyc.engine.inference.compiled`), so a change is a new array, which it sees."""
    array = np.array(getattr(owner, name))
    array[index] = value
    setattr(owner, name, array)


@dataclass(frozen=True)
class SourceLoc:
    """Where something was written: for error messages and reports."""
    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


@dataclass
class Variable:
    """A linguistic variable: a range and its terms, stored as arrays.

    kinds: (T,) int TermKind; params: (T, 4) float; names: T term names; `points` holds the
    (K, 2) points of each DISCRETE term.
    `learnable` marks output terms (singletons) whose values a learning rule may change.
    """
    name: str
    lo: float
    hi: float
    names: list[str]
    kinds: np.ndarray
    params: np.ndarray
    unit: str | None = None
    default: float = 0.0
    learnable: np.ndarray | None = None  # (T,) bool, outputs only
    coefficients: dict[int, np.ndarray] | None = None  # LINEAR terms with > 3 inputs
    points: dict[int, np.ndarray] | None = None        # DISCRETE terms: (K, 2) x, y rows
    formulas: dict[int, Formula] | None = None         # FUNCTION terms
    # an output that holds its last value where no rule fires (fuzzylite's lock-previous):
    # state, so a stateless evaluation refuses it (fuzzyc.engine.held_outputs)
    lock_previous: bool = False
    loc: SourceLoc | None = None
    term_locs: list[SourceLoc | None] = field(default_factory=list)

    @property
    def n_terms(self) -> int:
        return len(self.names)

    def index(self, term: str) -> int:
        return self.names.index(term)

    def term_numbers(self, t: int) -> tuple[float, ...]:
        """Term t's numbers as written: a DISCRETE term's x y pairs, a LINEAR term's long row,
        else its params."""
        if self.kinds[t] == TermKind.DISCRETE:
            return tuple(self.points[t].ravel().tolist())
        if self.kinds[t] == TermKind.LINEAR and (self.coefficients or {}).get(t) is not None:
            return tuple(self.coefficients[t].tolist())
        return tuple(np.asarray(self.params[t], dtype=float).tolist())

    def peaks(self) -> np.ndarray:
        """The representative value of each term (used by CENTER_OF_AREA and TSK outputs):
        its shape record's peak (fuzzyc.semantics.shapes)."""
        from .shapes import SHAPES      # the registry imports this module
        out = np.empty(len(self.kinds))
        for i, kind in enumerate(self.kinds):
            record = SHAPES[TermKind(int(kind))]
            data = (self.points or {}).get(i) if record.per_term else self.params[i]
            out[i] = record.peak(data, self.lo, self.hi)
        return out


@dataclass
class Inference:
    and_: TNorm = TNorm.MIN
    or_: SNorm = SNorm.MAX
    implication: Implication = Implication.MIN
    aggregation: Aggregation = Aggregation.MAX
    defuzzifier: Defuzzifier = Defuzzifier.CENTROID

    def describe(self) -> str:
        return (f"and={self.and_.name.lower()} or={self.or_.name.lower()} "
                f"implication={self.implication.name.lower()} "
                f"aggregation={self.aggregation.name.lower()} "
                f"defuzzify={self.defuzzifier.name.lower()}")


@dataclass
class RuleBase:
    """Rules as matrices over the rule base's (already scaled) inputs and outputs.

    antecedents (R, I) int: term index per input, -1 for "any" (the clause is absent).
    negated (R, I) bool, hedges (R, I) int Hedge, connective (R,) int Connective.
    consequents (R, O) int: term index per output, -1 when the rule says nothing about it.
    weights (R,) float.  origins: a human-readable place per rule ("table du1 when e1 is P,
    row e2=PB, col ce2=PS") so reports can name table cells.
    conditions: rule r -> its clause program when its condition is not a flat conjunction or
    disjunction of one clause per input (a (K, 4) int array of postfix steps: CondOp, input,
    term, hedge; 0 where a column does not apply).  The matrix row of such a rule holds
    wildcards only; a reader of the matrices that does not know programs must refuse the rule
    base (`nested_rules` names them).
    """
    inputs: list[Variable]
    outputs: list[Variable]
    antecedents: np.ndarray
    consequents: np.ndarray
    weights: np.ndarray
    negated: np.ndarray
    hedges: np.ndarray
    connective: np.ndarray
    inference: Inference = field(default_factory=Inference)
    rule_locs: list[SourceLoc | None] = field(default_factory=list)
    origins: list[str] = field(default_factory=list)
    conditions: dict[int, np.ndarray] = field(default_factory=dict)
    name: str = ""                    # the block's name when a Model has several
    output_choices: dict[str, tuple[Aggregation, Defuzzifier]] = field(default_factory=dict)

    @property
    def n_rules(self) -> int:
        return int(self.antecedents.shape[0])

    def input_index(self, name: str) -> int:
        return [v.name for v in self.inputs].index(name)

    def inference_of(self, o: int) -> Inference:
        """Output o's inference: the block's, with the output's own aggregation and
        defuzzifier where it has them."""
        choice = self.output_choices.get(self.outputs[o].name)
        if choice is None:
            return self.inference
        return replace(self.inference, aggregation=choice[0], defuzzifier=choice[1])

    def output_index(self, name: str) -> int:
        return [v.name for v in self.outputs].index(name)

    def nested_rules(self) -> str:
        """'' when every rule is a flat matrix row, else the first nested one, for a refusal."""
        if not self.conditions:
            return ""
        r = min(self.conditions)
        more = len(self.conditions) - 1
        return (f"rule {r + 1} `{self.describe_rule(r)}`"
                + (f" and {more} more" if more else ""))

    def describe_condition(self, r: int, clause, words=("and", "or", "not")) -> str:
        """The condition of rule r as text: clause(input, term, negated, hedge) writes one
        clause (term -1: `any`); `words` are the connectives and the prefix negation of a
        compound condition in the target syntax, and where the syntax has them (.fz) the words
        of a hedge said on this rule's conclusion and on an earlier one (CondOp.CONCLUDED)."""
        if r not in self.conditions:
            conn = f" {words[0]} " if self.connective[r] == Connective.AND else f" {words[1]} "
            return conn.join(clause(i, int(t), bool(self.negated[r, i]),
                                    Hedge(int(self.hedges[r, i])))
                             for i, t in enumerate(self.antecedents[r]) if t >= 0)
        # (text, the op of its top node, the clause's (input, term, hedge) if it is one)
        stack: list[tuple[str, int, tuple | None]] = []
        for op, i, t, h in self.conditions[r].tolist():
            if op == CondOp.CLAUSE:
                stack.append((clause(i, t, False, Hedge(h)), op, (i, t, Hedge(h))))
            elif op == CondOp.NOT:
                text, top, leaf = stack.pop()
                text = clause(*leaf[:2], True, leaf[2]) if leaf else f"{words[2]} ({text})"
                stack.append((text, CondOp.CLAUSE, None))
            elif op == CondOp.HEDGE:
                text, top, leaf = stack.pop()
                stack.append((f"{Hedge(h).name.lower()} ({text})", CondOp.CLAUSE, None))
            elif op == CondOp.WEIGHT:         # weighed before the hedges above it
                text, top, leaf = stack.pop()
                stack.append((f"{weight_of(t)!r} * ({text})", CondOp.CLAUSE, None))
            elif op == CondOp.CONCLUDED and len(words) > 3:     # .fz: `concluded very (...)`
                text, top, leaf = stack.pop()
                said = " ".join([words[3] if t else words[4], *([Hedge(h).name.lower()] if h
                                                                else [])])
                stack.append((f"{said} ({text})", CondOp.CLAUSE, None))
            elif op == CondOp.CONCLUDED:      # said on a conclusion: shown, not a clause word
                text, top, leaf = stack.pop()
                said = f"{Hedge(h).name.lower()} on {'this' if t else 'an earlier'} conclusion"
                stack.append((f"({text}) [FIS: {said}]", CondOp.CLAUSE, None))
            else:
                (b, top_b, _), (a, top_a, _) = stack.pop(), stack.pop()
                word = words[0] if op == CondOp.AND else words[1]
                a = a if top_a in (op, CondOp.CLAUSE) else f"({a})"
                b = b if top_b == CondOp.CLAUSE else f"({b})"
                stack.append((f"{a} {word} {b}", op, None))
        return stack[0][0]

    def describe_rule(self, r: int) -> str:
        """The rule as text, in the language's own syntax."""
        def clause(i: int, t: int, negated: bool, hedge: Hedge) -> str:
            v = self.inputs[i]
            term = (hedge.name.lower() + " " if hedge else "") + (v.names[t] if t >= 0 else "any")
            return f"{v.name} is {'not ' if negated else ''}{term}"
        cons = [f"{v.name} is {v.names[int(self.consequents[r, o])]}"
                for o, v in enumerate(self.outputs) if self.consequents[r, o] >= 0]
        text = "if " + (self.describe_condition(r, clause) or "true") + " then " + ", ".join(cons)
        if self.weights[r] != 1.0:
            text += f" with {self.weights[r]:g}"
        return text


class Op(IntEnum):
    """The kinds of step in the signal-chain program."""
    ASSIGN = 0    # name = expr
    DELTA = 1     # name = arg - memory; memory := arg           (first sample: 0)
    PREV = 2      # name = memory; memory := arg                 (first sample: arg)
    LOWPASS = 3   # name = a*memory + b*arg; memory := name      (first sample: arg)


@dataclass
class Step:
    """One step of the signal chain, executed in order every sample.

    `expr` is a sympy expression over symbols named after inputs, params and earlier steps.
    For DELTA/PREV/LOWPASS, `expr` is the argument and `coeffs` = (a, b) for LOWPASS.
    Stateful steps keep their last finite value: a NaN sample does not poison the memory.
    """
    name: str
    op: Op
    expr: sympy.Expr
    coeffs: tuple[float, float] = (0.0, 0.0)
    unit: str | None = None
    lo: float | None = None
    hi: float | None = None
    hidden: bool = False           # generated by the builder (e.g. the state of delta())
    loc: SourceLoc | None = None


class OutputKind(IntEnum):
    DIRECT = 0                 # u(k) = sat(expr)
    INCREMENT = 1              # u(k) = sat(u(k-1) + expr)
    RECIPROCAL_INCREMENT = 2   # v(k) = sat_v(v(k-1) + expr), u = 1/v; sat_v = [1/hi, 1/lo]


@dataclass
class Output:
    """A controller output: the end of the signal chain, saturated to [lo, hi]."""
    name: str
    kind: OutputKind
    expr: sympy.Expr
    lo: float
    hi: float
    init: float = 0.0          # u(-1), in the output's own units
    unit: str | None = None
    loc: SourceLoc | None = None


@dataclass
class Param:
    name: str
    value: float
    unit: str | None = None
    loc: SourceLoc | None = None


@dataclass
class Signal:
    """A raw controller input."""
    name: str
    lo: float
    hi: float
    unit: str | None = None
    loc: SourceLoc | None = None


@dataclass
class Property:
    """A verification property as written; `fuzzyc.verifier` gives it meaning.

    kind: covers | consistent | complete | continuous | monotone | bounded | closed_loop
    args: kind-specific, plain values (names, numbers, directions, guard clauses) and, for
    closed_loop, a list of temporal `Property` objects in args["checks"] (kinds always,
    eventually, settles, overshoot) with sympy conditions.
    """
    kind: str
    args: dict[str, Any]
    loc: SourceLoc | None = None
    text: str = ""


@dataclass
class Model:
    """A whole controller: signal chain in, rule blocks, signal chain out, properties."""
    name: str
    blocks: list[RuleBase]
    title: str = ""
    period: float | None = None          # seconds
    params: dict[str, Param] = field(default_factory=dict)
    signals: list[Signal] = field(default_factory=list)
    steps: list[Step] = field(default_factory=list)
    outputs: list[Output] = field(default_factory=list)
    properties: list[Property] = field(default_factory=list)
    source_path: str | None = None
    source_text: str | None = None
    notes: list[str] = field(default_factory=list)   # findings recorded in the file
    # a .fz file's located warnings (errors.Diagnostic, severity "warning"): what the reader
    # found legal but likely not meant; `fuzzyc check` prints them
    warnings: list = field(default_factory=list)
    # a .fz file's `fuzzylite` statements: what fuzzylite's semantics read of an imported
    # file (formats.tool_semantics.FileSettings; `locked`, `resolution`, `nan_default`,
    # `known`), None where the file has none (FLL and FCL files: read off their text)
    fuzzylite: dict | None = None
    # what `fuzzyc tune` may move (fuzzyc.semantics.tunable.TunedNumber), the rest is frozen
    tunables: list = field(default_factory=list)

    @property
    def source_hash(self) -> str:
        text = self.source_text or ""
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def symbol_values(self) -> dict[str, float]:
        return {p.name: p.value for p in self.params.values()}

    @classmethod
    def of_rulebase(cls, rb: RuleBase, name: str) -> "Model":
        """rb alone as a controller: its inputs read as signals, each output `y` written as it
        is to `y_out` (the importers' convention, `chain_output_names`; benchmarks and tests of
        wide rule bases)."""
        names = chain_output_names([v.name for v in rb.outputs],
                                   [v.name for v in (*rb.inputs, *rb.outputs)])
        return cls(name, [rb], signals=[Signal(v.name, v.lo, v.hi) for v in rb.inputs],
                   outputs=[Output(out, OutputKind.DIRECT, sympy.Symbol(v.name),
                                   v.lo, v.hi, init=v.lo) for out, v in zip(names, rb.outputs)])

    @property
    def rulebase(self) -> RuleBase:
        """The rule base of a one-block model.  A reader that handles one rule block asks for
        this, so a model with several is refused by name (FuzzycError)."""
        if len(self.blocks) == 1:
            return self.blocks[0]
        from ..errors import Diagnostic, FuzzycError    # errors imports this module
        names = ", ".join(f"`{b.name}`" for b in self.blocks)
        raise FuzzycError([Diagnostic(None, f"`{self.name}` has {len(self.blocks)} rule blocks "
                                            f"({names}); this step reads one rule block (the "
                                            "controller and `simulate` run chained blocks)")])

    def rulebase_input_sources(self) -> list[str]:
        """Names of the signals/steps that feed the rule base's inputs, in input order."""
        return [v.name for v in self.rulebase.inputs]

    def __repr__(self) -> str:          # a few lines, not the dataclass's array dump
        from ..display import model_text
        return model_text(self)

    def _repr_html_(self) -> str:       # Jupyter
        from ..display import model_html
        return model_html(self)


def chain_output_names(outputs: list[str], taken: list[str]) -> list[str]:
    """The names of the signal-chain outputs that pass rule-base outputs `y` through (the
    importers', `Model.of_rulebase`'s, the .fz writer's): `y_out`, or `y_out2`, `y_out3`, ...
    when that meets one of the `taken` names (every variable of the file) or an earlier choice.
    Names meet as C identifiers do, upper-cased (`escape.check_c_names`), so no user name is
    shadowed in eval's columns, in the controller's signals or in the C header."""
    from ..escape import c_identifier     # escape imports errors, which imports this module
    used = {c_identifier(n).upper() for n in taken}
    names = []
    for y in outputs:
        name, n = f"{y}_out", 2
        while c_identifier(name).upper() in used:
            name, n = f"{y}_out{n}", n + 1
        used.add(c_identifier(name).upper())
        names.append(name)
    return names
