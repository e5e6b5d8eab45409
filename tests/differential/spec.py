"""A random rule base in no tool's format (`System`), and its seeded generator.

Each tool has its own vocabulary (`VOCABULARY`: shapes, norms, hedges, defuzzifiers), read off
the tools' sources: pyfuzzylite 8's factories (term.py, norm.py, defuzzifier.py, hedge.py),
fuzzylite 6's FLL and FCL as its CLI reads and writes them, and the Octave fuzzy-logic-toolkit
0.4.6 (its private/evalmf_private.m, defuzz.m and the norm files beside readfis.m).  The
generator draws only from a tool's vocabulary, so every file is one that tool accepts."""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

# The Ramp, Sigmoid, SShape, ZShape, Concave: monotonic, so a WeightedAverage over them is
# fuzzylite's Tsukamoto
MONOTONIC = ("Ramp", "Sigmoid", "SShape", "ZShape", "Concave")
FUZZYLITE_AREA = ("Triangle", "Trapezoid", "Rectangle", "Ramp", "Bell", "Gaussian",
                  "GaussianProduct", "Sigmoid", "SigmoidDifference", "SigmoidProduct", "SShape",
                  "ZShape", "PiShape", "Spike", "Cosine", "Concave", "Discrete", "Binary")
TNORMS = ("Minimum", "AlgebraicProduct", "BoundedDifference", "DrasticProduct",
          "EinsteinProduct", "HamacherProduct", "NilpotentMinimum")
SNORMS = ("Maximum", "AlgebraicSum", "BoundedSum", "DrasticSum", "EinsteinSum", "HamacherSum",
          "NilpotentMaximum", "NormalizedSum", "UnboundedSum")
INTEGRAL = ("Centroid", "Bisector", "MeanOfMaximum", "SmallestOfMaximum", "LargestOfMaximum")
OCTAVE_TNORMS = ("min", "prod", "algebraic_product", "bounded_difference", "drastic_product",
                 "einstein_product", "hamacher_product")
# the toolkit has no probor.m (MATLAB's name): `@probor` is an error in evalfis
OCTAVE_SNORMS = ("max", "algebraic_sum", "bounded_sum", "drastic_sum", "einstein_sum",
                 "hamacher_sum")


@dataclass(frozen=True)
class Vocabulary:
    area_shapes: tuple[str, ...]
    tnorms: tuple[str, ...]
    snorms: tuple[str, ...]
    implications: tuple[str, ...]
    aggregations: tuple[str, ...]
    mamdani: tuple[str, ...]          # defuzzifiers of area terms
    sugeno: tuple[str, ...]           # defuzzifiers of constant/linear terms
    hedges: tuple[str, ...]           # FIS: the toolkit's exponents as names


VOCABULARY = {
    "fll": Vocabulary(FUZZYLITE_AREA + ("SemiEllipse", "Arc"), TNORMS, SNORMS, TNORMS, SNORMS,
                      INTEGRAL, ("WeightedAverage", "WeightedSum"),
                      ("very", "somewhat", "seldom", "extremely")),
    "fll6": Vocabulary(FUZZYLITE_AREA, TNORMS, SNORMS, TNORMS, SNORMS, INTEGRAL,
                       ("WeightedAverage", "WeightedSum"),
                       ("very", "somewhat", "seldom", "extremely")),
    "fis": Vocabulary(("trimf", "trapmf", "gaussmf", "gauss2mf", "gbellmf", "sigmf", "dsigmf",
                       "psigmf", "pimf", "smf", "zmf"), OCTAVE_TNORMS, OCTAVE_SNORMS,
                      OCTAVE_TNORMS, OCTAVE_SNORMS[:1] + ("sum",) + OCTAVE_SNORMS[1:],
                      ("centroid", "bisector", "mom", "som", "lom"), ("wtaver", "wtsum"),
                      ("somewhat", "very", "extremely", "very very")),
}


@dataclass
class Term:
    name: str
    shape: str
    params: list[float]


@dataclass
class Var:
    name: str
    lo: float
    hi: float
    terms: list[Term]
    lock_range: bool = False
    # outputs only
    aggregation: str = ""            # "" = none (Takagi-Sugeno)
    defuzzifier: str = ""
    resolution: int | None = None
    default: float = math.nan


@dataclass
class Clause:
    var: str
    term: str
    hedges: list[str] = field(default_factory=list)   # outermost first; may hold "not", "any"


@dataclass
class Node:
    op: str                 # "and" | "or"
    left: "Clause | Node"
    right: "Clause | Node"
    brackets: bool = True   # False: written without brackets where the tool's precedence decides


@dataclass
class Rule:
    cond: Clause | Node
    then: list[Clause]
    weight: float | None = None


@dataclass
class System:
    fmt: str                 # "fll", "fll6" (fuzzylite 6's FLL), "fcl", "fis"
    sugeno: bool
    name: str
    inputs: list[Var]
    outputs: list[Var]
    conjunction: str
    disjunction: str
    implication: str         # "" = none
    rules: list[Rule]

    @property
    def vocabulary(self) -> Vocabulary:
        return VOCABULARY["fis" if self.fmt == "fis" else "fll" if self.fmt == "fll" else "fll6"]


def clauses(cond: Clause | Node) -> list[Clause]:
    return [cond] if isinstance(cond, Clause) else clauses(cond.left) + clauses(cond.right)


def rounded(value: float, digits: int = 4) -> float:
    """value to `digits` significant digits: short files, numbers every tool reads alike."""
    if value == 0 or not math.isfinite(value):
        return value
    return float(f"{value:.{digits}g}")


class Generator:
    """Random Systems of one format, from one seed."""

    def __init__(self, fmt: str, seed: int):
        self.fmt = fmt
        self.rng = random.Random(seed)
        self.voc = VOCABULARY["fis" if fmt == "fis" else "fll" if fmt == "fll" else "fll6"]

    def system(self, name: str) -> System:
        r = self.rng
        sugeno = r.random() < 0.35
        inputs = [self.variable(f"in{i + 1}", False) for i in range(r.randint(1, 4))]
        outputs = [self.variable(f"out{i + 1}", True, sugeno, len(inputs))
                   for i in range(r.randint(1, 2))]
        if self.fmt == "fis":
            implication = r.choice(self.voc.implications)
        else:
            implication = "" if sugeno and r.random() < 0.6 else r.choice(self.voc.implications)
        rules = [self.rule(inputs, outputs) for _ in range(r.randint(1, 10))]
        return System(self.fmt, sugeno, name, inputs, outputs, r.choice(self.voc.tnorms),
                      r.choice(self.voc.snorms), implication, rules)

    # ------------------------------------------------------------------ variables
    def variable(self, name: str, output: bool, sugeno: bool = False, n_inputs: int = 0) -> Var:
        r = self.rng
        width = rounded(10 ** r.uniform(math.log10(0.03), math.log10(3000)))
        lo = rounded(r.choice([0.0, r.uniform(-2, 2) * width, r.uniform(-20, 20) * width]))
        var = Var(name, lo, rounded(lo + width), [])
        # fuzzylite 6's FCL locks the range of outputs only (`LOCK : RANGE` in DEFUZZIFY)
        lockable = self.fmt in ("fll", "fll6") or self.fmt == "fcl" and output
        var.lock_range = lockable and r.random() < 0.2
        count = r.randint(2, 7)
        tsukamoto = output and sugeno and self.fmt != "fis" and r.random() < 0.15
        for t in range(count):
            if output and sugeno and not tsukamoto:
                shape = "Linear" if r.random() < 0.4 else "Constant"
                if self.fmt == "fis":
                    shape = shape.lower()
            else:
                shape = r.choice(MONOTONIC if tsukamoto else self.voc.area_shapes)
            var.terms.append(Term(f"t{t + 1}", shape, self.params(shape, var, n_inputs)))
        if output:
            self.output_settings(var, sugeno)
        return var

    def output_settings(self, var: Var, sugeno: bool) -> None:
        r = self.rng
        if sugeno:
            var.defuzzifier = r.choice(self.voc.sugeno)
            var.aggregation = "" if r.random() < 0.6 else r.choice(self.voc.aggregations)
        else:
            var.defuzzifier = r.choice(self.voc.mamdani)
            var.aggregation = r.choice(self.voc.aggregations)
            if self.fmt in ("fll", "fll6") and r.random() < 0.7:
                var.resolution = r.randint(100, 1000)
        if r.random() < 0.4:
            var.default = rounded(r.uniform(var.lo, var.hi))

    def params(self, shape: str, var: Var, n_inputs: int) -> list[float]:
        r = self.rng
        lo, hi = var.lo, var.hi
        w = hi - lo

        def at() -> float:          # a break point, now and then a little outside the range
            return r.uniform(lo - 0.1 * w, hi + 0.1 * w) if r.random() < 0.15 else \
                r.uniform(lo, hi)

        def spread(lo_frac: float, hi_frac: float) -> float:
            return w * r.uniform(lo_frac, hi_frac)

        def points(n: int) -> list[float]:
            return sorted(at() for _ in range(n))

        slope = lambda: r.choice([-1, 1]) * r.uniform(2, 40) / w      # noqa: E731
        made = {
            "Triangle": lambda: points(3), "Trapezoid": lambda: points(4),
            "Rectangle": lambda: points(2), "SShape": lambda: points(2),
            "ZShape": lambda: points(2), "PiShape": lambda: points(4),
            "SemiEllipse": lambda: points(2), "Arc": lambda: points(2),
            "Ramp": lambda: points(2)[::r.choice([1, -1])],
            "Bell": lambda: [at(), spread(0.05, 0.5), r.uniform(0.5, 5)],
            "Gaussian": lambda: [at(), spread(0.03, 0.4)],
            "GaussianProduct": lambda: [p for m in points(2) for p in (m, spread(0.03, 0.3))],
            "Sigmoid": lambda: [at(), slope()],
            "SigmoidDifference": lambda: self._sigmoid_pair(points(2), w, 1),
            "SigmoidProduct": lambda: self._sigmoid_pair(points(2), w, -1),
            "Spike": lambda: [at(), spread(0.05, 0.8)], "Cosine": lambda: [at(), spread(0.1, 1)],
            "Concave": lambda: points(2)[::r.choice([1, -1])],
            "Binary": lambda: [at(), r.choice([-math.inf, math.inf])],
            "Discrete": lambda: [v for x in points(r.randint(2, 5)) for v in (x, r.random())],
            "Constant": lambda: [r.uniform(lo, hi)], "constant": lambda: [r.uniform(lo, hi)],
            "Linear": lambda: self._linear(var, n_inputs),
            "linear": lambda: self._linear(var, n_inputs),
            "trimf": lambda: points(3), "trapmf": lambda: points(4),
            "gaussmf": lambda: [spread(0.03, 0.4), at()],
            "gauss2mf": lambda: [p for c in points(2) for p in (spread(0.03, 0.3), c)],
            # the toolkit's gbellmf wants an integral b (are_mf_params.m)
            "gbellmf": lambda: [spread(0.05, 0.5), r.randint(1, 5), at()],
            "sigmf": lambda: [slope(), at()],
            "dsigmf": lambda: [p for c in points(2) for p in (abs(slope()), c)],
            "psigmf": lambda: [p for c, s in zip(points(2), (1, -1))
                               for p in (s * abs(slope()), c)],
            "pimf": lambda: points(4), "smf": lambda: points(2), "zmf": lambda: points(2),
        }[shape]()
        made = [rounded(p) for p in made]
        return _toolkit_order(shape, made) if self.fmt == "fis" else made

    def _sigmoid_pair(self, centres: list[float], w: float, sign: int) -> list[float]:
        """fuzzylite's SigmoidDifference/Product left rising falling right: rising > 0; the
        falling slope positive for a difference, negative for a product."""
        r = self.rng
        return [centres[0], r.uniform(2, 40) / w, sign * r.uniform(2, 40) / w, centres[1]]

    def _linear(self, var: Var, n_inputs: int) -> list[float]:
        r = self.rng
        scale = (var.hi - var.lo) or 1.0
        return [r.uniform(-1, 1) * scale / 10 for _ in range(n_inputs)] + \
            [r.uniform(var.lo, var.hi)]

    # ------------------------------------------------------------------ rules
    def rule(self, inputs: list[Var], outputs: list[Var]) -> Rule:
        r = self.rng
        if self.fmt == "fis":
            chosen = r.sample(inputs, r.randint(1, len(inputs)))
            op = r.choice(["and", "or"])
            cond: Clause | Node = self.clause(chosen[0])
            for var in chosen[1:]:
                cond = Node(op, cond, self.clause(var))
        else:
            cond = self.condition(inputs, r.randint(1, 5))
        then = [self.conclusion(v) for v in outputs
                if len(outputs) == 1 or r.random() < 0.7] or [self.conclusion(outputs[0])]
        weight = None if r.random() < 0.6 else rounded(r.choice([r.random(), 0.0, 1.0]))
        return Rule(cond, then, weight)

    def condition(self, inputs: list[Var], size: int) -> Clause | Node:
        r = self.rng
        if size <= 1:
            return self.clause(r.choice(inputs))
        left = r.randint(1, size - 1)
        return Node(r.choice(["and", "or"]), self.condition(inputs, left),
                    self.condition(inputs, size - left), brackets=r.random() < 0.7)

    def clause(self, var: Var) -> Clause:
        r = self.rng
        hedges = []
        while r.random() < 0.25 and len(hedges) < 3:
            hedges.append(r.choice(self.voc.hedges))
        if self.fmt == "fis":
            hedges = hedges[:1]
        if r.random() < 0.2:
            hedges.insert(0, "not")
        if self.fmt != "fis" and r.random() < 0.03:
            hedges = ["any"]
        return Clause(var.name, r.choice(var.terms).name, hedges)

    def conclusion(self, var: Var) -> Clause:
        r = self.rng
        hedges = [r.choice(self.voc.hedges)] if r.random() < 0.04 else []
        if self.fmt == "fis" and r.random() < 0.03:
            hedges.insert(0, "not")
        return Clause(var.name, r.choice(var.terms).name, hedges)


# The Octave toolkit's parameter checks (private/are_mf_params.m): which neighbouring break
# points must differ (True: p[i] < p[i + 1]; False: p[i] <= p[i + 1]).  A term that fails them
# makes evalfis fail, so the generator separates break points that rounding made equal.
TOOLKIT_ORDER = {"trimf": (True, True), "trapmf": (True, False, True),
                 "pimf": (True, False, True), "smf": (True,), "zmf": (True,)}


def _toolkit_order(shape: str, p: list[float]) -> list[float]:
    """p with each break point that must exceed the one before it moved up by a unit of its
    fourth significant digit until it does (no random draw: the other files stay as drawn)."""
    for i, strict in enumerate(TOOLKIT_ORDER.get(shape, ())):
        if not strict:
            p[i + 1] = max(p[i + 1], p[i])
            continue
        while p[i + 1] <= p[i]:
            scale = abs(p[i + 1]) or abs(p[i]) or 1.0
            p[i + 1] = rounded(p[i + 1] + 10.0 ** (math.floor(math.log10(scale)) - 3))
    return p


def evaluation_points(system: System, seed: int, rows: int = 40) -> list[list[float]]:
    """Rows of inputs: every input at its range ends and outside them, then rows whose inputs
    are break points of its terms (and ends) or random points of its range.  Octave's evalfis
    refuses inputs outside the range (is_input_matrix), so FIS rows stay inside."""
    r = random.Random(seed)
    outside = 0.0 if system.fmt == "fis" else 0.25
    special = []
    for var in system.inputs:
        w = var.hi - var.lo
        marks = {var.lo, var.hi, var.lo - outside * w, var.hi + outside * w}
        marks.update(p for t in var.terms for p in t.params if math.isfinite(p)
                     and var.lo - 4 * outside * w <= p <= var.hi + 4 * outside * w)
        special.append(sorted(marks))
    out = [[v.lo for v in system.inputs], [v.hi for v in system.inputs],
           [v.lo - outside * (v.hi - v.lo) for v in system.inputs],
           [v.hi + outside * (v.hi - v.lo) for v in system.inputs]]
    while len(out) < rows:
        out.append([r.choice(marks) if r.random() < 0.5 else rounded(r.uniform(v.lo, v.hi), 6)
                    for v, marks in zip(system.inputs, special)])
    return out
