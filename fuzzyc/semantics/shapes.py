"""The registry of term shapes: one record per TermKind holds everything about the shape.

The builder, the importers and exporters, the engine, the verifier and the C back ends read
these records instead of restating a shape's meaning; a back end's capability is an allow-list
derived from them (`c_kinds()`, `enclosed_kinds()`), so a shape a record says nothing about is
refused by name, never handled wrongly.  The meaning itself is the model's docstring
(`fuzzyc.semantics.model`); the numpy functions are in `shape_functions`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from . import shape_derivatives as d
from . import shape_enclosures as enc
from . import shape_functions as f
from . import shape_levels as levels
from .model import TermKind

INF = math.inf
Values = Sequence[float]


@dataclass(frozen=True)
class Word:
    """A `.fz` word for a shape: `NAME = word(n1, n2, ...)`."""
    word: str
    arity: int | None                          # None: any count (linear, discrete)
    valid: Callable[[Values], bool]            # the numbers make a well-defined term
    message: Callable[[Values, str], str]      # (numbers, term name) -> why not
    params: Callable[[Values], tuple]          # the numbers -> the model's params
    at: int = 0                                # the number an error points at
    plain: bool = False                        # params are the numbers in the model's order
    usage: str = ""                                # how to write it, for the messages
    # other formats' names for this word where its record's fll/fcl/fis name another word
    # (MATLAB's trimf is `tri`): the parser's "did you mean" reads them
    names: tuple[str, ...] = ()


@dataclass(frozen=True)
class Shape:
    """Everything about one term shape.  None in a field = not supported, by name."""
    kind: TermKind
    words: tuple[Word, ...]
    # membership(x, p): x (N, 1) and params p (T, 4) -> (N, T), or x (T,) -> (T,); for the
    # per-term shapes (points, formulas) p is that term's own data
    membership: Callable
    core: Callable[[Values], tuple[float, float]]      # where it is 1 (or its centre)
    support: Callable                                  # p (T, 4) -> where mu > 0: lo, hi (T,)
    peak: Callable                                     # (params or points, lo, hi) -> float
    monotone: Callable[[Values], bool]                 # one inverse exists (Tsukamoto)
    inverse: Callable | None                           # (a, b, c, d, y) -> z with mu(z) = y
    critical: Callable | None                          # p (T, 4) -> (T, K) turning/jump points
    enclosure: Callable | None                         # (p, lo (N,), hi (N,)) -> low, high
    exact: bool                                        # the enclosure's ends are attained
    derivative: Callable | None                        # (x, p) -> d mu / d p (..., 4)
    superlevel: Callable | None                        # (p, lam, strict) -> {mu >= lam}
    fll: str | None
    fcl: str | None
    fis: str | None
    fis_params: Callable | None                        # (a, b, c, d) -> MATLAB's order
    c_float: Callable | None                           # (row, x, prefix, fn, lit) -> C expr
    c_row: Callable | None                             # params (4,) -> the C table's 6 numbers
    c_fixed_input: bool                                # the q15/q31 input partitions take it
    on_inputs: bool = True
    per_term: bool = False                             # its data is not the params row
    notes: str = ""                                    # what it does not support, and why

    @property
    def name(self) -> str:
        return self.kind.name.lower()


# -- the .fz words -------------------------------------------------------------------------

def _numbers(values: Values) -> str:
    return ", ".join(f"{v:g}" for v in values)


def _ordered(points: Values) -> bool:
    return not any(p > q for p, q in zip(points, points[1:])) and points[0] != points[-1]


def _said(text: str) -> Callable[[Values, str], str]:
    return lambda values, name: text.format(name=name)


def _plain(word: str, arity: int, valid: Callable[[Values], bool], usage: str) -> Word:
    """A word whose numbers are the model's params in order."""
    return Word(word, arity, valid, lambda values, name: f"degenerate {word} `{name}`: write "
                                                         f"{usage}",
                lambda v: (*v, 0.0, 0.0, 0.0)[:max(4, arity)], plain=True, usage=usage)


# what a triangle's and a trapezoid's break points must satisfy (every format's messages)
TRIANGLE_NEEDS = "a <= b <= c with a < c"
TRAPEZOID_NEEDS = "a <= b <= c <= d with a < d"
TRAPEZOID_WORDS = (
    Word("tri", 3, lambda v: _ordered([v[0], v[1], v[1], v[2]]),
         lambda v, name: f"degenerate tri `{name}`({_numbers(v)}): break points must satisfy "
                         + TRIANGLE_NEEDS,
         lambda v: (v[0], v[1], v[1], v[2]), names=("trimf", "Triangle", "TRIAN")),
    Word("trap", 4, lambda v: _ordered(list(v)),
         lambda v, name: f"degenerate trap `{name}`({_numbers(v)}): break points must satisfy "
                         + TRAPEZOID_NEEDS,
         lambda v: tuple(v), names=("trapmf", "Trapezoid", "TRAPE", "Rectangle", "rectmf")),
    Word("lshoulder", 2, lambda v: v[0] < v[1],
         _said("lshoulder `{name}` needs its top end before its foot: lshoulder(c, d) with "
               "c < d"), lambda v: (-INF, -INF, *v), names=("Ramp", "rampmf")),
    Word("rshoulder", 2, lambda v: v[0] < v[1],
         _said("rshoulder `{name}` needs rshoulder(a, b) with a < b"), lambda v: (*v, INF, INF),
         names=("Ramp", "rampmf")),
)


# -- core, peak, support ---------------------------------------------------------------------

def _at_first(p: Values) -> tuple[float, float]:
    return p[0], p[0]


def _between(i: int, j: int) -> Callable[[Values], tuple[float, float]]:
    return lambda p: (p[i], p[j])


def _edge(edge: int, rising: Callable[[Values], bool]) -> Callable[[Values], tuple]:
    """An edge: fully true from its end on (rising) or up to it."""
    return lambda p: (p[edge], INF) if rising(p) else (-INF, p[edge])


def _discrete_core(values: Values) -> tuple[float, float]:
    """x1 y1 x2 y2 ...: where y is highest."""
    top = [x for x, y in zip(values[0::2], values[1::2]) if y == max(values[1::2])]
    return top[0], top[-1]


def _peak_param(i: int):
    return lambda p, lo, hi: p[i]


def _peak_mid(i: int, j: int):
    return lambda p, lo, hi: 0.5 * (p[i] + p[j])


def _trapezoid_peak(p, lo, hi) -> float:
    low = p[1] if np.isfinite(p[1]) else lo
    high = p[2] if np.isfinite(p[2]) else hi
    return 0.5 * (low + high)


def _discrete_peak(xy, lo, hi) -> float:     # the mean of the highest points
    return float(np.mean(xy[xy[:, 1] == xy[:, 1].max(), 0]))


def _no_peak(p, lo, hi) -> float:
    return np.nan                            # no fixed value: depends on the inputs


def _everywhere(p):
    return np.full(len(p), -INF), np.full(len(p), INF)


def _columns(i: int, j: int):
    return lambda p: (p[:, i], p[:, j])


def _from(i: int, upward: Callable):
    """The support of an edge at column i: [p_i, inf) where upward(p), else (-inf, p_i]."""
    return lambda p: (np.where(upward(p), p[:, i], -INF), np.where(upward(p), INF, p[:, i]))


def _discrete_support(xy):
    positive = np.flatnonzero(xy[:, 1] > 0)
    if positive.size == 0:          # nowhere positive: say nothing narrower than the range
        return -INF, INF
    first, last = positive[0], positive[-1]
    return (-INF if first == 0 else xy[first - 1, 0],
            INF if last == len(xy) - 1 else xy[last + 1, 0])


def _never(p) -> bool:
    return False


def _always(p) -> bool:
    return True


# -- inverses (Tsukamoto) -------------------------------------------------------------------

def _s_inverse(a, b, c, dd, y):
    low, high = np.sqrt(y / 2.0), np.sqrt((1.0 - y) / 2.0)
    return np.where(y <= 0.5, a + (b - a) * low, b - (b - a) * high)


def _z_inverse(a, b, c, dd, y):
    low, high = np.sqrt(y / 2.0), np.sqrt((1.0 - y) / 2.0)
    return np.where(y <= 0.5, b - (b - a) * low, a + (b - a) * high)


# -- critical points -------------------------------------------------------------------------

def _critical(*columns: int):
    return lambda p: p[:, list(columns)]


def _gaussian_product_critical(p):
    """Both means, and where the two gaussians' product peaks when they overlap (mean_b <
    mean_a): the sigma-weighted mean, which lies between them."""
    ma, sa, mb, sb = p.T
    with np.errstate(invalid="ignore", divide="ignore"):
        inner = (ma * sb ** 2 + mb * sa ** 2) / (sa ** 2 + sb ** 2)
    return np.stack([ma, mb, np.where(mb < ma, inner, np.nan)], axis=1)


def _rounded_up(enclose):
    """An enclosure whose interior top is in no parameter: the engine's floats around it
    may round a few ulps above the value at the computed point, so its top is raised by 4
    ulps (1 stays 1)."""
    def wider(p, lo, hi):
        low, high = enclose(p, lo, hi)
        return low, np.minimum(1.0, high * (1.0 + 4.0 * np.finfo(float).eps))
    return wider


def _semi_ellipse_critical(p):
    s, e = np.minimum(p[:, 0], p[:, 1]), np.maximum(p[:, 0], p[:, 1])
    return np.stack([s, s + 0.5 * (e - s), e], axis=1)     # the centre as the engine has it


# -- C (float/double) ------------------------------------------------------------------------

def _trapezoid_row(params) -> list[float]:
    """a b c d 1/(b-a) 1/(d-c); shoulders have a = b = -inf or c = d = +inf."""
    a, b, c, dd = (float(v) for v in params)
    if np.isneginf(a):
        b = -np.inf
    if np.isposinf(dd):
        c = np.inf
    rise = 1.0 / (b - a) if np.isfinite(a) and b > a else 0.0
    fall = 1.0 / (dd - c) if np.isfinite(dd) and dd > c else 0.0
    return [a, b, c, dd, rise, fall]


def _padded_row(params) -> list[float]:
    return list(params) + [0.0, 0.0]


def _gaussian_row(params) -> list[float]:
    return list(params) + [1.0 / (2.0 * params[1] ** 2), 0.0]


def _c_trapezoid(row, x, p, fn, lit) -> str:
    return f"{p}trapezoid({x}, {row})"


def _c_singleton(row, x, p, fn, lit) -> str:
    return f"({x} == {row}[0] ? {lit(1)} : {lit(0)})"


def _c_gaussian(row, x, p, fn, lit) -> str:
    return f"{p}number_or_zero({fn('exp')}(-({x} - {row}[0]) * ({x} - {row}[0]) * {row}[4]))"


def _c_bell(row, x, p, fn, lit) -> str:
    return (f"{p}number_or_zero({lit(1)} / ({lit(1)} + {fn('pow')}({fn('fabs')}(({x} - "
            f"{row}[0]) / {row}[1]), {lit(2)} * {row}[2])))")


def _c_sigmoid(row, x, p, fn, lit) -> str:
    # 0 * inf (slope 0, infinite x) is NaN in C too, hence number_or_zero
    return f"{p}number_or_zero({lit(1)} / ({lit(1)} + {fn('exp')}(-{row}[1] * ({x} - {row}[0]))))"


NO_C = "no C emission (use the lookup-table back end)"


def _record(kind: TermKind, words: tuple[Word, ...], membership, core, support, peak, *,
            critical=None, enclosure=None, exact=True, derivative=None, superlevel=None,
            monotone=_never,
            inverse=None, fll=None, fcl=None, fis=None, fis_params=None, c_float=None,
            c_row=_padded_row, c_fixed_input=False, on_inputs=True, per_term=False,
            notes="") -> Shape:
    if enclosure is None and critical is not None:
        enclosure = enc.by_critical_points(membership, critical)
    if c_float is None:
        notes = "; ".join(n for n in (notes, NO_C) if n)
        c_row = None
    if derivative is None and "derivative" not in notes:
        notes = "; ".join(n for n in (notes, "no derivative") if n)
    if superlevel is None:
        notes = "; ".join(n for n in (notes, "no closed-form level sets (proof methods)") if n)
    return Shape(kind, words, membership, core, support, peak, monotone, inverse, critical,
                 enclosure, exact, derivative, superlevel, fll, fcl, fis, fis_params, c_float,
                 c_row, c_fixed_input, on_inputs, per_term, notes)


def _monotone_trapezoid(p) -> bool:
    return bool(np.isinf(p[0]) != np.isinf(p[3]))


def _z_of_pishape(x, p):
    return f.mu_zshape(x, p[:, 2:])


def _pi_plateau(p):
    return p[:, 1] <= p[:, 2]


_RECORDS = (
    _record(TermKind.TRAPEZOID, TRAPEZOID_WORDS, f.mu_trapezoid, _between(1, 2), _columns(0, 3),
            _trapezoid_peak,
            superlevel=levels.trapezoid, critical=_critical(0, 1, 2, 3),
            derivative=d.d_trapezoid,
            monotone=_monotone_trapezoid,
            inverse=lambda a, b, c, dd, y: np.where(np.isinf(dd), a + (b - a) * y,
                                                    dd - (dd - c) * y),
            fll="Trapezoid", fcl="TRAPE", fis="trapmf", c_float=_c_trapezoid,
            c_row=_trapezoid_row, c_fixed_input=True),
    _record(TermKind.GAUSSIAN, (Word("gauss", 2, lambda v: v[1] > 0,
                                     _said("gauss `{name}` needs a width > 0"),
                                     lambda v: (*v, 0, 0), at=1),),
            f.mu_gaussian, _at_first, _everywhere, _peak_param(0),
            superlevel=levels.gaussian, critical=_critical(0),
            derivative=d.d_gaussian, fll="Gaussian", fcl="GAUSS", fis="gaussmf",
            fis_params=lambda a, b, c, dd: (b, a), c_float=_c_gaussian, c_row=_gaussian_row),
    _record(TermKind.BELL, (Word("bell", 3, lambda v: v[1] > 0 and v[2] > 0,
                                 _said("bell `{name}` needs width > 0 and slope > 0"),
                                 lambda v: (*v, 0), at=1),),
            f.mu_bell, _at_first, _everywhere, _peak_param(0),
            superlevel=levels.bell, critical=_critical(0),
            derivative=d.d_bell, fll="Bell", fcl="GBELL", fis="gbellmf",
            fis_params=lambda a, b, c, dd: (b, c, a), c_float=_c_bell),
    _record(TermKind.SIGMOID, (Word("sigmoid", 2, lambda v: v[1] != 0,
                                    _said("sigmoid `{name}` needs a slope other than 0"),
                                    lambda v: (*v, 0, 0), at=1),),
            f.mu_sigmoid, _at_first, _everywhere, _peak_param(0),
            superlevel=levels.sigmoid, critical=_critical(),
            derivative=d.d_sigmoid, monotone=_always,
            inverse=lambda a, b, c, dd, y: a - np.log(1.0 / y - 1.0) / b,
            fll="Sigmoid", fcl="SIGM", fis="sigmf", fis_params=lambda a, b, c, dd: (b, a),
            c_float=_c_sigmoid),
    _record(TermKind.SINGLETON, (Word("singleton", 1, _always, _said(""),
                                      lambda v: (v[0], 0, 0, 0)),),
            f.mu_singleton, _at_first, _columns(0, 0), _peak_param(0),
            superlevel=levels.singleton, critical=_critical(0),
            monotone=_always, inverse=lambda a, b, c, dd, y: a, fll="Constant", fis="constant",
            c_float=_c_singleton,
            notes="a step: no derivative; FCL writes it as a bare number"),
    # start = end is a step (0 up to start, 1 above it), as fuzzylite 6 and pyfuzzylite 8
    # compute it: their branches never divide by end - start then (FIS refuses it: fis.py)
    _record(TermKind.SSHAPE, (_plain("sshape", 2, lambda v: v[0] <= v[1],
                                     "sshape(start, end) with start <= end"),),
            f.mu_sshape, _edge(1, _always), _from(0, lambda p: True), _peak_param(1),
            critical=_critical(), derivative=d.d_sshape, monotone=_always, inverse=_s_inverse,
            fll="SShape", fis="smf", fis_params=lambda a, b, c, dd: (a, b)),
    _record(TermKind.ZSHAPE, (_plain("zshape", 2, lambda v: v[0] <= v[1],
                                     "zshape(start, end) with start <= end"),),
            f.mu_zshape, _edge(0, _never), _from(1, lambda p: False), _peak_param(0),
            critical=_critical(), derivative=d.d_zshape, monotone=_always, inverse=_z_inverse,
            fll="ZShape", fis="zmf", fis_params=lambda a, b, c, dd: (a, b)),
    _record(TermKind.PISHAPE, (_plain("pishape", 4, lambda v: v[0] <= v[1] and v[2] <= v[3],
                                      "pishape(a, b, c, d) with a <= b and c <= d"),),
            f.mu_pishape, _between(1, 2), _columns(0, 3), _peak_mid(1, 2),
            critical=_critical(1, 2),
            # where S and Z overlap (b > c) the top is inside, in no closed form: compose
            enclosure=enc.choose(_pi_plateau,
                                 enc.by_critical_points(f.mu_pishape, _critical(1, 2)),
                                 enc.product_of(f.mu_sshape, _z_of_pishape)),
            exact=False, derivative=d.d_pishape, fll="PiShape", fis="pimf",
            fis_params=lambda a, b, c, dd: (a, b, c, dd),
            notes="enclosure exact only when b <= c"),
    _record(TermKind.SPIKE, (_plain("spike", 2, lambda v: v[1] > 0,
                                    "spike(center, width) with width > 0"),),
            f.mu_spike, _at_first, _everywhere, _peak_param(0), critical=_critical(0),
            derivative=d.d_spike, fll="Spike", fis="spikemf"),
    _record(TermKind.COSINE, (_plain("cosine", 2, lambda v: v[1] > 0,
                                     "cosine(center, width) with width > 0"),),
            f.mu_cosine, _at_first,
            lambda p: (p[:, 0] - 0.5 * p[:, 1], p[:, 0] + 0.5 * p[:, 1]), _peak_param(0),
            critical=_critical(0), derivative=d.d_cosine, fll="Cosine", fis="cosinemf"),
    _record(TermKind.CONCAVE, (_plain("concave", 2, lambda v: v[0] != v[1],
                                      "concave(inflection, end) with inflection != end"),),
            f.mu_concave, _edge(1, lambda p: p[0] < p[1]), _everywhere, _peak_param(1),
            critical=_critical(1), derivative=d.d_concave, monotone=_always,
            inverse=lambda a, b, c, dd, y: 2.0 * b - a - (b - a) / y,
            fll="Concave", fis="concavemf"),
    _record(TermKind.LINEAR, (Word("linear", None, _always, _said(""),
                                   lambda v: (*v, 0, 0, 0)[:max(4, len(v))]),),
            f.mu_linear, lambda p: (-INF, INF), _everywhere, _no_peak, enclosure=enc.zero,
            fll="Linear", fis="linear", on_inputs=False,
            notes="a Takagi-Sugeno consequent, not a shape: membership 0, no peak, no "
                  "inverse, no derivative"),
    _record(TermKind.SIGMOID_DIFFERENCE,
            (_plain("sigmoid_difference", 4, lambda v: v[1] != 0 and v[2] != 0,
                    "sigmoid_difference(left, rising, falling, right) with slopes != 0"),),
            f.mu_sigmoid_difference, _between(0, 3), _everywhere, _peak_mid(0, 3),
            enclosure=enc.distance_of(f.mu_sigmoid,
                                      lambda x, p: f.mu_sigmoid(x, p[:, [3, 2]])),
            exact=False, derivative=d.d_sigmoid_difference, fll="SigmoidDifference",
            fis="dsigmf", notes="enclosure by its monotone sigmoids: sound, not exact"),
    _record(TermKind.SIGMOID_PRODUCT,
            (_plain("sigmoid_product", 4, lambda v: v[1] != 0 and v[2] != 0,
                    "sigmoid_product(left, rising, falling, right) with slopes != 0"),),
            f.mu_sigmoid_product, _between(0, 3), _everywhere, _peak_mid(0, 3),
            enclosure=enc.product_of(f.mu_sigmoid, lambda x, p: f.mu_sigmoid(x, p[:, [3, 2]])),
            exact=False, derivative=d.d_sigmoid_product, fll="SigmoidProduct", fis="psigmf",
            notes="enclosure by its monotone sigmoids: sound, not exact"),
    _record(TermKind.GAUSSIAN_PRODUCT,
            (_plain("gaussian_product", 4, lambda v: v[1] > 0 and v[3] > 0,
                    "gaussian_product(mean_a, sigma_a, mean_b, sigma_b) with sigmas > 0"),),
            f.mu_gaussian_product, _between(0, 2), _everywhere, _peak_mid(0, 2),
            critical=_gaussian_product_critical, derivative=d.d_gaussian_product,
            enclosure=_rounded_up(enc.by_critical_points(f.mu_gaussian_product,
                                                         _gaussian_product_critical)),
            fll="GaussianProduct", fis="gauss2mf"),
    _record(TermKind.BINARY, (_plain("binary", 2, lambda v: v[0] != v[1],
                                     "binary(start, direction) with direction != start"),),
            f.mu_binary, _edge(0, lambda p: p[0] < p[1]), _from(0, lambda p: p[:, 1] > p[:, 0]),
            _peak_param(0), critical=_critical(0), fll="Binary",
            notes="a step: no derivative"),
    _record(TermKind.SEMI_ELLIPSE, (_plain("semi_ellipse", 2, lambda v: v[0] != v[1],
                                           "semi_ellipse(start, end) with start != end"),),
            f.mu_semi_ellipse, lambda p: (0.5 * (p[0] + p[1]),) * 2,
            lambda p: (np.minimum(p[:, 0], p[:, 1]), np.maximum(p[:, 0], p[:, 1])),
            _peak_mid(0, 1), critical=_semi_ellipse_critical, derivative=d.d_semi_ellipse,
            fll="SemiEllipse"),
    _record(TermKind.ARC, (_plain("arc", 2, lambda v: v[0] != v[1],
                                  "arc(start, end) with start != end"),),
            f.mu_arc, _edge(1, lambda p: p[0] < p[1]), _from(0, lambda p: p[:, 0] < p[:, 1]),
            _peak_param(1), critical=_critical(0, 1), derivative=d.d_arc, fll="Arc"),
    _record(TermKind.DISCRETE, (Word("discrete", None, lambda v: not f.discrete_problem(v),
                                     lambda v, name: f"discrete `{name}`: "
                                                     f"{f.discrete_problem(v)}",
                                     lambda v: tuple(v)),),
            f.mu_discrete, _discrete_core, _discrete_support, _discrete_peak,
            enclosure=enc.discrete, fll="Discrete", fis="discretemf", per_term=True,
            notes="its data is Variable.points (K, 2), one term at a time; no derivative"),
    _record(TermKind.FUNCTION, (), f.mu_function, lambda p: (-INF, INF),
            lambda p: (-INF, INF), _no_peak, fll="Function", fis="function", per_term=True,
            notes="a formula (Variable.formulas), one term at a time: no .fz word, no "
                  "enclosure, no inverse, no derivative"),
)

SHAPES: dict[TermKind, Shape] = {record.kind: record for record in _RECORDS}

# `.fz` word -> (record, word)
WORDS: dict[str, tuple[Shape, Word]] = {w.word: (s, w) for s in _RECORDS for w in s.words}


def shape_words() -> list[str]:
    """Every `.fz` shape word, in the registry's order."""
    return list(WORDS)


def c_kinds() -> frozenset[TermKind]:
    """The kinds the float/double C headers emit."""
    return frozenset(k for k, s in SHAPES.items() if s.c_float is not None)


def enclosed_kinds() -> frozenset[TermKind]:
    """The kinds with a sound enclosure over intervals (what set-valued evaluation takes)."""
    return frozenset(k for k, s in SHAPES.items() if s.enclosure is not None)


def plain_words() -> dict[str, tuple[Shape, Word]]:
    """The words whose numbers are the model's params in order (every format writes those
    as NAME p1 p2 ...)."""
    return {w.word: (s, w) for s, w in WORDS.values() if w.plain}


def provable_kinds() -> frozenset[TermKind]:
    """The kinds the proof methods take (closed-form level sets)."""
    return frozenset(k for k, s in SHAPES.items() if s.superlevel is not None)


def term_core(kind: TermKind, params) -> tuple[float, float]:
    """The interval where a term is fully true (or its centre): it must meet the range."""
    return SHAPES[TermKind(int(kind))].core(params)


def enclosures(kinds: np.ndarray, params: np.ndarray, points: dict | None,
               lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least and largest membership (N, T) of terms (kinds (T,), params (T, 4), DISCRETE
    points) over the boxes [lo, hi] (N,).  ValueError naming a shape without an enclosure."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    params = np.asarray(params, dtype=float)
    low, high = np.zeros((len(lo), len(kinds))), np.zeros((len(lo), len(kinds)))
    for kind in np.unique(kinds):
        record = SHAPES[TermKind(int(kind))]
        if record.enclosure is None:
            raise ValueError(f"{record.name} terms have no enclosure over intervals")
        cols = np.flatnonzero(kinds == kind)
        if record.per_term:
            for t in cols:
                low[:, t], high[:, t] = record.enclosure((points or {})[int(t)], lo, hi)
            continue
        low[:, cols], high[:, cols] = record.enclosure(params[cols], lo, hi)
    return low, high
