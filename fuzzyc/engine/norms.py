"""The t-norms and s-norms of the model, elementwise on arrays (fuzzylite's definitions).

Every norm has its neutral element (1 for t-norms, 0 for s-norms), so an absent clause can be
stood in for by it.  Rules with more than two clauses fold left to right: ((a1 * a2) * a3) ...
"""
from __future__ import annotations

import numpy as np

from ..semantics.model import ACTIVATION_FLOOR, SNorm, TNorm


def _hamacher_product(a, b):
    den = a + b - a * b
    return np.where(den != 0.0, a * b / np.where(den != 0.0, den, 1.0), 0.0)


def _hamacher_sum(a, b):
    den = 1.0 - a * b
    return np.where(den != 0.0, (a + b - 2.0 * a * b) / np.where(den != 0.0, den, 1.0), 1.0)


T_NORMS = {
    TNorm.MIN: np.minimum,
    TNorm.PRODUCT: np.multiply,
    TNorm.BOUNDED_DIFFERENCE: lambda a, b: np.maximum(0.0, a + b - 1.0),
    TNorm.DRASTIC_PRODUCT: lambda a, b: np.where(np.maximum(a, b) == 1.0, np.minimum(a, b), 0.0),
    TNorm.EINSTEIN_PRODUCT: lambda a, b: a * b / (2.0 - (a + b - a * b)),
    TNorm.HAMACHER_PRODUCT: _hamacher_product,
    TNorm.NILPOTENT_MIN: lambda a, b: np.where(a + b > 1.0, np.minimum(a, b), 0.0),
}

S_NORMS = {
    SNorm.MAX: np.maximum,
    SNorm.PROBSUM: lambda a, b: a + b - a * b,
    SNorm.BOUNDED_SUM: lambda a, b: np.minimum(1.0, a + b),
    SNorm.DRASTIC_SUM: lambda a, b: np.where(np.minimum(a, b) == 0.0, np.maximum(a, b), 1.0),
    SNorm.EINSTEIN_SUM: lambda a, b: (a + b) / (1.0 + a * b),
    SNorm.HAMACHER_SUM: _hamacher_sum,
    SNorm.NILPOTENT_MAX: lambda a, b: np.where(a + b < 1.0, np.maximum(a, b), 1.0),
}


def implied(level: np.ndarray, mu: np.ndarray, implication) -> np.ndarray:
    """A rule's level applied to a term's membership: the implication's t-norm (broadcast)."""
    return T_NORMS[TNorm(int(implication))](level, mu)


def combine(values: list[np.ndarray], norm: TNorm | SNorm, conjunction: bool) -> np.ndarray:
    """values[0] (norm) values[1] (norm) ..., left to right."""
    op = T_NORMS[TNorm(int(norm))] if conjunction else S_NORMS[SNorm(int(norm))]
    out = values[0]
    for v in values[1:]:
        out = op(out, v)
    return out


def firing(act: np.ndarray) -> np.ndarray:
    """Rule activations with those below ACTIVATION_FLOOR set to 0 (they do not fire)."""
    return np.where(act < ACTIVATION_FLOOR, 0.0, act)
