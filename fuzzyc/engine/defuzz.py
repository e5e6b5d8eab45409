"""Defuzzification of one rule-base output, for a batch.

Input: the activations of candidate rules act (N, C) and the consequent term of each candidate
for this output, J ((C,) static or (N, C) per sample; -1 = the rule says nothing about it).

Peak-based defuzzifiers (center of area, weighted average/sum, centroid of singletons) need
only the term strengths alpha_j.  Area-based ones (centroid, bisector, mean of maximum) work on
the aggregated membership M(u), which is piecewise linear when the output terms are trapezoids:
it is evaluated at a set of points that contains every break point of M (the terms' break
points, pairwise edge crossings, and the points where an edge meets a clip level or another
scaled edge), so integrating it piece by piece is exact.  Gaussian, bell and sigmoid output
terms are the one sampled case: M is evaluated on a fixed grid of GRID_POINTS over [lo, hi] and
integrated as the piecewise-linear interpolant.  Singleton terms have no area: they enter the
centroid only when all terms of the output are singletons (point masses, as COA).

PROBSUM and BOUNDED_SUM aggregation combine each rule's implied shape on its own (every rule is
an item, as SUM of MIN-clipped terms), M(u) = S_r IMP(act_r, mu_t(r)(u)): the probabilistic or
bounded sum of clipped shapes is not the shape clipped at the combined level.  The rules that
do not fire are dropped first (a level 0 adds 0 to a sum and a factor 1 to the product).
- BOUNDED_SUM: the plain sum of the items is piecewise linear on the break-point set, and
  min(1, sum) bends where the sum crosses 1: that point is added on every piece where it
  crosses (interpolated exactly, the sum being linear there), so the integrals stay exact.
- PROBSUM: M = 1 - prod_r (1 - g_r) with every g_r linear between break points, so on each
  piece M is a polynomial of degree <= K (K firing rules), not piecewise linear.  It is
  integrated exactly, not sampled: Gauss-Legendre with (K + 3) // 2 nodes per piece is exact
  for u M(u), of degree K + 1 (chosen over the grid because the centroid is exact everywhere
  else, and the degree is small: at most 2**I rules fire in a partitioned rule base).  The
  bisector finds the piece from those exact areas and the point inside it by Newton's method
  kept in a shrinking bracket (to the last bits), each partial integral again by
  Gauss-Legendre.  The mean of maximum needs no integral: each 1 - g_r is linear and >= 0 on a
  piece, so their product is log-concave and takes its minimum at an end of the piece; M's
  maximum is at break points, and a piece is flat at the top iff M is top at its ends and its
  midpoint (a log-concave function equal at three points is constant between them), so M is
  evaluated at the break points and the pieces' midpoints.
  Smooth output terms under PROBSUM are sampled on the grid as under the other aggregations.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import product

import numpy as np

from .centroid import ClosedFormCentroid
from .crisp import AT_LEVEL_STEPS, safe_ratio
from .crisp import FLAT_TOLERANCE  # noqa: F401  (the C back end reads it from here)
from .membership import linear_coefficients, memberships, term_inverse, trapezoid
from ..semantics.model import Aggregation, Defuzzifier, Implication, Inference, TermKind, Variable
from ..semantics.operators import AGGREGATIONS, DEFUZZIFIERS, IMPLICATIONS, members
from .norms import combine, implied

GRID_POINTS = 2001
# assumption: at most 60 steps for the probsum bisector inside its piece: Newton's method
# converges in a handful, and 60 halvings (the fallback) take a piece of any width below one ulp
# of its position (2**-60 < eps / 2**8), so it is exact to the last bits either way.
BISECTION_STEPS = 60
# assumption: rules firing at once in a sample, for sizing chunks under probsum / bounded sum
# (the rules that do not fire are dropped); a partitioned rule base fires at most 2**I, 8 for
# the paper's three inputs.  More firing rules only make a chunk larger than planned.
FIRING_GUESS = 16

PEAK_BASED = members(DEFUZZIFIERS, lambda rec: rec.family == "peaks")
# where the aggregated set is largest: its mean, smallest or largest point
MAXIMUM_BASED = (Defuzzifier.MEAN_OF_MAXIMUM, Defuzzifier.SMALLEST_OF_MAXIMUM,
                 Defuzzifier.LARGEST_OF_MAXIMUM)


@dataclass(frozen=True)
class Scatter:
    """How an aggregation accumulates activations by scattering them into their terms' slots:
    the ufunc, the start value, and what goes in and comes out.  PROBSUM adds log(1 - act)
    and returns 1 - exp(the sum): 1 - prod(1 - act) itself cancels at small activations (1 -
    1e-14 keeps two digits of the 1e-14), log1p/expm1 keep every digit; BOUNDED_SUM adds and
    caps the sum at 1."""
    ufunc: np.ufunc
    start: float = 0.0
    complement: bool = False
    bounded: bool = False

    def values(self, act: np.ndarray) -> np.ndarray:
        if not self.complement:
            return act
        with np.errstate(divide="ignore"):       # act = 1 gives log 0 = -inf, and 1 at the end
            return np.log1p(-np.minimum(act, 1.0))

    def finish(self, out: np.ndarray) -> np.ndarray:
        if self.complement:
            return -np.expm1(out)
        return np.minimum(out, 1.0) if self.bounded else out


SCATTERS = {Aggregation.MAX: Scatter(np.maximum), Aggregation.SUM: Scatter(np.add),
            Aggregation.PROBSUM: Scatter(np.add, complement=True),
            Aggregation.BOUNDED_SUM: Scatter(np.add, bounded=True)}


# aggregations folded with their s-norm, and implications other than MIN/PRODUCT: M is not
# piecewise linear (nor a low-degree polynomial) there, so it is integrated on the grid (the
# registry's `exact`)
FOLDED = members(AGGREGATIONS, lambda rec: not rec.exact)
EXACT_IMPLICATIONS = members(IMPLICATIONS, lambda rec: rec.exact)


def _folded_strengths(act: np.ndarray, J: np.ndarray, n_terms: int,
                      aggregation: Aggregation) -> np.ndarray:
    """alpha (N, T) for an s-norm folded over the candidates in order (0 where none)."""
    snorm = AGGREGATIONS[aggregation].snorm
    J = np.broadcast_to(J, act.shape)
    out = np.zeros((act.shape[0], n_terms))
    rows = np.arange(act.shape[0])
    for c in range(act.shape[1]):
        ok = J[:, c] >= 0
        r, t = rows[ok], J[ok, c]
        out[r, t] = combine([out[r, t], act[ok, c]], snorm, False)
    return out


def term_strengths(act: np.ndarray, J: np.ndarray, n_terms: int,
                   aggregation: Aggregation) -> np.ndarray:
    """alpha (N, T): the aggregation of act over the candidates concluding each term."""
    if aggregation in FOLDED:
        return _folded_strengths(act, J, n_terms, aggregation)
    if n_terms == 0:        # an output without terms (legal in FIS/FLL): nothing to aggregate
        return np.zeros((act.shape[0], 0))
    scatter = SCATTERS[aggregation]
    if J.ndim == 1:        # the same consequents for every sample: a matrix product / gather
        onehot = J[:, None] == np.arange(n_terms)
        if scatter.ufunc is np.add and not scatter.complement:   # log(1 - 1) * 0 would be nan
            return scatter.finish(act @ onehot.astype(float))
        values = scatter.values(act)
        return scatter.finish(np.stack([
            scatter.ufunc.reduce(values[:, onehot[:, j]], axis=1, initial=scatter.start)
            for j in range(n_terms)], axis=1))
    # Per-sample consequents: scatter into (N, T + 1), column T collecting "no consequent".
    n = act.shape[0]
    flat = (np.arange(n) * (n_terms + 1))[:, None] + np.where(J >= 0, J, n_terms)
    out = np.full(n * (n_terms + 1), scatter.start)
    scatter.ufunc.at(out, flat.ravel(), scatter.values(act).ravel())
    return scatter.finish(out.reshape(n, n_terms + 1)[:, :n_terms])


class OutputDefuzzifier:
    """Everything about one output that does not depend on the sample, prepared once."""

    def __init__(self, var: Variable, inference: Inference, inputs: list[Variable] = ()):
        self.var = var
        self.inference = inference
        self.params_key = np.asarray(var.params, dtype=float).tobytes()
        self.peaks = var.peaks()
        kinds = var.kinds
        method = inference.defuzzifier
        self.linear = None
        if np.any(kinds == TermKind.LINEAR):
            # any peak-based defuzzifier: center_of_area groups the rules per term first,
            # as pyfuzzylite 8's WeightedAverage does with an aggregation
            if method not in PEAK_BASED:
                raise ValueError(f"`{var.name}` has linear terms: they need a peak-based "
                                 f"defuzzifier, not {method.name.lower()}")
            self.linear = linear_coefficients(var, len(inputs))
            self.is_linear = kinds == TermKind.LINEAR
            self.reads = self.linear[:, 1:] != 0          # (T, I): the inputs each term weights
            self.input_lo = np.array([v.lo for v in inputs], dtype=float)
            self.input_hi = np.array([v.hi for v in inputs], dtype=float)
        # FUNCTION terms of a Takagi-Sugeno output: values of the inputs and earlier outputs
        self.functions = {t: f for t, f in (var.formulas or {}).items()
                          if method in PEAK_BASED}
        self.tsukamoto = DEFUZZIFIERS[method].family == "inverse"    # TSUKAMOTO(_SUM)
        self.use_peaks = not self.tsukamoto and (
            method in PEAK_BASED or bool(np.all(kinds == TermKind.SINGLETON)))
        self.sampled = not self.use_peaks and not self.tsukamoto and (bool(
            np.any((kinds != TermKind.TRAPEZOID) & (kinds != TermKind.SINGLETON)))
            or inference.aggregation in FOLDED
            or inference.implication not in EXACT_IMPLICATIONS)
        self.closed_form = None
        if not self.use_peaks and not self.tsukamoto:
            self._prepare_area(var)
            if method == Defuzzifier.CENTROID:
                self.closed_form = ClosedFormCentroid.build(var, inference)

    # -- preparation of the area-based case -------------------------------------------------

    def _prepare_area(self, var: Variable) -> None:
        lo, hi = float(var.lo), float(var.hi)
        if self.sampled:
            self.grid = np.linspace(lo, hi, GRID_POINTS)
            self.grid_mu = memberships(var, self.grid)                       # (P, T)
            return
        p = np.asarray(var.params, dtype=float).copy()
        p[var.kinds == TermKind.SINGLETON] = np.inf    # no area: zero membership everywhere
        self.params = p
        lines = [self._term_lines(t) for t in range(len(p))]
        overlapping = [(j, k) for j in range(len(p)) for k in range(len(p))
                       if p[j, 0] < p[k, 3] and p[k, 0] < p[j, 3]]
        static = [lo, hi] + [v for v in p.ravel() if lo < v < hi]
        static += [_cross(l1, l2) for j, k in overlapping if j < k
                   for l1, l2 in product(lines[j], lines[k])]
        # M jumps at a vertical edge (a == b or c == d) inside the range: a point 1 ulp to
        # each side holds both of its values, so the pieces next to it do not ramp over the jump
        vertical = [v for t in range(len(p)) for v, w in ((p[t, 0], p[t, 1]), (p[t, 2], p[t, 3]))
                    if v == w and lo < v < hi]
        static += [np.nextafter(v, side) for v in vertical for side in (-np.inf, np.inf)]
        static = np.array([v for v in static if np.isfinite(v)])
        self.static_points = np.unique(np.clip(static, lo, hi))
        self.pairs = overlapping
        self.lines = lines

    def _term_lines(self, t: int) -> list[tuple[float, float]]:
        """The pieces of term t as lines y = s*u + q: rise, top, fall (finite, sloped edges
        only: a vertical edge, a == b as in MATLAB's trapmf [0 0 1 3], is no line, and its
        crossings are its break point, already a static point)."""
        a, b, c, d = self.params[t]
        out = []
        if np.isfinite(a) and np.isfinite(b) and b > a:
            out.append((1.0 / (b - a), -a / (b - a)))
        if np.isfinite(a) or np.isfinite(d):
            out.append((0.0, 1.0))
        if np.isfinite(c) and np.isfinite(d) and d > c:
            out.append((-1.0 / (d - c), d / (d - c)))
        return out

    # -- evaluation ---------------------------------------------------------------------------

    def work_per_sample(self, n_candidates: int) -> int:
        """A rough count of floats per sample, so the engine can size its chunks."""
        if self.use_peaks or self.tsukamoto:
            return 8 * n_candidates
        if self.closed_form is not None:
            return self.closed_form.work_per_sample()
        n_items, n_dynamic = self.var.n_terms, 8 * self.var.n_terms ** 2
        if not self._static_items():
            # only the firing rules are kept, each clipped on its own: 2 points per rule
            n_items = min(n_candidates, FIRING_GUESS)
            n_dynamic = 2 * n_items
        n_points = GRID_POINTS if self.sampled else len(self.static_points) + n_dynamic
        if self.inference.aggregation == Aggregation.PROBSUM and not self.sampled:
            n_points *= (n_items + 3) // 2                # Gauss-Legendre nodes per piece
        return 4 * n_points * n_items

    def _static_items(self) -> bool:
        """Whether M is a function of the terms' strengths alone: max of the implied terms,
        or the sum of scaled ones (sum_r act_r mu_j = (sum act_r) mu_j)."""
        agg = self.inference.aggregation
        return agg == Aggregation.MAX or (
            agg == Aggregation.SUM and self.inference.implication == Implication.PRODUCT)

    def strength_aggregation(self) -> Aggregation | None:
        """How the terms' strengths alpha are aggregated over the rules, or None when this
        output needs every rule on its own (the SUM of MIN-clipped terms, Tsukamoto)."""
        if self.tsukamoto:
            return None
        if self.use_peaks:
            return Aggregation.SUM if self.inference.defuzzifier in (
                Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM) \
                else self.inference.aggregation
        return self.inference.aggregation if self._static_items() else None

    def _values(self, x: np.ndarray | None, env: dict | None = None,
                keep_nonfinite: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
        """The terms' values z: the peaks (T,), or (N, T) with linear terms at the inputs x,
        and where a linear term has no value (None when every term has one).

        A linear term reads its inputs clamped to their ranges (a local linear model of the
        range: past it the nearest edge holds, so z stays finite), and has no value where an
        input it weights is NaN.  A function term is its formula over `env` (the inputs and
        earlier outputs by name) and has no value where that is not finite, unless
        `keep_nonfinite` (fuzzylite's arithmetic, which carries NaN and inf on)."""
        if self.functions:
            return self._function_values(x, env, keep_nonfinite)
        return self._plain_values(x)

    def _plain_values(self, x: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        if self.linear is None:
            return self.peaks, None
        clamped = np.clip(x, self.input_lo, self.input_hi)
        missing = np.isnan(clamped)
        z = np.where(missing, 0.0, clamped) @ self.linear[:, 1:].T + self.linear[:, 0]
        z = np.where(self.is_linear, z, self.peaks)
        if not missing.any():
            return z, None
        return z, (missing.astype(float) @ self.reads.T.astype(float)) > 0

    def _function_values(self, x: np.ndarray, env: dict | None,
                         keep_nonfinite: bool) -> tuple[np.ndarray, np.ndarray | None]:
        z, void = self._plain_values(x)
        n = x.shape[0]
        z = np.array(np.broadcast_to(z, (n, self.var.n_terms)), dtype=float)
        for t, formula in self.functions.items():
            z[:, t] = np.broadcast_to(formula.evaluate(env), (n,))
        if keep_nonfinite:
            return z, void
        bad = ~np.isfinite(z)
        if not bad.any():
            return z, void
        return np.where(bad, 0.0, z), bad if void is None else (void | bad)

    def from_strengths(self, alpha: np.ndarray, x: np.ndarray | None = None,
                       env: dict | None = None, keep_nonfinite: bool = False) -> np.ndarray:
        """The crisp output from the terms' strengths alpha (N, T) (see strength_aggregation);
        x (N, I), the rule base's inputs, is needed only by linear terms, env (name -> (N,))
        only by function terms."""
        var, method = self.var, self.inference.defuzzifier
        if self.use_peaks:
            z, void = self._values(x, env, keep_nonfinite)
            if void is not None:        # a term without a value does not count
                alpha = np.where(void, 0.0, alpha)
            num = alpha @ z if z.ndim == 1 else (alpha * z).sum(axis=1)
            den = alpha.sum(axis=1)
            # the defuzzifier's own ratio or sum; a centroid of singletons is their ratio
            ratio = DEFUZZIFIERS[method].numpy if method in PEAK_BASED else safe_ratio
            return ratio(num, den, var.default)
        if self.closed_form is not None:
            return self.closed_form(alpha)
        if not self._static_items():
            raise ValueError(f"{method.name.lower()} with {self.inference.describe()} needs "
                             "every rule's own shape, not the terms' strengths")
        # max_r IMP(act_r, mu_j) = IMP(max_r act_r, mu_j); sum_r act_r mu_j = (sum act_r) mu_j
        x, f = self._aggregated(alpha, np.arange(var.n_terms))
        return _area_defuzzify(method, x, f, var.default)

    def __call__(self, act: np.ndarray, J: np.ndarray, x: np.ndarray | None = None,
                 env: dict | None = None, keep_nonfinite: bool = False) -> np.ndarray:
        aggregation = self.strength_aggregation()
        if aggregation is not None:
            return self.from_strengths(term_strengths(act, J, self.var.n_terms, aggregation), x,
                                       env, keep_nonfinite)
        # every candidate rule is its own item (SUM of MIN-clipped terms, PROBSUM, BOUNDED_SUM)
        levels = np.where(J >= 0, act, 0.0)
        if self.tsukamoto:
            return self._tsukamoto(levels, np.broadcast_to(J, act.shape))
        ids = np.broadcast_to(J, act.shape)
        method, agg = self.inference.defuzzifier, self.inference.aggregation
        levels, ids = _firing(levels, ids)
        if agg == Aggregation.SUM:
            x, items = self._sample(levels, ids)
            return _area_defuzzify(method, x, items.sum(axis=2), self.var.default)
        if agg == Aggregation.PROBSUM and not self.sampled:
            return self._probsum_area(levels, ids)
        x, items = self._sample(levels, ids)
        if agg == Aggregation.PROBSUM:
            return _area_defuzzify(method, x, _probsum(items), self.var.default)
        if agg in FOLDED:
            folded = combine([items[..., k] for k in range(items.shape[2])] or
                             [np.zeros(items.shape[:2])], AGGREGATIONS[agg].snorm, False)
            return _area_defuzzify(method, x, folded, self.var.default)
        x, f = _bounded_at_one(x, items.sum(axis=2))
        return _area_defuzzify(method, x, f, self.var.default)

    def _tsukamoto(self, levels: np.ndarray, ids: np.ndarray) -> np.ndarray:
        """sum act_r z_r / sum act_r over the firing rules (TSUKAMOTO_SUM: sum act_r z_r),
        z_r = mu^-1(act_r) (model.py) in the output's range (a sigmoid reaches 1 only at
        infinity)."""
        firing = levels > 0
        t = ids.clip(0)
        z = term_inverse(self.var.kinds[t], np.asarray(self.var.params, dtype=float)[t],
                         np.where(firing, levels, 1.0)).clip(self.var.lo, self.var.hi)
        num = np.where(firing, levels * z, 0.0).sum(axis=1)
        return DEFUZZIFIERS[self.inference.defuzzifier].numpy(num, levels.sum(axis=1),
                                                              self.var.default)

    def _sample(self, levels: np.ndarray, ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points (N, P) sorted, and the implied items IMP(level_k, mu_ids_k) there (N, P, K)."""
        n = levels.shape[0]
        if self.sampled:
            x = np.broadcast_to(self.grid, (n, len(self.grid)))
            mu = self.grid_mu[:, ids.clip(0)]                    # (P, K) or (P, N, K)
            mu = mu[None] if ids.ndim == 1 else mu.transpose(1, 0, 2)
            if ids.ndim == 2:
                mu = np.where((ids >= 0)[:, None, :], mu, 0.0)
            return x, self._implied(levels, mu)
        x = self._points(levels, ids)
        return x, self._items_at(x, levels, ids)

    def _points(self, levels: np.ndarray, ids: np.ndarray) -> np.ndarray:
        """Every break point of every item, sorted (N, P)."""
        n = levels.shape[0]
        return np.sort(np.concatenate([np.broadcast_to(self.static_points,
                                                       (n, len(self.static_points))),
                                       self._dynamic_points(levels, ids)], axis=1), axis=1)

    def _items_at(self, x: np.ndarray, levels: np.ndarray, ids: np.ndarray) -> np.ndarray:
        """IMP(level_k, mu_ids_k(x)) (N, Q, K) at points x (N, Q), piecewise-linear terms."""
        p = self.params[ids.clip(0)]                             # (K, 4) or (N, K, 4)
        p = p[None, None] if ids.ndim == 1 else p[:, None]
        mu = trapezoid(x[:, :, None], p[..., 0], p[..., 1], p[..., 2], p[..., 3])
        if ids.ndim == 2:
            mu = np.where((ids >= 0)[:, None, :], mu, 0.0)
        return self._implied(levels, mu)

    def _implied(self, levels: np.ndarray, mu: np.ndarray) -> np.ndarray:
        return implied(levels[:, None, :], mu, self.inference.implication)

    def _aggregated(self, levels: np.ndarray, ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points and M there for MAX, or SUM of strengths (items one per term)."""
        x, items = self._sample(levels, ids)
        agg = items.max(axis=2) if self.inference.aggregation == Aggregation.MAX \
            else items.sum(axis=2)
        return x, agg

    # -- probsum over piecewise-linear terms: piecewise polynomial M ---------------------------

    def _probsum_area(self, levels: np.ndarray, ids: np.ndarray) -> np.ndarray:
        method, default = self.inference.defuzzifier, self.var.default
        x = self._points(levels, ids)
        if method in MAXIMUM_BASED:     # break points and midpoints suffice
            xs = _interleave(x[:, :-1], 0.5 * (x[:, :-1] + x[:, 1:]), x[:, -1:])
            return DEFUZZIFIERS[method].numpy(xs, _probsum(self._items_at(xs, levels, ids)),
                                              default)
        nodes, weights = _gauss_legendre(ids.shape[1])
        x0, dx = x[:, :-1], np.diff(x, axis=1)
        piece_area, moment = self._gauss(x0, dx, levels, ids, nodes, weights)
        area = piece_area.sum(axis=1)
        if method == Defuzzifier.CENTROID:
            return safe_ratio(moment.sum(axis=1), area, default)
        return np.where(area > 0, self._probsum_bisector(x0, dx, piece_area, area, levels, ids),
                        default)

    def _gauss(self, x0, dx, levels, ids, nodes, weights) -> tuple[np.ndarray, np.ndarray]:
        """int M and int u M over each piece [x0, x0 + dx] (N, S), exact for M polynomial."""
        u = x0[..., None] + dx[..., None] * nodes                    # (N, S, G)
        f = _probsum(self._items_at(u.reshape(len(u), -1), levels, ids)).reshape(u.shape)
        wf = f * weights * dx[..., None]
        return wf.sum(axis=2), (wf * u).sum(axis=2)

    def _probsum_bisector(self, x0, dx, piece_area, area, levels, ids) -> np.ndarray:
        """The leftmost u with int_lo^u M = area / 2: its piece from the exact areas, the point
        inside by Newton's method on the exact partial integral F(t) (F' = M), inside a bracket
        that every step narrows; a step that would leave the bracket halves it instead."""
        half = 0.5 * area
        before = np.cumsum(piece_area, axis=1) - piece_area
        k = np.argmax(before + piece_area >= half[:, None], axis=1)[:, None]
        a0 = np.take_along_axis(x0, k, axis=1)                       # (N, 1)
        rem = half[:, None] - np.take_along_axis(before, k, axis=1)
        # samples without area (their default is taken) get an empty bracket: nothing to solve
        lo_t = np.zeros_like(a0)
        hi_t = np.where(area[:, None] > 0, np.take_along_axis(dx, k, axis=1), 0.0)
        t = 0.5 * hi_t
        nodes, weights = _gauss_legendre(ids.shape[1])
        for _ in range(BISECTION_STEPS):       # every sample's step at once
            gap = self._gauss(a0, t, levels, ids, nodes, weights)[0] - rem
            slope = _probsum(self._items_at(a0 + t, levels, ids))   # M(a0 + t), (N, 1)
            lo_t, hi_t = np.where(gap < 0, t, lo_t), np.where(gap < 0, hi_t, t)
            with np.errstate(divide="ignore", invalid="ignore"):
                newton = t - gap / slope
            nxt = np.where((newton >= lo_t) & (newton <= hi_t), newton, 0.5 * (lo_t + hi_t))
            # converged where a step moves u = a0 + t by a few ulps at most (a last-bit
            # oscillation would otherwise run every sample through all the steps)
            done = np.all(np.abs(nxt - t) <= 4.0 * np.spacing(np.abs(a0) + np.abs(t)))
            t = nxt
            if done:
                break
        return (a0 + t)[:, 0]

    def _dynamic_points(self, levels: np.ndarray, ids: np.ndarray) -> np.ndarray:
        """The break points of M that move with the levels, clipped into [lo, hi]."""
        lo, hi = float(self.var.lo), float(self.var.hi)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            if ids.ndim == 2:      # each rule clipped on its own: its edges meet its level
                p = self.params[ids.clip(0)]
                a, b, c, d = (p[..., i] for i in range(4))
                pts = np.concatenate([
                    _at_level(a + levels * (b - a), levels, p, b > a, np.inf),
                    _at_level(d - levels * (d - c), levels, p, d > c, -np.inf)], axis=1)
            elif self.inference.implication == Implication.MIN:
                # (terms with only vertical edges, rectangles, have no sloped line to meet)
                pts = np.stack([_at_level((levels[:, j] - q) / s, levels[:, j], self.params[k],
                                          True, np.inf if s > 0 else -np.inf)
                                for j, k in self.pairs for s, q in self.lines[k] if s != 0.0] or
                               [np.full(len(levels), lo)], axis=1)
            else:                  # scaled pieces of two different terms cross
                pts = np.stack([(levels[:, k] * q2 - levels[:, j] * q1)
                                / (levels[:, j] * s1 - levels[:, k] * s2)
                                for j, k in self.pairs if j < k
                                for (s1, q1), (s2, q2) in product(self.lines[j], self.lines[k])
                                if not (s1 == 0.0 and s2 == 0.0)] or
                               [np.full(len(levels), lo)], axis=1)
        pts = np.where(np.isfinite(pts), pts, lo)
        return np.clip(pts, lo, hi)


def _at_level(point, level, params, sloped, toward):
    """Where a level meets a term's sloped edge, moved by an ulp or two toward the term's top
    until the term reaches the level there. Rounded, the point can fall where the term is
    already below the level; M there is then less than the level and the clipped flat part
    ramps down over its whole width: a term with a vertical edge clipped at 1e-14 lost 1e-4
    of its centroid, clipped at 1e-18 (where a + h (b - a) == a) it gave the unclipped
    centroid, 1/6 for 1/4 on [0, 0.5]."""
    a, b, c, d = (params[..., i] for i in range(4))
    for _ in range(AT_LEVEL_STEPS):
        short = sloped & (level > 0) & (trapezoid(point, a, b, c, d) < level)
        if not short.any():
            break
        point = np.where(short, np.nextafter(point, toward), point)
    return point


def _firing(levels: np.ndarray, ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The items with a positive level, in their order, padded with level 0 and id -1 (an item
    at 0 adds 0 to a sum and a factor 1 to a product, so dropping it changes nothing)."""
    fires = levels > 0
    k = max(1, int(fires.sum(axis=1).max(initial=0)))
    order = np.argsort(~fires, axis=1, kind="stable")[:, :k]
    kept = np.take_along_axis(levels, order, axis=1)
    return np.where(kept > 0, kept, 0.0), \
        np.where(kept > 0, np.take_along_axis(ids, order, axis=1), -1)


def _probsum(items: np.ndarray) -> np.ndarray:
    """1 - prod_k (1 - items_k) over the last axis, in logs so small items keep their digits."""
    probsum = SCATTERS[Aggregation.PROBSUM]
    return probsum.finish(probsum.values(items).sum(axis=-1))


def _gauss_legendre(n_items: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes on [0, 1] and weights (summing to 1) exact for polynomials of degree n_items + 1:
    (n_items + 3) // 2 nodes are exact up to degree 2 ((n_items + 3) // 2) - 1 >= n_items + 1."""
    nodes, weights = np.polynomial.legendre.leggauss((n_items + 3) // 2)
    return 0.5 * (nodes + 1.0), 0.5 * weights


def _bounded_at_one(x: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """min(1, s) of the piecewise-linear (x, s), with the point where s crosses 1 inserted in
    every piece (the piece's left end again, a zero-width piece, where it does not cross)."""
    x0, x1, s0, s1 = x[:, :-1], x[:, 1:], s[:, :-1], s[:, 1:]
    crosses = (s0 < 1.0) != (s1 < 1.0)
    t = np.where(crosses, (1.0 - s0) / np.where(crosses, s1 - s0, 1.0), 0.0)
    cut = x0 + np.clip(t, 0.0, 1.0) * (x1 - x0)
    f = np.minimum(s, 1.0)
    at_cut = np.where(crosses, 1.0, f[:, :-1])
    return _interleave(x0, cut, x[:, -1:]), _interleave(f[:, :-1], at_cut, f[:, -1:])


def _interleave(a: np.ndarray, b: np.ndarray, last: np.ndarray) -> np.ndarray:
    """a0 b0 a1 b1 ... then last, along axis 1 ((N, S), (N, S), (N, 1) -> (N, 2S + 1))."""
    return np.concatenate([np.stack([a, b], axis=2).reshape(len(a), -1), last], axis=1)


def _cross(l1: tuple[float, float], l2: tuple[float, float]) -> float:
    (s1, q1), (s2, q2) = l1, l2
    return (q2 - q1) / (s1 - s2) if s1 != s2 else np.nan


def _area_defuzzify(method: Defuzzifier, x: np.ndarray, f: np.ndarray,
                    default: float) -> np.ndarray:
    """Exact centroid / bisector / mean of maximum of the piecewise-linear (x, f): the
    defuzzifier's own function (its registry record's, fuzzyc.engine.crisp)."""
    return DEFUZZIFIERS[method].numpy(x, f, default)
