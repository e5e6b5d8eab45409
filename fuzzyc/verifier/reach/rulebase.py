"""A rule base evaluated on boxes: sound bounds of every output over every input in a box.

- Memberships: every term kind of the model is unimodal (rises to a plateau [p1, p2], then
  falls) or monotone (an empty plateau), so over [x1, x2] its least value is the smaller of its
  end values and its largest is 1 where [x1, x2] meets the plateau, else the larger end value.
- Hedges, NOT, t-norms, s-norms, weights >= 0, the firing threshold and the aggregations are
  monotone in every argument: bounds go through the engine's own code
  (`engine.flat_activations`, `norms.firing`, `defuzz.term_strengths`) as lower and upper
  bounds. Nested conditions (clause programs) are refused by name.
- Peak-based outputs (center of area, weighted average, a centroid of singletons) are
  sum(w z) / sum(w) with each weight w in [w_lo, w_hi]: the exact extremes of this ratio over
  the weight box put w_hi on the values above the optimum and w_lo below it (as the
  Karnik-Mendel procedure does), so sorting the values and trying every split decides them.
  Where every weight may be 0 the output's default joins the set. The weighted sum:
  sum(w z) term by term.
- Area-based outputs (centroid, bisector, mean of maximum): the hull of the supports (clipped to
  the output's range) of the terms that may fire, and the default if nothing may.
- Linear (Takagi-Sugeno) consequents have no bound here: `unsupported` names them.
"""
from __future__ import annotations

import warnings

import numpy as np

from ...engine.defuzz import OutputDefuzzifier, term_strengths
from ...engine.inference import flat_activations
from ...engine.norms import firing
from ...engine.membership import term_values
from ...semantics.model import Defuzzifier, RuleBase, TermKind

UNIMODAL = {TermKind.TRAPEZOID: (1, 2), TermKind.PISHAPE: (1, 2), TermKind.GAUSSIAN: (0, 0),
            TermKind.BELL: (0, 0), TermKind.SPIKE: (0, 0), TermKind.COSINE: (0, 0),
            TermKind.SINGLETON: (0, 0)}     # the params that are the plateau's ends


def unsupported(rb: RuleBase) -> str | None:
    """Why this rule base has no set-valued evaluation here, by name (None if it has one)."""
    if rb.conditions:
        return f"nested conditions ({rb.nested_rules()})"
    if np.any(rb.weights < 0):
        return "negative rule weights (the activations would not be monotone)"
    for v in rb.outputs:
        if np.any(v.kinds == TermKind.LINEAR):
            return f"the linear (Takagi-Sugeno) terms of `{v.name}`"
        if v.lock_previous:
            return f"lock-previous on `{v.name}` (it holds its last value: state)"
    for v in rb.inputs + rb.outputs:
        if v.formulas:
            return f"the Function (formula) terms of `{v.name}`"
    return None


def _plateaus(kinds: np.ndarray, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    lo = np.full(len(kinds), np.inf)
    hi = np.full(len(kinds), -np.inf)
    for t, kind in enumerate(kinds):
        ends = UNIMODAL.get(TermKind(int(kind)))
        if ends is not None:
            lo[t], hi[t] = params[t, ends[0]], params[t, ends[1]]
    return lo, hi


def membership_bounds(var, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N,) input bounds -> (N, T) least and largest membership of each term."""
    at_lo = term_values(var.kinds, var.params, lo)
    at_hi = term_values(var.kinds, var.params, hi)
    p1, p2 = _plateaus(var.kinds, var.params)
    meets = (lo[:, None] <= p2) & (hi[:, None] >= p1)
    return np.minimum(at_lo, at_hi), np.where(meets, 1.0, np.maximum(at_lo, at_hi))


def ratio_bounds(w_lo: np.ndarray, w_hi: np.ndarray, z: np.ndarray, default: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Extremes of sum(w z) / sum(w) over w in [w_lo, w_hi] (N, J), z (J,); default joins
    where every w may be 0."""
    order = np.argsort(z)
    zs, lo, hi = z[order], w_lo[:, order], w_hi[:, order]
    out = []
    # split k (0..J) of the values sorted ascending: the first k weights from `first`, the
    # rest from `rest`; the largest ratio has w_lo then w_hi, the least w_hi then w_lo
    for first, rest, pick in ((lo, hi, np.nanmax), (hi, lo, np.nanmin)):
        num = _prefix(first * zs) + _suffix(rest * zs)
        den = _prefix(first) + _suffix(rest)
        ok = den > 0
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)     # all-NaN rows: nothing fires
            out.append(pick(np.where(ok, num / np.where(ok, den, 1.0), np.nan), axis=1))
    high, low = out
    silent = w_lo.sum(axis=1) <= 0
    low = np.where(silent, np.fmin(low, default), low)
    high = np.where(silent, np.fmax(high, default), high)
    return low, high


def _prefix(a: np.ndarray) -> np.ndarray:
    """(N, J) -> (N, J + 1): the sums of the first k columns, k = 0..J."""
    return np.concatenate([np.zeros((len(a), 1)), np.cumsum(a, axis=1)], axis=1)


def _suffix(a: np.ndarray) -> np.ndarray:
    """(N, J) -> (N, J + 1): the sums of the columns from k on, k = 0..J."""
    return np.concatenate([np.cumsum(a[:, ::-1], axis=1)[:, ::-1], np.zeros((len(a), 1))],
                          axis=1)


def _supports(var) -> tuple[np.ndarray, np.ndarray]:
    p, k = var.params, var.kinds
    lo = np.where(k == TermKind.TRAPEZOID, p[:, 0], np.where(k == TermKind.SINGLETON, p[:, 0],
                                                              var.lo))
    hi = np.where(k == TermKind.TRAPEZOID, p[:, 3], np.where(k == TermKind.SINGLETON, p[:, 0],
                                                              var.hi))
    return np.clip(lo, var.lo, var.hi), np.clip(hi, var.lo, var.hi)


def evaluate(rb: RuleBase, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Input bounds (N, I) -> output bounds (N, O) holding every engine output in the box."""
    n = lo.shape[0]
    bounds = [membership_bounds(v, lo[:, i], hi[:, i]) for i, v in enumerate(rb.inputs)]
    mu_lo, mu_hi = [b[0] for b in bounds], [b[1] for b in bounds]
    act_lo = firing(flat_activations(rb, mu_lo, mu_hi, n) * rb.weights)
    act_hi = firing(flat_activations(rb, mu_hi, mu_lo, n) * rb.weights)
    y_lo, y_hi = np.empty((n, len(rb.outputs))), np.empty((n, len(rb.outputs)))
    for o, var in enumerate(rb.outputs):
        inference = rb.inference_of(o)
        d = OutputDefuzzifier(var, inference, rb.inputs)
        J = rb.consequents[:, o]
        method = inference.defuzzifier
        if d.use_peaks:
            agg = d.strength_aggregation()
            a_lo = term_strengths(act_lo, J, var.n_terms, agg)
            a_hi = term_strengths(act_hi, J, var.n_terms, agg)
            if method == Defuzzifier.WEIGHTED_SUM:
                z = d.peaks
                y_lo[:, o] = np.minimum(a_lo * z, a_hi * z).sum(axis=1)
                y_hi[:, o] = np.maximum(a_lo * z, a_hi * z).sum(axis=1)
                silent = a_lo.sum(axis=1) <= 0
                y_lo[:, o] = np.where(silent, np.minimum(y_lo[:, o], var.default), y_lo[:, o])
                y_hi[:, o] = np.where(silent, np.maximum(y_hi[:, o], var.default), y_hi[:, o])
            else:
                y_lo[:, o], y_hi[:, o] = ratio_bounds(a_lo, a_hi, d.peaks, var.default)
            continue
        fires = (act_hi[:, J >= 0] > 0)
        terms = J[J >= 0]
        s_lo, s_hi = _supports(var)
        low = np.where(fires, s_lo[terms], np.inf).min(axis=1)
        high = np.where(fires, s_hi[terms], -np.inf).max(axis=1)
        silent = ~(act_lo[:, J >= 0] > 0).any(axis=1)
        y_lo[:, o] = np.where(silent, np.minimum(low, var.default), low)
        y_hi[:, o] = np.where(silent, np.maximum(high, var.default), high)
    return y_lo, y_hi

