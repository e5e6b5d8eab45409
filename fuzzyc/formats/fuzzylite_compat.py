"""fuzzylite's numbers, for users validating a migration: the integral defuzzifiers sampled the
way fuzzylite samples them.

fuzzylite (C++ 6 and pyfuzzylite 8 alike) integrates Centroid, Bisector and MeanOfMaximum with
the midpoint rule: the aggregated set is evaluated at u_k = lo + (k + 1/2)(hi - lo)/n,
k = 0..n-1, n = the defuzzifier's resolution (C++ default 100, pyfuzzylite 8 default 1000), and
  Centroid = sum u_k M(u_k) / sum M(u_k);
  Bisector = the mean of the u_k where |cumsum(M)_k / cumsum(M)_(n-1) - 1/2| is smallest
    (normalised by the cumsum's last element, as fuzzylite: normalising by a pairwise sum M
    instead differs in the last bit and moved near-ties by one sample, 0.001-0.002 off on
    tests/format_corpus/ramp.fll at n = 1000 under Maximum and UnboundedSum aggregation);
  MeanOfMaximum = the mean of the u_k where M is largest (and positive);
  SmallestOfMaximum / LargestOfMaximum = the smallest / largest such u_k (pyfuzzylite 8; fuzzylite
    6 scans from the left with its 1e-6 tolerance: a larger sample for the smallest, a larger or
    equal one for the largest; Octave: the samples equal to the maximum).
The Bisector above is pyfuzzylite 8's; fuzzylite 6's (its Bisector.cpp, under
`--semantics fuzzylite`) sweeps the midpoints from both ends, adding to the smaller side's
area, and returns the two last midpoints' area-weighted average (`_fuzzylite6_bisector`;
measured against the fuzzylite 6 CLI by the differential fuzzer's kept Bisector cases).
The model's own defuzzifiers integrate exactly.  Agreement with pyfuzzylite 8.0.6, all three
methods, n = 100 and 1000, aggregation Maximum / AlgebraicSum / BoundedSum / UnboundedSum x
implication Minimum / AlgebraicProduct (tests/test_formats_fuzzylite.py, live; and
tests/test_fuzzylite_pinned.py, recorded outputs, checked without fuzzylite):
- tipper.fll (2000 random inputs): at most 2.0e-14 (Centroid), 7.1e-15 (MeanOfMaximum), 0
  (Bisector); ramp.fll (41 x 41 input grid, where rule levels repeat and bisector near-ties
  decide): at most 8.9e-16 -- same midpoints and fuzzylite's operation order, so even
  exact-equality ties fall on the same samples.
Measured on tests/format_corpus/tipper.fll (output range [0, 30], 2000 random inputs):
- the exact centroid differs from fuzzylite's by at most 0.0087 at n = 100 and 0.00015 at
  n = 1000 (the midpoint rule's error);
- the bisector and mean of maximum differ by about half a sample step typically, but a lot where
  sampling changes the answer: fuzzylite's bisector returns the middle of a zero-membership gap
  whose samples tie for "closest to half" (14.85 where the exact bisector is 20.27), and its
  mean of maximum misses a triangle's peak that falls between samples (4.95 where the exact
  answer is 25); median differences 0.17 and 0.05, maxima 5.4 and 20 at n = 100.
The peak-based defuzzifiers (weighted average, weighted sum, center of area) are exact in both
tools and are taken from the engine unchanged.
"""
from __future__ import annotations

from enum import Enum
from typing import Callable, Sequence

import numpy as np

from ..engine.inference import activations, evaluate
from ..engine.membership import memberships
from ..semantics.model import (Aggregation, Defuzzifier, RuleBase, SNorm, TermKind, TNorm,
                               aggregation_snorm)
from ..engine.norms import combine, implied

SAMPLED = (Defuzzifier.CENTROID, Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM,
           Defuzzifier.SMALLEST_OF_MAXIMUM, Defuzzifier.LARGEST_OF_MAXIMUM)
EXTREMES = (Defuzzifier.SMALLEST_OF_MAXIMUM, Defuzzifier.LARGEST_OF_MAXIMUM)
CHUNK_FLOATS = 1 << 22
# fuzzylite folds AlgebraicSum (a + b - ab) and BoundedSum (min(1, a + b)) over the rules in
# order; the same fold here, so sampled ties fall where fuzzylite's do
AGGREGATE = {Aggregation.MAX: lambda g: g.max(axis=1), Aggregation.SUM: lambda g: g.sum(axis=1),
             Aggregation.PROBSUM: lambda g: _fold(g, SNorm.PROBSUM),
             Aggregation.BOUNDED_SUM: lambda g: _fold(g, SNorm.BOUNDED_SUM)}


FL_EPSILON = 1e-6      # fuzzylite's Op::isEq tolerance


class Sampling(Enum):
    """Where a tool samples the output range, and how it sums the samples."""
    MIDPOINT = "midpoint"     # fuzzylite: u_k = lo + (k + 1/2) step, plain sums
    TRAPEZOID = "trapezoid"   # Octave/MATLAB: linspace(lo, hi, n), trapz (end samples halved)


def evaluate_sampled(rb: RuleBase, x: np.ndarray, resolution: int | Sequence[int] = 100,
                     sampling: Sampling = Sampling.MIDPOINT,
                     methods: tuple[Defuzzifier, ...] = SAMPLED,
                     first_plateau: bool = False, octave: bool = False,
                     activations: Callable = activations) -> np.ndarray:
    """x (N, I) -> y (N, O) as fuzzylite computes it with integral defuzzifiers sampled at
    `resolution` midpoints (or as Octave does, `sampling`); `resolution` is one for every
    output or one per output (each fuzzylite OutputVariable has its own defuzzifier and
    resolution: `defuzzifier: Centroid 300`); `methods` are the defuzzifiers sampled, the
    others as the engine (every tool is exact there).  `first_plateau`: the mean of maximum
    over the first run of maximal samples only, and fuzzylite 6's other scans (its smallest
    and largest of maximum, its bisector from both ends).  `octave`: the Octave
    toolkit's own arithmetic (`_octave_defuzzify`): its n-ary drastic sum over every rule
    (`octave_drastic_sum`), its bisector (a sample's index) and its values where the set is
    empty (no default).  `activations`: the rules' activations (N, R) at x, by default the
    engine's (tool_semantics.octave_activations: the toolkit's n-ary drastic norms)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    y = evaluate(rb, x)
    sampled = [o for o in range(len(rb.outputs)) if _is_sampled(rb, o, methods)]
    if not sampled:
        return y
    per_output = [resolution] * len(rb.outputs) if isinstance(resolution, (int, np.integer)) \
        else [int(r) for r in resolution]
    rows = max(1, CHUNK_FLOATS // max(1, rb.n_rules * max(per_output)))
    for start in range(0, x.shape[0], rows):
        act = activations(rb, x[start:start + rows])
        for o in sampled:
            y[start:start + rows, o] = _defuzzify(rb, o, act, per_output[o], sampling,
                                                  first_plateau, octave)
    return y


def _is_sampled(rb: RuleBase, o: int, methods) -> bool:
    singletons = bool(np.all(rb.outputs[o].kinds == TermKind.SINGLETON))
    return rb.inference_of(o).defuzzifier in methods and not singletons


def _samples(var, resolution: int, sampling: Sampling) -> tuple[np.ndarray, np.ndarray | None]:
    """(u (K,), trapz weights (K,) or None for plain sums)."""
    if sampling == Sampling.TRAPEZOID:
        u = octave_linspace(var.lo, var.hi, resolution)
        w = np.full(resolution, (var.hi - var.lo) / (resolution - 1))
        w[[0, -1]] *= 0.5
        return u, w
    # The midpoints computed with fuzzylite's own operation order, so that ties match bit for bit.
    return var.lo + (np.arange(resolution) + 0.5) * ((var.hi - var.lo) / resolution), None


def octave_linspace(lo: float, hi: float, n: int) -> np.ndarray:
    """Octave 7's linspace, bit for bit: built from both ends (lo + i d and hi - i d, d =
    (hi - lo) / (n - 1)), the middle element of an odd count (lo + hi) / 2.  numpy's
    lo + i d differs in the last bit in the upper half, which decides the ties of the
    maximum-based defuzzifiers (som 7.8 for Octave's 7.9 on tests/tool_numbers/extremes_som.fis)."""
    u, d = np.empty(n), (hi - lo) / (n - 1)
    i = np.arange(1, n // 2)
    u[0], u[-1], u[i], u[n - 1 - i] = lo, hi, lo + i * d, hi - i * d
    if n % 2:
        u[n // 2] = 0.0 if lo == -hi else (lo + hi) / 2
    return u


def _defuzzify(rb: RuleBase, o: int, act: np.ndarray, resolution: int,
               sampling: Sampling, first_plateau: bool, octave: bool = False) -> np.ndarray:
    var, inf = rb.outputs[o], rb.inference_of(o)
    rules = np.flatnonzero(rb.consequents[:, o] >= 0)
    if not rules.size and not octave:   # no rule concludes the output: its set is empty
        return np.full(act.shape[0], var.default)
    u, w = _samples(var, resolution, sampling)                                       # (K,)
    if not rules.size:      # the toolkit defuzzifies the empty set as it is (no default)
        return _octave_defuzzify(np.zeros((act.shape[0], u.size)), u, w, inf.defuzzifier)
    mu = memberships(var, u)[:, rb.consequents[rules, o]].T                          # (R, K)
    a = act[:, rules, None]                                                          # (N, R, 1)
    if first_plateau and inf.implication == TNorm.DRASTIC_PRODUCT:
        clipped = fuzzylite6_drastic_product(a, mu)
    elif first_plateau and inf.implication in FL6_T:      # fuzzylite 6's, within 1e-6
        clipped = FL6_T[inf.implication](a, mu)
    else:
        clipped = implied(a, mu, inf.implication)
    if first_plateau or sampling == Sampling.MIDPOINT:
        # fuzzylite 6 and pyfuzzylite 8 fold Aggregated::membership from 0 (mu = 0, then mu =
        # S(mu, term) per term): a zero rule in front gives the same bits where the implied
        # sets lie in [0, 1], and their numbers where an activation above 1 (an unbounded sum
        # of clauses) makes an implication leave [0, 1] (Einstein's product with a pole: the
        # maximum drops its negative side)
        clipped = np.concatenate([np.zeros_like(clipped[:, :1]), clipped], axis=1)
    if first_plateau and inf.aggregation == Aggregation.DRASTIC_SUM:
        m = np.zeros((clipped.shape[0], clipped.shape[2]))
        for r in range(clipped.shape[1]):       # Aggregated::membership: from 0, in order
            m = np.where(np.abs(np.minimum(m, clipped[:, r])) < FL_EPSILON,
                         np.maximum(m, clipped[:, r]), 1.0)
    elif octave and inf.aggregation == Aggregation.DRASTIC_SUM:
        m = octave_drastic_sum(clipped, a[:, :, 0] > 0,
                               rules.size == rb.n_rules and not any(merged_rows(rb)))
    else:
        m = AGGREGATE[inf.aggregation](clipped) if inf.aggregation in AGGREGATE else \
            _fold(clipped, aggregation_snorm(inf.aggregation),
                  FL6_S if first_plateau else None)
    if octave and rb.n_rules == 1 and rules.size == 1 and not any(merged_rows(rb)):
        m = _octave_one_rule(clipped[:, 0, :], inf.aggregation)
    if octave:
        return _octave_defuzzify(m, u, w, inf.defuzzifier)
    total = m.sum(axis=1)
    # pyfuzzylite 8's centroid and bisector divide by the sampled area whatever its sign (an
    # activation above 1 through a norm with a pole can make parts of the set negative): NaN
    # only where it is 0
    fired = total != 0 if sampling == Sampling.MIDPOINT and not first_plateau else total > 0
    safe_total = np.where(fired, total, 1.0)
    if inf.defuzzifier == Defuzzifier.CENTROID and w is not None:
        value = (m @ (w * u)) / np.where(fired, m @ w, 1.0)
    elif inf.defuzzifier == Defuzzifier.CENTROID:
        value = (m @ u) / safe_total
    elif inf.defuzzifier == Defuzzifier.BISECTOR and first_plateau:
        value = _fuzzylite6_bisector(m, var.lo, var.hi)
    elif inf.defuzzifier == Defuzzifier.BISECTOR:
        # Normalised by the cumsum's last element as fuzzylite does, not by m.sum (pairwise
        # summation): the two differ in the last bit, which moves near-ties by one sample.
        area = np.cumsum(m, axis=1)
        last = np.where(fired, area[:, -1], 1.0)
        gap = np.abs(area / last[:, None] - 0.5)
        value = _mean_where(gap == gap.min(axis=1, keepdims=True), u)
    elif inf.defuzzifier in EXTREMES:
        last = inf.defuzzifier == Defuzzifier.LARGEST_OF_MAXIMUM
        value = _scanned_extreme(m, u, last) if first_plateau else \
            _extreme_where((m > 0) & (m == m.max(axis=1, keepdims=True)), u, last)
    elif first_plateau:
        value = _first_plateau_mean(m, u)
    else:
        # Exact equality, as fuzzylite: which samples tie can hang on the last bit.
        value = _mean_where((m > 0) & (m == m.max(axis=1, keepdims=True)), u)
    if first_plateau:
        # fuzzylite 6 defuzzifies a set its rules triggered even where it is 0 throughout
        # (OutputVariable::defuzzify takes the default only where no rule fired: the caller's
        # mask): its scans give a sample there (the last for the largest of maximum, the
        # first for the smallest, the middle for the mean), the centroid and bisector 0/0
        ratio = inf.defuzzifier in (Defuzzifier.CENTROID, Defuzzifier.BISECTOR)
        return np.where(fired, value, np.nan) if ratio else value
    if sampling == Sampling.MIDPOINT:
        # pyfuzzylite 8: every defuzzifier is NaN on a set that is 0 throughout; the output
        # then takes the file's default (tool_semantics applies it), not the model's
        return np.where(fired, value, np.nan)
    return np.where(fired, value, var.default)


def _octave_defuzzify(m: np.ndarray, u: np.ndarray, w: np.ndarray,
                      method: Defuzzifier) -> np.ndarray:
    """The Octave toolkit's defuzz.m on the sampled set m (N, K) at u = linspace(lo, hi, K)
    (trapz weights w), also where m is 0 throughout (nothing fired: the toolkit has no
    default there): centroid trapz(u, u m) / trapz(u, m) (0/0 = NaN); mom the mean of the
    u where m equals its maximum (all of them: the middle); som/lom the smallest/largest
    such u (lo/hi); bisector its search for half the area, which returns the sample's index
    1..K, not the sample (defuzz.m: `crisp_x = midpoint`)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        if method == Defuzzifier.CENTROID:
            return (m @ (w * u)) / (m @ w)
        if method == Defuzzifier.BISECTOR:
            return _octave_bisector_index(m, u)
        top = m == m.max(axis=1, keepdims=True)
        if method == Defuzzifier.MEAN_OF_MAXIMUM:
            return (top @ u) / top.sum(axis=1)
        return _extreme_where(top, u, method == Defuzzifier.LARGEST_OF_MAXIMUM)


def _octave_bisector_index(m: np.ndarray, u: np.ndarray) -> np.ndarray:
    """defuzz.m's bisector: lower = 1, upper = K; K - 1 times midpoint = round((lower +
    upper) / 2), the area of m zeroed after the midpoint minus half the area: > 0 moves
    upper there, else lower; the last midpoint (1-based) is the answer."""
    n, k = m.shape
    segment = np.diff(u) * (m[:, :-1] + m[:, 1:])                     # (N, K-1), trapz's
    half = 0.5 * segment.sum(axis=1) / 2
    before = np.concatenate([np.zeros((n, 1)), np.cumsum(segment, axis=1)], axis=1)  # (N, K)
    # zeroed after sample j (0-based): the segments before it, and j's own half segment
    left = 0.5 * (before[:, :k] + np.append(np.diff(u), 0.0) * m)
    lower, upper = np.ones(n, dtype=np.int64), np.full(n, k, dtype=np.int64)
    midpoint = lower
    rows = np.arange(n)
    for _ in range(k - 1):
        midpoint = np.floor((lower + upper) / 2 + 0.5).astype(np.int64)   # round half up
        above = left[rows, midpoint - 1] - half > 0
        upper = np.where(above, midpoint, upper)
        lower = np.where(above, lower, midpoint)
    return midpoint.astype(float)


def _fl_eq(a, b):
    """fuzzylite 6's Op::isEq: equal within its macheps 1e-6 (FL_EPSILON)."""
    return (a == b) | (np.abs(a - b) < FL_EPSILON)


# fuzzylite 6's norms where they differ from the model's: their comparisons are Op::isEq,
# isGt, isLt, within 1e-6 (norm/t/DrasticProduct.cpp, NilpotentMinimum.cpp, HamacherProduct.cpp,
# norm/s/DrasticSum.cpp, NilpotentMaximum.cpp, HamacherSum.cpp); pyfuzzylite 8 compares exactly
FL6_T = {TNorm.DRASTIC_PRODUCT: lambda a, b: np.where(_fl_eq(np.maximum(a, b), 1.0),
                                                       np.minimum(a, b), 0.0),
          TNorm.NILPOTENT_MIN: lambda a, b: np.where((a + b > 1.0) & ~_fl_eq(a + b, 1.0),
                                                     np.minimum(a, b), 0.0),
          TNorm.HAMACHER_PRODUCT: lambda a, b: np.where(
              _fl_eq(a + b, 0.0), 0.0, a * b / np.where(_fl_eq(a + b, 0.0), 1.0, a + b - a * b))}
FL6_S = {SNorm.DRASTIC_SUM: lambda a, b: np.where(_fl_eq(np.minimum(a, b), 0.0),
                                                   np.maximum(a, b), 1.0),
          SNorm.NILPOTENT_MAX: lambda a, b: np.where((a + b < 1.0) & ~_fl_eq(a + b, 1.0),
                                                     np.maximum(a, b), 1.0),
          SNorm.HAMACHER_SUM: lambda a, b: np.where(
              _fl_eq(a * b, 1.0), 1.0,
              (a + b - 2.0 * a * b) / np.where(_fl_eq(a * b, 1.0), 1.0, 1.0 - a * b))}


def fuzzylite6_drastic_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """fuzzylite 6's DrasticProduct (norm/t/DrasticProduct.cpp): min(a, b) where max(a, b)
    is 1 within its 1e-6 (Op::isEq), else 0; its DrasticSum likewise takes the max where the
    min is 0 within 1e-6.  A Gaussian or Bell near its peak is 1 for fuzzylite there (exact
    equality, the model's and pyfuzzylite 8's, gives 0)."""
    top = np.maximum(a, b)
    return np.where((top == 1.0) | (np.abs(top - 1.0) < FL_EPSILON), np.minimum(a, b), 0.0)


def merged_rows(rb: RuleBase) -> list[bool]:
    """Per rule whether it stands for several rows of its file: rows with the same premise
    concluding different outputs are one rule (language/builder/rules.merge_rules joins their
    origins with `; `), so each of those rows has no conclusion on the others' outputs."""
    return ["; " in origin for origin in (rb.origins or [""] * rb.n_rules)]


def octave_drastic_sum(clipped: np.ndarray, firing: np.ndarray, every_rule: bool) -> np.ndarray:
    """The Octave toolkit's aggregation `drastic_sum` (drastic_sum.m's vector_arg, applied by
    aggregate_output_mamdani.m to a column of every rule's output): max over the rules where
    some rule's value is 0, else 1 -- not the pairwise fold (which is 1 wherever two rules are
    positive).  Its column holds every rule: one not concluding the output, or not firing
    (eval_rules_mamdani.m skips it), is 0 throughout, so then the aggregation is the max.
    clipped (N, R, K) the implied sets of the rules concluding the output, firing (N, R)."""
    if clipped.shape[1] == 0:
        return np.zeros((clipped.shape[0], clipped.shape[2]))
    top = clipped.max(axis=1)
    if not every_rule:
        return top
    some_zero = (clipped == 0.0).any(axis=1) | ~firing.all(axis=1)[:, None]
    return np.where(some_zero, top, 1.0)


def _octave_one_rule(g: np.ndarray, aggregation: Aggregation) -> np.ndarray:
    """The Octave toolkit's aggregate of a FIS of one rule (aggregate_output_mamdani.m): it
    applies AggMethod to the rules' columns transposed, which for one rule is a row vector,
    so max.m, sum.m, bounded_sum.m ... reduce it over the samples: the set is that one
    number at every sample (defuzz.m then gives the middle for centroid and mom, the ends
    for som and lom).  g (N, K): the rule's implied set."""
    if aggregation == Aggregation.MAX:
        c = g.max(axis=1)
    elif aggregation == Aggregation.SUM:
        c = g.sum(axis=1)
    elif aggregation == Aggregation.DRASTIC_SUM:         # drastic_sum.m's vector_arg
        c = np.where(g.min(axis=1) == 0.0, g.max(axis=1), 1.0)
    else:                                                # the s-norm folded from 0
        c = _fold(g[:, :, None], aggregation_snorm(aggregation))[:, 0]
    return np.repeat(c[:, None], g.shape[1], axis=1)


def _fold(g: np.ndarray, norm: SNorm, own: dict | None = None) -> np.ndarray:
    """g (N, R, K) folded over the rules (axis 1) with the s-norm (`own`: a tool's s-norms
    where they differ, FL6_S); 0 when there is no rule."""
    if not g.shape[1]:
        return np.zeros((g.shape[0], g.shape[2]))
    if own and norm in own:
        out = g[:, 0]
        for r in range(1, g.shape[1]):
            out = own[norm](out, g[:, r])
        return out
    return combine([g[:, r] for r in range(g.shape[1])], norm, False)


def _fuzzylite6_bisector(m: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """fuzzylite 6's Bisector (src/defuzzifier/Bisector.cpp): n = the resolution steps, each
    adding the next midpoint's membership to the left area (from lo up) while it is at most
    the right one (Op::isLE, within FL_EPSILON), else to the right area (from hi down); then
    (left area * the last right midpoint + right area * the last left midpoint) / (left area
    + right area), the midpoints computed as fuzzylite does (lo + (k + 1/2) dx from the left,
    hi - (k + 1/2) dx from the right; x = lo and hi before any).  m (N, n): the set at the
    midpoints from the left."""
    count, n = m.shape[0], m.shape[1]
    dx = (hi - lo) / n
    rows = np.arange(count)
    left, right = np.zeros(count, dtype=np.int64), np.zeros(count, dtype=np.int64)
    left_area, right_area = np.zeros(count), np.zeros(count)
    x_left, x_right = np.full(count, float(lo)), np.full(count, float(hi))
    for _ in range(n):
        go_left = (np.abs(left_area - right_area) < FL_EPSILON) | (left_area < right_area)
        x_left = np.where(go_left, lo + (left + 0.5) * dx, x_left)
        x_right = np.where(go_left, x_right, hi - (right + 0.5) * dx)
        take = np.where(go_left, m[rows, np.minimum(left, n - 1)],
                        m[rows, np.maximum(n - 1 - right, 0)])
        left_area = np.where(go_left, left_area + take, left_area)
        right_area = np.where(go_left, right_area, right_area + take)
        left, right = left + go_left, right + ~go_left
    with np.errstate(invalid="ignore", divide="ignore"):
        return (left_area * x_right + right_area * x_left) / (left_area + right_area)


def _first_plateau_mean(m: np.ndarray, u: np.ndarray) -> np.ndarray:
    """fuzzylite 6's MeanOfMaximum, scanning the samples from the left: a sample above the
    maximum so far starts a plateau, one equal to it (within FL_EPSILON) extends the plateau
    while no lower sample came between; the mean of the first and last x of that plateau."""
    n = m.shape[0]
    ymax, first, last = np.full(n, -1.0), np.full(n, u[0]), np.full(n, u[-1])
    same = np.zeros(n, dtype=bool)
    for k, uk in enumerate(u):
        y = m[:, k]
        equal = np.abs(y - ymax) < FL_EPSILON
        above, below = ~equal & (y > ymax), ~equal & (y < ymax)
        first = np.where(above, uk, first)
        last = np.where(above | (equal & same), uk, last)
        same = (same | above) & ~below
        ymax = np.where(above, y, ymax)
    return 0.5 * (first + last)


def _scanned_extreme(m: np.ndarray, u: np.ndarray, last: bool) -> np.ndarray:
    """fuzzylite 6's SmallestOfMaximum / LargestOfMaximum, scanning the samples from the
    left: the smallest takes a sample above the maximum so far by more than FL_EPSILON
    (Op::isGt), the largest one above or equal within FL_EPSILON (Op::isGE)."""
    n = m.shape[0]
    ymax, at = np.full(n, -1.0), np.full(n, u[0])
    for k, uk in enumerate(u):
        y = m[:, k]
        equal = np.abs(y - ymax) < FL_EPSILON
        take = (~equal & (y > ymax)) | (equal & last)
        at = np.where(take, uk, at)
        ymax = np.where(take, y, ymax)
    return at


def _extreme_where(mask: np.ndarray, u: np.ndarray, last: bool) -> np.ndarray:
    """The smallest (largest) u where mask holds (pyfuzzylite 8, Octave: exact equality)."""
    k = mask.shape[1] - 1 - np.argmax(mask[:, ::-1], axis=1) if last else np.argmax(mask, axis=1)
    return u[k]


def _mean_where(mask: np.ndarray, u: np.ndarray) -> np.ndarray:
    count = mask.sum(axis=1)
    return (mask @ u) / np.maximum(count, 1)
