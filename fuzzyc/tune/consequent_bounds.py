"""`bounded` on a Takagi-Sugeno output kept by construction, not searched for.

Under weighted_average the output is a convex combination of the fired rules' consequents
(the rule weights and firing strengths are >= 0), or the default where no rule fires; a linear
consequent reads the inputs clamped to their box, so its extremes are at the box's corners.
Consequents within [lo, hi] at every corner (a singleton: its value) and the default within
[lo, hi] therefore bound the output everywhere. The condition is sufficient, not necessary
(it asks each rule alone what only the blend needs), and linear in the consequent numbers: the
consequent least squares takes it as constraints (scipy's SLSQP)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import LinearConstraint, minimize

from ..engine.membership import linear_coefficients
from ..semantics.model import Defuzzifier, Property, TermKind
from ..verifier.space import tensor_points
from .space import Space

MAX_CORNERS = 256       # 8 inputs: 2^8 corners per consequent
SLACK = 1e-9            # of the bound's width: the solver's rounding stays inside


@dataclass
class CornerBounds:
    """lo <= C @ c + d <= hi for the consequent numbers c = theta[linear_part]."""
    C: np.ndarray
    d: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    props: list[Property]
    corners: int

    def holds(self, c: np.ndarray) -> bool:
        z = self.C @ c + self.d
        return bool(np.all(z >= self.lo) and np.all(z <= self.hi))

    def _inside(self) -> tuple[np.ndarray, np.ndarray]:
        """The bounds SLACK inside, for the solver: its rounding stays within them."""
        slack = SLACK * (self.hi - self.lo)
        return self.lo + slack - self.d, self.hi - slack - self.d

    def solve(self, A: np.ndarray, r: np.ndarray, lo: np.ndarray, hi: np.ndarray,
              start: np.ndarray) -> np.ndarray:
        """argmin |A c - r|^2 within [lo, hi] and the corner constraints, from `start`."""
        if A.shape[0] > A.shape[1]:          # the same problem on R of A = QR: smaller
            Q, A = np.linalg.qr(A)
            r = Q.T @ r
        result = minimize(lambda c: float(np.sum((A @ c - r) ** 2)), np.clip(start, lo, hi),
                          jac=lambda c: 2.0 * A.T @ (A @ c - r), method="SLSQP",
                          bounds=list(zip(lo, hi)),
                          constraints=[LinearConstraint(self.C, *self._inside())],
                          options={"maxiter": 2000, "ftol": 1e-14})
        if self.holds(result.x):
            return result.x
        return start if self.holds(start) else result.x     # keep a feasible start


def corner_bounds(space: Space, form, props: list[Property]) -> CornerBounds | None:
    """The corner constraints of the `bounded` properties among `props` that they can keep
    (a Takagi-Sugeno form, weighted_average, the default inside, the rule weights >= 0, at
    most MAX_CORNERS corners, the written consequents meeting them), or None."""
    if form is None or not form.linear_part.any():
        return None
    rb = space.model.blocks[0]
    if 2 ** len(rb.inputs) > MAX_CORNERS or np.any(np.asarray(rb.weights) < 0) or any(
            n.kind == "weight" and n.lo < 0 for n in space.numbers):
        return None
    taken = [p for p in props if p.kind == "bounded" and _fits(rb, p)]
    if not taken:
        return None
    lin = form.linear_part
    corners = tensor_points([np.array([v.lo, v.hi]) for v in rb.inputs])

    def values(c):                    # every corner value of every used consequent: affine
        theta = space.x0.copy()
        theta[lin] = c
        model = space.apply(theta)
        block = model.blocks[0]
        return np.concatenate([_corner_values(block, p, corners) for p in taken])

    d = values(np.zeros(lin.sum()))
    C = np.column_stack([values(e) - d for e in np.eye(lin.sum())])
    lo, hi = [], []
    for p in taken:
        n = _corner_values(rb, p, corners).size
        lo.append(np.full(n, p.args["lo"]))
        hi.append(np.full(n, p.args["hi"]))
    rows = np.unique(np.column_stack([C, d, np.concatenate(lo), np.concatenate(hi)]), axis=0)
    bounds = CornerBounds(rows[:, :-3], rows[:, -3], rows[:, -2], rows[:, -1], taken,
                          len(corners))        # a singleton's value: one row, not one a corner
    space.apply(space.x0)
    return bounds if bounds.holds(space.x0[lin]) else None


def _fits(rb, prop: Property) -> bool:
    a = prop.args
    if a["signal"] not in [v.name for v in rb.outputs]:
        return False
    o = rb.output_index(a["signal"])
    return (rb.inference_of(o).defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
            and a["lo"] <= rb.outputs[o].default <= a["hi"])


def _corner_values(rb, prop: Property, corners: np.ndarray) -> np.ndarray:
    """(corners, used terms) values of the consequents that output `signal`'s rules use."""
    o = rb.output_index(prop.args["signal"])
    var = rb.outputs[o]
    used = np.unique(rb.consequents[:, o][rb.consequents[:, o] >= 0])
    coef = linear_coefficients(var, len(rb.inputs))[used]
    linear = var.kinds[used] == TermKind.LINEAR
    z = corners @ coef[:, 1:].T + coef[:, 0]
    peaks = np.where(linear, 0.0, np.nan_to_num(var.peaks()[used]))
    return np.where(linear[None, :], z, peaks[None, :]).ravel()
