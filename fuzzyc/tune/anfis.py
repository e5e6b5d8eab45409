"""Jang's hybrid learning rule (ANFIS, IEEE SMC 23(3), 1993), in its batch (off-line) form.

Each epoch: the forward pass solves the consequents by least squares with the premises fixed
and records the training error; the backward pass takes one gradient-descent step on the
premises with the consequents fixed, of length k along the normalised gradient of the squared
error (Jang's eta = k / sqrt(sum of the squared derivatives)).  k starts at 0.01 and grows by
10 % after four reductions of the error in a row, shrinks by 10 % after two alternations of an
increase and a reduction; two changes of the same kind are at least four epochs apart (the
rule as the MATLAB toolbox's anfis, which Jang co-wrote, applies it: its defaults 0.01, 0.9,
1.1).  The result is the epoch with the lowest training error (the toolbox's choice too); no
checking data is read.  Nothing here is random: the same data give the same numbers, bit for
bit.  Premises are held in the `tune` section's bounds (a projection: Jang's rule has none).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import lsq_linear

from .sugeno import SugenoForm

INITIAL_STEP = 0.01        # k at the first epoch
DECREASE, INCREASE = 0.9, 1.1


@dataclass
class StepRule:
    """Jang's step-size heuristic over the epochs' errors (errors[0] the first epoch)."""
    k: float = INITIAL_STEP
    last_up: int = 0              # the epoch of the last increase (0: the first epoch)
    last_down: int = 0
    changes: list = field(default_factory=list)     # (epoch, new k)

    def update(self, errors: list[float]) -> float:
        """k after the epoch whose error is errors[-1]."""
        i = len(errors) - 1
        e = errors
        if i - self.last_down >= 4 and e[i] < e[i - 1] > e[i - 2] < e[i - 3] > e[i - 4]:
            self.k *= DECREASE                     # up, down, up, down: oscillating
            self.last_down = i
            self.changes.append((i, self.k))
        elif i - self.last_up >= 4 and e[i] < e[i - 1] < e[i - 2] < e[i - 3] < e[i - 4]:
            self.k *= INCREASE                     # four reductions in a row
            self.last_up = i
            self.changes.append((i, self.k))
        return self.k


@dataclass
class Training:
    theta: np.ndarray             # the numbers at the epoch of the lowest training error
    errors: list[float]           # training RMSE per epoch (after the forward pass)
    best_epoch: int               # 0-based
    steps: list                   # (epoch, k) where k changed


def lstsq(A: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """argmin |A x - b| by Householder QR in numpy's vector operations; None when A has a
    zero column left (rank deficient).  Not LAPACK's: its threaded factorisations cost a
    hundred times the CPU on a loaded machine (0.17 s against 4 ms for 500 x 80), and this
    gives the same bits whatever the thread count."""
    R = np.array(A, dtype=float)
    q = np.array(b, dtype=float)
    n = R.shape[1]
    for j in range(n):
        v = R[j:, j].copy()
        norm = float(np.sqrt(v @ v))
        if norm == 0.0:
            return None
        v[0] += norm if v[0] >= 0 else -norm          # away from cancellation
        w = (2.0 / (v @ v)) * v
        R[j:, j:] -= np.multiply.outer(w, v @ R[j:, j:])
        q[j:] -= w * (v @ q[j:])
    x = np.zeros(n)
    for j in range(n - 1, -1, -1):                     # back substitution
        x[j] = (q[j] - R[j, j + 1:] @ x[j + 1:]) / R[j, j]
    return x


def consequents(form: SugenoForm, theta, target, lo, hi) -> np.ndarray:
    """theta with the consequents solved by least squares (premises fixed); bounded least
    squares only when the free solution leaves the `tune` bounds (or A is rank deficient)."""
    lin = form.linear_part
    A, b = form.design(theta)
    solved = lstsq(A, target - b)
    if solved is None or np.any(solved < lo[lin]) or np.any(solved > hi[lin]):
        solved = lsq_linear(A, target - b, bounds=(lo[lin], hi[lin]), method="bvls").x
    out = theta.copy()
    out[lin] = solved
    return out


def gradient(form: SugenoForm, theta, target) -> tuple[np.ndarray, float]:
    """(dE/d premises, E) for E the sum of squared errors, consequents fixed."""
    premises = ~form.linear_part
    residual = form.predict(theta).ravel() - target
    J = form.jacobian(theta, columns=np.flatnonzero(premises))
    return 2.0 * J.T @ residual, float(residual @ residual)


def train(form: SugenoForm, theta, target, lo, hi, epochs: int = 500,
          k: float = INITIAL_STEP) -> Training:
    """`epochs` epochs of the hybrid rule from theta (premises as given)."""
    premises = ~form.linear_part
    rule = StepRule(k=k)
    theta = np.asarray(theta, dtype=float).copy()
    errors: list[float] = []
    best, best_theta = np.inf, theta
    for epoch in range(epochs):
        theta = consequents(form, theta, target, lo, hi)             # forward pass
        g, sse = gradient(form, theta, target)
        errors.append(float(np.sqrt(sse / len(target))))
        if errors[-1] < best:
            best, best_theta = errors[-1], theta.copy()
        if epoch == epochs - 1:
            break
        norm = float(np.sqrt(g @ g))
        if norm > 0:                                                 # backward pass
            moved = theta[premises] - rule.k * g / norm
            theta[premises] = np.clip(moved, lo[premises], hi[premises])
        rule.update(errors)
    return Training(best_theta, errors, int(np.argmin(errors)), rule.changes)
