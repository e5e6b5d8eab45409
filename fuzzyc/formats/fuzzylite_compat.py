"""fuzzylite's numbers, for users validating a migration: the integral defuzzifiers sampled the
way fuzzylite samples them.

fuzzylite (C++ 6 and pyfuzzylite 8 alike) integrates Centroid, Bisector and MeanOfMaximum with
the midpoint rule: the aggregated set is evaluated at u_k = lo + (k + 1/2)(hi - lo)/n,
k = 0..n-1, n = the defuzzifier's resolution (C++ default 100, pyfuzzylite 8 default 1000), and
  Centroid = sum u_k M(u_k) / sum M(u_k);
  Bisector = the mean of the u_k where |cumsum(M)_k / sum M - 1/2| is smallest;
  MeanOfMaximum = the mean of the u_k where M is largest (and positive).
The model's own defuzzifiers integrate exactly.  The difference is the midpoint rule's error: on
the test corpus's Mamdani engines it is a few 1e-4 of the output range at n = 100 and a few 1e-6
at n = 1000 for the centroid, and up to half a sample step ((hi - lo)/2n) for the bisector and
mean of maximum, which can only land on samples (tests/test_formats_fuzzylite.py measures it).
The peak-based defuzzifiers (weighted average, weighted sum, center of area) are exact in both
tools and are taken from the engine unchanged.
"""
from __future__ import annotations

import numpy as np

from ..engine import activations, evaluate
from ..membership import term_values
from ..model import Aggregation, Defuzzifier, Implication, RuleBase, TermKind

SAMPLED = (Defuzzifier.CENTROID, Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM)
CHUNK_FLOATS = 1 << 22


def evaluate_sampled(rb: RuleBase, x: np.ndarray, resolution: int = 100) -> np.ndarray:
    """x (N, I) -> y (N, O) as fuzzylite computes it with integral defuzzifiers sampled at
    `resolution` midpoints; other defuzzifiers as the engine (both tools are exact there)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    y = evaluate(rb, x)
    sampled = [o for o, v in enumerate(rb.outputs) if _is_sampled(rb, v)]
    if not sampled:
        return y
    rows = max(1, CHUNK_FLOATS // max(1, rb.n_rules * resolution))
    for start in range(0, x.shape[0], rows):
        act = activations(rb, x[start:start + rows])
        for o in sampled:
            y[start:start + rows, o] = _defuzzify(rb, o, act, resolution)
    return y


def _is_sampled(rb: RuleBase, var) -> bool:
    singletons = bool(np.all(var.kinds == TermKind.SINGLETON))
    return rb.inference.defuzzifier in SAMPLED and not singletons


def _defuzzify(rb: RuleBase, o: int, act: np.ndarray, resolution: int) -> np.ndarray:
    var, inf = rb.outputs[o], rb.inference
    rules = np.flatnonzero(rb.consequents[:, o] >= 0)
    u = var.lo + (np.arange(resolution) + 0.5) * (var.hi - var.lo) / resolution   # (K,)
    mu = term_values(var.kinds, var.params, u)[:, rb.consequents[rules, o]].T       # (R, K)
    a = act[:, rules, None]                                                          # (N, R, 1)
    clipped = np.minimum(a, mu) if inf.implication == Implication.MIN else a * mu
    m = clipped.max(axis=1) if inf.aggregation == Aggregation.MAX else clipped.sum(axis=1)
    total = m.sum(axis=1)
    fired = total > 0
    safe_total = np.where(fired, total, 1.0)
    if inf.defuzzifier == Defuzzifier.CENTROID:
        value = (m @ u) / safe_total
    elif inf.defuzzifier == Defuzzifier.BISECTOR:
        gap = np.abs(np.cumsum(m, axis=1) / safe_total[:, None] - 0.5)
        value = _mean_where(gap == gap.min(axis=1, keepdims=True), u)
    else:
        value = _mean_where((m > 0) & (m == m.max(axis=1, keepdims=True)), u)
    return np.where(fired, value, var.default)


def _mean_where(mask: np.ndarray, u: np.ndarray) -> np.ndarray:
    count = mask.sum(axis=1)
    return (mask @ u) / np.maximum(count, 1)
