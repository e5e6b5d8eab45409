"""The operators of the model, one record each: t-norms, s-norms, hedges, aggregations and
defuzzifiers (issue 27: one definition per concept).

A record holds everything about its operator that more than one place needs:
- `word`: the .fz word (the grammar's for hedges, the `inference` setting's value otherwise);
  `also` lists further words a reader accepts but no writer writes, as (format, word) pairs
  with format one of fz, fll, fcl, fis;
- `numpy`: the function the engine calls (elementwise for norms and hedges; a defuzzifier's
  per family, see `fuzzyc.engine.crisp`), None for the hedge NONE (the truth as it is);
- `monotone`: nondecreasing in every argument on [0, 1] (the set-valued evaluation of
  `fuzzyc.verifier.reach` passes lower and upper bounds through the engine's own code, which
  is sound only then);
- `fll`, `fcl`, `fis`: the word each format writes for it, None where it has none;
- `c_float`: the text the float/double C header writes for it, None = not emitted in C (the C
  back end refuses it by name); `fixed`: the same for the q15/q31 headers.
The capability checks of the back ends and the verifier are allow-lists derived from these
records (`emitted_in_c`, `emitted_in_fixed`, `provable`).  Their meaning in words is the
model's docstring (fuzzyc.semantics.model).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..engine import crisp
from .model import Aggregation, Defuzzifier, Hedge, SNorm, TNorm


@dataclass(frozen=True)
class Operator:
    word: str
    numpy: Callable[..., np.ndarray] | None
    monotone: bool
    fll: str | None = None
    fcl: str | None = None
    fis: str | None = None
    c_float: str | None = None
    fixed: str | None = None
    also: tuple[tuple[str, str], ...] = ()

    def also_in(self, fmt: str) -> tuple[str, ...]:
        """The further words format `fmt` reads for this operator."""
        return tuple(word for f, word in self.also if f == fmt)

    @property
    def name(self) -> str:
        """The word as a refusal says it."""
        return self.word.replace("_", " ")


@dataclass(frozen=True)
class Norm(Operator):
    """A t-norm or s-norm. C: `{a}`, `{b}` the operands, `{p}` the header's prefix; fixed: the
    fixed-point header's helper function.  `exact`: as an implication, the engine integrates
    it exactly on piecewise-linear terms (else on its sampled grid); `provable`: the proof
    methods of the verifier (proof, coverage, levelsets) handle it."""
    exact: bool = False
    provable: bool = False


@dataclass(frozen=True)
class HedgeOp(Operator):
    """A hedge on a clause.  `exponent`: the power it raises a truth to, None for the
    piecewise ones (they have no entry in HEDGE_EXPONENT).  C: `{mu}` the truth, `{sqrt}` the
    real type's square root."""
    exponent: float | None = None


@dataclass(frozen=True)
class AggregationOp(Operator):
    """How the rules' implied shapes (or the terms' strengths) are accumulated.  `snorm`: the
    s-norm folded over the rules (None for SUM); `exact`: integrated exactly on
    piecewise-linear terms (else on the sampled grid).  C and fixed: a statement accumulating
    `{x}` into `{acc}`."""
    snorm: SNorm | None = None
    exact: bool = False


@dataclass(frozen=True)
class DefuzzifierOp(Operator):
    """`family`: area (reads the aggregated shape), peaks (reads the terms' strengths and
    values), inverse (Tsukamoto: the terms' inverses at the rules' levels).  C: the value the
    header writes from its `num` and `den` (peaks), or `area` (backends/c/area.py and
    centroid.py integrate the shape)."""
    family: str = "area"


def _hamacher_product(a, b):
    den = a + b - a * b
    return np.where(den != 0.0, a * b / np.where(den != 0.0, den, 1.0), 0.0)


def _hamacher_sum(a, b):
    den = 1.0 - a * b
    return np.where(den != 0.0, (a + b - 2.0 * a * b) / np.where(den != 0.0, den, 1.0), 1.0)


def _seldom(mu):
    m = np.clip(mu, 0.0, 1.0)
    return np.where(m <= 0.5, np.sqrt(0.5 * m), 1.0 - np.sqrt(0.5 * (1.0 - m)))


def _sharply(mu):
    m = np.clip(mu, 0.0, 1.0)
    return np.where(m <= 0.5, 2.0 * m * m, 1.0 - 2.0 * (1.0 - m) ** 2)


def _power(exponent: float) -> Callable[[np.ndarray], np.ndarray]:
    return lambda mu: mu ** exponent


# Every t-norm and s-norm is monotone: that is an axiom of both.
T_NORMS: dict[TNorm, Norm] = {
    TNorm.MIN: Norm("min", np.minimum, True, "Minimum", "MIN", "min",
                    "{p}lesser({a}, {b})", "lesser", exact=True, provable=True),
    TNorm.PRODUCT: Norm("product", np.multiply, True, "AlgebraicProduct", "PROD", "prod",
                        "{a} * {b}", "product",
                        also=(("fz", "prod"), ("fis", "algebraic_product")),
                        exact=True, provable=True),
    TNorm.BOUNDED_DIFFERENCE: Norm("bounded_difference",
                                   lambda a, b: np.maximum(0.0, a + b - 1.0), True,
                                   "BoundedDifference", "BDIF",
                                   also=(("fis", "bounded_difference"),)),
    TNorm.DRASTIC_PRODUCT: Norm("drastic_product", lambda a, b: np.where(
        np.maximum(a, b) == 1.0, np.minimum(a, b), 0.0), True, "DrasticProduct", "DPROD",
        also=(("fis", "drastic_product"),)),
    TNorm.EINSTEIN_PRODUCT: Norm("einstein_product",
                                 lambda a, b: a * b / (2.0 - (a + b - a * b)), True,
                                 "EinsteinProduct", "EPROD", also=(("fis", "einstein_product"),)),
    TNorm.HAMACHER_PRODUCT: Norm("hamacher_product", _hamacher_product, True,
                                 "HamacherProduct", "HPROD", also=(("fis", "hamacher_product"),)),
    TNorm.NILPOTENT_MIN: Norm("nilpotent_min",
                              lambda a, b: np.where(a + b > 1.0, np.minimum(a, b), 0.0), True,
                              "NilpotentMinimum", "NMIN", also=(("fis", "nilpotent_minimum"),)),
}

# No s-norm has a fixed-point emission: the q15/q31 headers take plain AND rules only.
S_NORMS: dict[SNorm, Norm] = {
    SNorm.MAX: Norm("max", np.maximum, True, "Maximum", "MAX", "max",
                    "{p}greater({a}, {b})", provable=True),
    SNorm.PROBSUM: Norm("probsum", lambda a, b: a + b - a * b, True, "AlgebraicSum", "ASUM",
                        "probor", "({a} + {b} - {a} * {b})",
                        also=(("fz", "probabilistic_sum"), ("fis", "algebraic_sum")),
                        provable=True),
    # fuzzylite 8's NormalizedSum (a+b)/max(1, a+b) is min(1, a+b)
    SNorm.BOUNDED_SUM: Norm("bounded_sum", lambda a, b: np.minimum(1.0, a + b), True,
                            "BoundedSum", "BSUM",
                            also=(("fll", "NormalizedSum"), ("fcl", "NSUM"),
                                  ("fis", "bounded_sum"))),
    SNorm.DRASTIC_SUM: Norm("drastic_sum", lambda a, b: np.where(
        np.minimum(a, b) == 0.0, np.maximum(a, b), 1.0), True, "DrasticSum", "DSUM",
        also=(("fis", "drastic_sum"),)),
    SNorm.EINSTEIN_SUM: Norm("einstein_sum", lambda a, b: (a + b) / (1.0 + a * b), True,
                             "EinsteinSum", "ESUM", also=(("fis", "einstein_sum"),)),
    SNorm.HAMACHER_SUM: Norm("hamacher_sum", _hamacher_sum, True, "HamacherSum", "HSUM",
                             also=(("fis", "hamacher_sum"),)),
    SNorm.NILPOTENT_MAX: Norm("nilpotent_max",
                              lambda a, b: np.where(a + b < 1.0, np.maximum(a, b), 1.0), True,
                              "NilpotentMaximum", "NMAX", also=(("fis", "nilpotent_maximum"),)),
    # fuzzylite's UnboundedSum (fuzzylite 6 and pyfuzzylite 8: a + b); fuzzylite 6's FCL has
    # no word for it and reads the class name, as its FclExporter writes it
    SNorm.UNBOUNDED_SUM: Norm("unbounded_sum", np.add, True, "UnboundedSum", "UnboundedSum",
                              also=(("fcl", "UnboundedSum"),)),
}

# An implication is a t-norm of the rule's level and the term's membership (model.Implication
# is TNorm): its records are the t-norms'.
IMPLICATIONS = T_NORMS

# Every hedge is nondecreasing on [0, 1].  fuzzylite's `extremely` is SHARPLY (its S-curve);
# FIS writes a power hedge as the fraction of a rule index (the Octave toolkit's, fis.py);
# IEC FCL has no hedges (fcl.py reads fuzzylite's words, and writes none).
HEDGES: dict[Hedge, HedgeOp] = {
    Hedge.NONE: HedgeOp("none", None, True, c_float="{mu}", exponent=1.0),
    Hedge.VERY: HedgeOp("very", _power(2.0), True, "very", fis=".2",
                        c_float="{mu} * {mu}", exponent=2.0),
    Hedge.SOMEWHAT: HedgeOp("somewhat", _power(0.5), True, "somewhat", fis=".05",
                            c_float="{sqrt}({mu})", exponent=0.5),
    Hedge.EXTREMELY: HedgeOp("extremely", _power(3.0), True, fis=".3",
                             c_float="{mu} * {mu} * {mu}", exponent=3.0),
    Hedge.SELDOM: HedgeOp("seldom", _seldom, True, "seldom"),
    Hedge.SHARPLY: HedgeOp("sharply", _sharply, True, "extremely"),
}


def _fold(snorm: SNorm) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    return S_NORMS[snorm].numpy


AGGREGATIONS: dict[Aggregation, AggregationOp] = {
    Aggregation.MAX: AggregationOp("max", _fold(SNorm.MAX), True, "Maximum", "MAX", "max",
                                   "{acc} = {p}greater({acc}, {x});",
                                   "{acc} = {acc} > {x} ? {acc} : {x};",
                                   snorm=SNorm.MAX, exact=True),
    # FCL: fuzzylite 6 has no word for it (its FclExporter writes the class name, and its
    # FclImporter reads no `SUM`): written so; jFuzzyLogic's `SUM` is read
    Aggregation.SUM: AggregationOp("sum", np.add, True, "UnboundedSum", "UnboundedSum", "sum",
                                   "{acc} += {x};", "{acc} += {x};",
                                   also=(("fcl", "SUM"), ("fcl", "UnboundedSum")), exact=True),
    Aggregation.PROBSUM: AggregationOp("probsum", _fold(SNorm.PROBSUM), True, "AlgebraicSum",
                                       "PROBOR", "probor",
                                       also=(("fz", "probabilistic_sum"), ("fcl", "ASUM"),
                                             ("fis", "algebraic_sum")),
                                       snorm=SNorm.PROBSUM, exact=True),
    Aggregation.BOUNDED_SUM: AggregationOp("bounded_sum", _fold(SNorm.BOUNDED_SUM), True,
                                           "BoundedSum", "BSUM",
                                           # NormalizedSum folds to min(1, sum) too (measured:
                                           # pyfuzzylite 8 and the fuzzylite 6 CLI)
                                           also=(("fll", "NormalizedSum"), ("fcl", "NSUM"),
                                                 ("fis", "bounded_sum")),
                                           snorm=SNorm.BOUNDED_SUM, exact=True),
    Aggregation.DRASTIC_SUM: AggregationOp("drastic_sum", _fold(SNorm.DRASTIC_SUM), True,
                                           "DrasticSum", "DSUM", also=(("fis", "drastic_sum"),),
                                           snorm=SNorm.DRASTIC_SUM),
    Aggregation.EINSTEIN_SUM: AggregationOp("einstein_sum", _fold(SNorm.EINSTEIN_SUM), True,
                                            "EinsteinSum", "ESUM",
                                            also=(("fis", "einstein_sum"),),
                                            snorm=SNorm.EINSTEIN_SUM),
    Aggregation.HAMACHER_SUM: AggregationOp("hamacher_sum", _fold(SNorm.HAMACHER_SUM), True,
                                            "HamacherSum", "HSUM",
                                            also=(("fis", "hamacher_sum"),),
                                            snorm=SNorm.HAMACHER_SUM),
    Aggregation.NILPOTENT_MAX: AggregationOp("nilpotent_max", _fold(SNorm.NILPOTENT_MAX), True,
                                             "NilpotentMaximum", "NMAX",
                                             also=(("fis", "nilpotent_maximum"),),
                                             snorm=SNorm.NILPOTENT_MAX),
}

# No defuzzifier is monotone in the term strengths: raising one strength moves the output
# toward that term, up or down.  fll: fuzzylite's defuzzifier class (center of area is its
# WeightedAverage with a grouping aggregation, Tsukamoto its WeightedAverage over monotonic
# terms); fcl: the METHOD word (COA is IEC's name for the bisector, COGS the singletons').
DEFUZZIFIERS: dict[Defuzzifier, DefuzzifierOp] = {
    Defuzzifier.CENTROID: DefuzzifierOp("centroid", crisp.centroid, False, "Centroid", "COG",
                                        "centroid", "area", family="area"),
    Defuzzifier.BISECTOR: DefuzzifierOp("bisector", crisp.bisector, False, "Bisector", "COA",
                                        "bisector", "area", family="area"),
    Defuzzifier.MEAN_OF_MAXIMUM: DefuzzifierOp("mean_of_maximum", crisp.mean_of_maximum, False,
                                               "MeanOfMaximum", "MM", "mom", "area",
                                               also=(("fz", "mom"),), family="area"),
    # sampled by the tools like the mean of maximum; the C back ends do not emit them (yet)
    Defuzzifier.SMALLEST_OF_MAXIMUM: DefuzzifierOp(
        "smallest_of_maximum", crisp.smallest_of_maximum, False, "SmallestOfMaximum", "LM",
        "som", None, also=(("fz", "som"),), family="area"),
    Defuzzifier.LARGEST_OF_MAXIMUM: DefuzzifierOp(
        "largest_of_maximum", crisp.largest_of_maximum, False, "LargestOfMaximum", "RM", "lom",
        None, also=(("fz", "lom"),), family="area"),
    Defuzzifier.CENTER_OF_AREA: DefuzzifierOp("center_of_area", crisp.safe_ratio, False,
                                              "WeightedAverage", "COGS", None, "num / den",
                                              "ratio", also=(("fz", "coa"),), family="peaks"),
    Defuzzifier.WEIGHTED_AVERAGE: DefuzzifierOp("weighted_average", crisp.safe_ratio, False,
                                                "WeightedAverage", None, "wtaver", "num / den",
                                                "ratio", family="peaks"),
    Defuzzifier.WEIGHTED_SUM: DefuzzifierOp("weighted_sum", crisp.weighted_sum, False,
                                            "WeightedSum", "COGSS", "wtsum", "num", "sum",
                                            family="peaks"),
    Defuzzifier.TSUKAMOTO: DefuzzifierOp("tsukamoto", crisp.safe_ratio, False,
                                         "WeightedAverage", family="inverse"),
    # fuzzylite's WeightedSum over monotonic terms (the Tsukamoto values summed, not averaged)
    Defuzzifier.TSUKAMOTO_SUM: DefuzzifierOp("tsukamoto_sum", crisp.weighted_sum, False,
                                             "WeightedSum", family="inverse"),
    # pyfuzzylite 8's WeightedSum with an aggregation (FLL writes WeightedSum and the
    # aggregation); no FCL, FIS or C emission (fuzzylite 6's COGSS ignores ACCU)
    Defuzzifier.GROUPED_SUM: DefuzzifierOp("grouped_sum", crisp.weighted_sum, False,
                                           "WeightedSum", family="peaks"),
}

REGISTRIES = {"and": T_NORMS, "or": S_NORMS, "implication": IMPLICATIONS,
              "aggregation": AGGREGATIONS, "defuzzify": DEFUZZIFIERS, "hedge": HEDGES}


def members(table: dict, where: Callable[[Operator], bool]) -> tuple:
    """The members of a registry whose record passes `where`, in enum order."""
    return tuple(k for k, rec in table.items() if where(rec))


def emitted_in_c(table: dict) -> tuple:
    """The allow-list of the float/double C back end for one kind of operator."""
    return members(table, lambda rec: rec.c_float is not None)


def emitted_in_fixed(table: dict) -> tuple:
    """The allow-list of the q15/q31 back ends for one kind of operator."""
    return members(table, lambda rec: rec.fixed is not None)


def names(table: dict, chosen) -> str:
    """`a, b and c`: the records' names, for refusals that say what is supported."""
    words = [table[k].name for k in chosen]
    return ", ".join(words[:-1]) + " and " + words[-1] if len(words) > 1 else "".join(words)


def format_words(table: dict, fmt: str, read: bool = True) -> dict:
    """word -> member in format `fmt` (fz, fll, fcl, fis): the written words in enum order,
    then, with `read`, the words only read (so a listing shows the written words first)."""
    out = {}
    for k, rec in table.items():
        written = rec.word if fmt == "fz" else getattr(rec, fmt)
        if written:
            out.setdefault(written, k)
    for k, rec in table.items():
        for word in rec.also_in(fmt) if read else ():
            out.setdefault(word, k)
    return out


def power_exponents() -> np.ndarray:
    """The exponents of the power hedges indexed by Hedge; they are the first members, so an
    index of a piecewise hedge falls outside (code that only knows powers fails loudly)."""
    powers = [rec.exponent for rec in HEDGES.values() if rec.exponent is not None]
    assert list(HEDGES)[:len(powers)] == list(Hedge)[:len(powers)], "power hedges come first"
    return np.array(powers)
