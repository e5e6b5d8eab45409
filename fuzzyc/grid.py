"""The grid fast path: term strengths alpha of every output straight from the inputs.

It applies where the engine's sparse path does (every input a `LocalPartition`, rules plain AND
conjunctions of one term per input).  The inputs' segments split the input space into cells; in
a cell each input has two slots (terms that can be positive there), so a sample fires at most
2**I term tuples, the corners of its cell, and which rules those are is the same for every sample
of the cell.  Built once per rule base: per cell and candidate k (corner k // depth, k-th rule of
that corner) the rule's weight and, per output, the column of its consequent in a flat row of all
outputs' strengths.  Per sample: one segment lookup per input, the corner activations by
broadcasting the t-norm, one gather of the cell's columns and one scatter (max or sum) into the
strength row.  The arithmetic per activation is the sparse path's, so results are identical.
"""
from __future__ import annotations

import numpy as np

from .membership import LocalPartition
from .model import Aggregation, RuleBase, TNorm

MAX_TABLE_ENTRIES = 1 << 22


class GridStrengths:
    """The strengths of all outputs' terms for a rule base whose inputs are local partitions."""

    def __init__(self, rb: RuleBase, partitions: list[LocalPartition], lookup: np.ndarray,
                 radix: np.ndarray, aggregation: Aggregation):
        self.partitions = partitions
        self.product = rb.inference.and_ == TNorm.PRODUCT
        self.scatter = np.maximum if aggregation == Aggregation.MAX else np.add
        n_terms = [v.n_terms for v in rb.outputs]
        # Column T of each output collects "no rule / no consequent" and is dropped at the end.
        self.offsets = np.concatenate([[0], np.cumsum([t + 1 for t in n_terms])])
        self.width = int(self.offsets[-1])
        self.slices = [slice(int(o), int(o) + t) for o, t in zip(self.offsets, n_terms)]
        self.n_seg = np.array([len(p.breaks) + 1 for p in partitions])
        self.depth = lookup.shape[1]
        self._build(rb, lookup, radix)

    @staticmethod
    def fits(rb: RuleBase, partitions: list[LocalPartition], depth: int) -> bool:
        cells = np.prod([len(p.breaks) + 1 for p in partitions], dtype=float)
        return cells * (2 ** len(partitions)) * depth * max(1, len(rb.outputs)) \
            <= MAX_TABLE_ENTRIES

    def work_per_sample(self) -> int:
        """Floats per sample: memberships and segments, activations, scatter indices, alpha."""
        n_candidates = self.columns.shape[0]
        return 4 * (8 * len(self.partitions) + 2 * n_candidates + self.width)

    def _build(self, rb: RuleBase, lookup: np.ndarray, radix: np.ndarray) -> None:
        n_in = len(self.partitions)
        # term id of input i in slot s of segment k: table column 6 + s (see LocalPartition)
        seg = np.stack(np.meshgrid(*[np.arange(n) for n in self.n_seg], indexing="ij"),
                       axis=-1).reshape(-1, n_in)                           # (cells, I)
        corner_slots = (np.arange(2 ** n_in)[:, None] >> np.arange(n_in)[::-1]) & 1   # (2^I, I)
        term = np.stack([self.partitions[i].table[seg[:, None, i], 6 + corner_slots[None, :, i]]
                         for i in range(n_in)], axis=-1).astype(np.intp)    # (cells, 2^I, I)
        place = np.concatenate([np.cumprod(radix[::-1])[::-1][1:], [1]])
        rules = lookup[term @ place].reshape(len(seg), -1)                  # (cells, K)
        weights = np.append(rb.weights.astype(float), 0.0)
        consequents = np.vstack([rb.consequents, np.full(len(rb.outputs), -1)])
        cons = consequents[rules]                                           # (cells, K, O)
        n_terms = self.offsets[1:] - self.offsets[:-1] - 1
        column = self.offsets[:-1] + np.where(cons >= 0, cons, n_terms)
        # candidate-major tables so every gather and every loop runs along the batch
        self.columns = np.ascontiguousarray(column.transpose(2, 1, 0).reshape(-1, len(seg)))
        self.weights = np.ascontiguousarray(weights[rules].T)               # (K, cells)
        self.unit_weights = bool(np.all(rb.weights == 1.0))
        self.stride = np.concatenate([np.cumprod(self.n_seg[::-1])[::-1][1:], [1]])

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """x (N, I) -> alpha (width, N): strength of every output term, term-major."""
        n = x.shape[0]
        cell = np.zeros(n, dtype=np.intp)
        act = np.ones((1, n))
        for i, part in enumerate(self.partitions):
            seg, mu = part.locate(x[:, i])
            cell += seg * self.stride[i]
            if self.product:
                act = (act[:, None] * mu[None]).reshape(-1, n)
            else:
                act = np.minimum(act[:, None], mu[None]).reshape(-1, n)
        if self.depth > 1:
            act = np.repeat(act, self.depth, axis=0)
        if not self.unit_weights:
            act = act * self.weights.take(cell, axis=1)
        index = self.columns.take(cell, axis=1)                             # (O * K, N)
        index *= n
        index += np.arange(n)
        alpha = np.zeros(self.width * n)
        act = act.reshape(-1)
        for rows in index.reshape(len(self.slices), -1):       # one scatter per output
            self.scatter.at(alpha, rows, act)
        return alpha.reshape(self.width, n)
