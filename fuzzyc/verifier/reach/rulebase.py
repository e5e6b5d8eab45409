"""A rule base evaluated on boxes: sound bounds of every output over every input in a box.

- Memberships: each shape's registry record (`fuzzyc.semantics.shapes`) encloses its values
  over an interval soundly: by its critical points (where it may turn or jump) or by
  composing its monotone factors.  A shape without an enclosure (a formula) is refused by
  name.  (This once assumed every shape was unimodal or monotone: a gaussian product, a
  sigmoid difference or product, a semi-ellipse or a point list over a box around its top
  got the larger end value as its largest, short of the engine's.)
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
from ...semantics.model import Defuzzifier, RuleBase, TermKind
from ...semantics.operators import AGGREGATIONS, HEDGES, S_NORMS, T_NORMS
from ...semantics.shapes import SHAPES, enclosed_kinds, enclosures


def unsupported(rb: RuleBase) -> str | None:
    """Why this rule base has no set-valued evaluation here, by name (None if it has one)."""
    if rb.conditions:
        return f"nested conditions ({rb.nested_rules()})"
    # bounds pass through the engine's own code: only operators monotone in every argument
    inf = rb.inference
    used = [T_NORMS[inf.and_], S_NORMS[inf.or_], T_NORMS[inf.implication],
            *(AGGREGATIONS[rb.inference_of(o).aggregation] for o in range(len(rb.outputs))),
            *(HEDGES[h] for h in HEDGES if np.any(rb.hedges == h))]
    bent = [rec.word for rec in used if not rec.monotone]
    if bent:
        return f"the operator {bent[0]}, which is not monotone"
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
    for v in rb.inputs:     # the shape records say which shapes have an enclosure
        missing = {TermKind(int(k)) for k in v.kinds} - enclosed_kinds()
        if missing:
            names = ", ".join(sorted(SHAPES[k].name for k in missing))
            return f"the {names} terms of `{v.name}` (no enclosure over intervals)"
    return None


def membership_bounds(var, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N,) input bounds -> (N, T) least and largest membership of each term."""
    return enclosures(var.kinds, var.params, var.points, lo, hi)


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
    """Where each term may be positive (the registry's supports), clipped to the range."""
    lo, hi = np.full(var.n_terms, float(var.lo)), np.full(var.n_terms, float(var.hi))
    params = np.asarray(var.params, dtype=float)
    for t, kind in enumerate(var.kinds):
        record = SHAPES[TermKind(int(kind))]
        data = (var.points or {}).get(t) if record.per_term else params[t:t + 1]
        if data is not None:
            lo[t], hi[t] = (float(np.ravel(v)[0]) for v in record.support(data))
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
            if method in (Defuzzifier.WEIGHTED_SUM, Defuzzifier.GROUPED_SUM):
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

