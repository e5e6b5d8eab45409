"""The plain baseline: the 75-rule WEDM controller (Yan & Liao 1998, Table 2) in simple numpy.

Every rule is evaluated for every sample (no tricks), max-min inference, center of area over
the output terms' peaks (the paper's eq. 2).  Terms as in rulebases/wedm_three_region.fz.
"""
from __future__ import annotations

import numpy as np

LABELS = ["NB", "NS", "ZO", "PS", "PB"]
PEAKS = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
# Table 2: per e1 region, rows e2 = PB PS ZO NS NB, columns ce2 = PB PS ZO NS NB.
TABLE = {
    "P": ("PB PB PB PS PS / PB PB PS ZO PS / PB PS ZO NS NS / NS NS NS NS NB / NB NB NB NB NB",
          "PB PB PB NS NS / PB PS PS ZO NS / PB PS ZO NS NB / NB NS NS NS NB / NB NB NB NB NB"),
    "ZO": ("PS PS PS NS NS / PS PS PS ZO NS / PS NS ZO NS NB / NB NS NS NS NB / NB NB NB NB NB",
           "ZO ZO ZO NS NS / ZO ZO ZO ZO NS / NS NS NS NS NB / NB NB NB NB NB / NB NB NB NB NB"),
    "N": ("ZO ZO ZO ZO NS / NS NS NS NS NS / NS NS NS NS NB / NB NB NB NB NB / NB NB NB NB NB",
          "NS NS NS NS NS / NB NB NB NB NB / NB NB NB NB NB / NB NB NB NB NB / NB NB NB NB NB"),
}
E1_TERMS = {"N": -1.0, "ZO": 0.0, "P": 1.0}
ROW_COL = ["PB", "PS", "ZO", "NS", "NB"]


def rules() -> list[tuple[int, int, int, int, int]]:
    """(e1 term, e2 term, ce2 term, du1 term, du2 term) as indices; e1 terms N ZO P = 0 1 2."""
    out = []
    for e1, (du1, du2) in TABLE.items():
        t1 = [r.split() for r in du1.split("/")]
        t2 = [r.split() for r in du2.split("/")]
        for i, row in enumerate(ROW_COL):
            for j, col in enumerate(ROW_COL):
                out.append((list(E1_TERMS).index(e1), LABELS.index(row), LABELS.index(col),
                            LABELS.index(t1[i][j]), LABELS.index(t2[i][j])))
    return out


def triangle(x, a, b, c):
    return np.maximum(np.minimum((x - a) / (b - a), (c - x) / (c - b)), 0.0)


def uniform5(x):
    """NB and PB are shoulders, the others triangles with peaks -0.5, 0, 0.5."""
    return [np.clip((-0.5 - x) / 0.5, 0, 1)] + \
        [triangle(x, p - 0.5, p, p + 0.5) for p in (-0.5, 0.0, 0.5)] + \
        [np.clip((x - 0.5) / 0.5, 0, 1)]


RULES = rules()


def evaluate(x: np.ndarray) -> np.ndarray:
    """x (N, 3) = e1, e2, ce2 -> (N, 2) = du1, du2."""
    mu1 = [triangle(x[:, 0], p - 1, p, p + 1) for p in E1_TERMS.values()]
    mu2, mu3 = uniform5(x[:, 1]), uniform5(x[:, 2])
    alpha = [[np.zeros(len(x)) for _ in LABELS] for _ in range(2)]
    for a, b, c, d1, d2 in RULES:
        act = np.minimum(np.minimum(mu1[a], mu2[b]), mu3[c])
        alpha[0][d1] = np.maximum(alpha[0][d1], act)
        alpha[1][d2] = np.maximum(alpha[1][d2], act)
    out = []
    for al in alpha:
        total = sum(al)
        num = sum(a * p for a, p in zip(al, PEAKS))
        out.append(np.where(total > 0, num / np.where(total > 0, total, 1.0), 0.0))
    return np.stack(out, axis=1)


ANTECEDENTS = np.array([r[:3] for r in RULES])                 # (75, 3) term indices
ONE_HOT = [np.eye(len(LABELS), dtype=bool)[[r[3 + o] for r in RULES]] for o in range(2)]


def evaluate_matrix(x: np.ndarray, chunk: int = 65536) -> np.ndarray:
    """The same rule base written the way numpy invites: memberships as (N, T) matrices, all 75
    rule activations as one (N, 75) matrix, max aggregation through a (75, 5) one-hot map.
    In chunks, so that its (N, 75, 5) temporary stays bounded."""
    return np.concatenate([_matrix_chunk(x[i:i + chunk]) for i in range(0, len(x), chunk)])


def _matrix_chunk(x: np.ndarray) -> np.ndarray:
    mu1 = np.stack([triangle(x[:, 0], p - 1, p, p + 1) for p in E1_TERMS.values()], axis=1)
    mu2, mu3 = np.stack(uniform5(x[:, 1]), axis=1), np.stack(uniform5(x[:, 2]), axis=1)
    act = np.minimum(np.minimum(mu1[:, ANTECEDENTS[:, 0]], mu2[:, ANTECEDENTS[:, 1]]),
                     mu3[:, ANTECEDENTS[:, 2]])
    out = []
    for one_hot in ONE_HOT:
        alpha = np.where(one_hot[None], act[:, :, None], 0.0).max(axis=1)     # (N, 5)
        total = alpha.sum(axis=1)
        out.append(np.where(total > 0, alpha @ PEAKS / np.where(total > 0, total, 1.0), 0.0))
    return np.stack(out, axis=1)
