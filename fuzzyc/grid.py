"""The grid fast path: term strengths alpha of every output straight from the inputs.

It applies where the engine's sparse path does (every input a `LocalPartition`, rules plain AND
conjunctions of one term per input).  The inputs' segments split the input space into cells; in
a cell each input has two slots (terms that can be positive there), so a sample fires at most
2**I term tuples, the corners of its cell, and which rules those are is the same for every sample
of the cell.  Built once per rule base: per cell and candidate k (corner k // depth, k-th rule of
that corner) the rule's weight and, per output, the column of its consequent in a flat row of all
outputs' strengths.  Per sample: one segment lookup per input, the memberships of all inputs
from one gather in a joint segment table, the corner activations by broadcasting the t-norm, one
gather of the cell's columns and one scatter per output into the strength row (`defuzz.Scatter`:
max, sum, bounded sum = sum capped at 1, probsum = 1 - the product of 1 - act).  The
arithmetic per activation is the sparse path's, so results are identical.
"""
from __future__ import annotations

import numpy as np

from .expr import clip
from .membership import LocalPartition
from .defuzz import SCATTERS
from .model import Aggregation, RuleBase, TNorm
from .norms import firing

MAX_TABLE_ENTRIES = 1 << 22


class GridStrengths:
    """The strengths of all outputs' terms for a rule base whose inputs are local partitions."""

    def __init__(self, rb: RuleBase, partitions: list[LocalPartition], lookup: np.ndarray,
                 radix: np.ndarray, aggregation: Aggregation):
        self.partitions = partitions
        self.product = rb.inference.and_ == TNorm.PRODUCT
        self.accumulate = SCATTERS[aggregation]
        n_terms = [v.n_terms for v in rb.outputs]
        # Column T of each output collects "no rule / no consequent" and is dropped at the end.
        self.offsets = np.concatenate([[0], np.cumsum([t + 1 for t in n_terms])])
        self.width = int(self.offsets[-1])
        self.slices = [slice(int(o), int(o) + t) for o, t in zip(self.offsets, n_terms)]
        self.n_seg = np.array([len(p.breaks) + 1 for p in partitions])
        self.depth = lookup.shape[1]
        self._build(rb, lookup, radix)
        self._fuse_partitions()

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

    def _fuse_partitions(self) -> None:
        """One table for all inputs' segments, so locating a sample takes a few numpy calls
        for all inputs together instead of a few per input (the same arithmetic as
        `LocalPartition.locate`, hence the same bits)."""
        parts = self.partitions
        self.lo = np.array([[p.breaks[0]] for p in parts])
        self.hi = np.array([[p.breaks[-1]] for p in parts])
        self.segment_base = np.concatenate([[0], np.cumsum(self.n_seg)[:-1]])[:, None]
        self.segment_table = np.concatenate([p.columns for p in parts], axis=1)  # (6, segs)
        # all inputs' breaks counted in one comparison, padded with +inf (never at or below a
        # clipped x); a partition with many breaks keeps its binary search
        self.padded_breaks = None
        if all(p.count_breaks for p in parts):
            width = max(len(p.breaks) for p in parts)
            self.padded_breaks = np.full((len(parts), width, 1), np.inf)
            for i, p in enumerate(parts):
                self.padded_breaks[i, :len(p.breaks), 0] = p.breaks
        self._tables: tuple = (-1,)

    def _batch_tables(self, n: int) -> tuple:
        """(n, the columns as flat positions in a batch of n, arange(n), the clip bounds at
        full size (I, n))."""
        shape = (len(self.lo), n)
        self._tables = (n, self.columns * n, np.arange(n),
                        np.ascontiguousarray(np.broadcast_to(self.lo, shape)),
                        np.ascontiguousarray(np.broadcast_to(self.hi, shape)))
        return self._tables

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """x (N, I) -> alpha (width, N): strength of every output term, term-major."""
        return self.rows(np.asarray(x, dtype=float).T)

    def rows(self, xt: np.ndarray) -> np.ndarray:
        """xt (I, N), one row per input -> alpha (width, N) (see __call__)."""
        n = xt.shape[1]
        # As LocalPartition.locate: clipping to the outermost break points changes no
        # membership and keeps infinities out; a NaN sits in segment 0 with memberships 0.
        tables = self._tables             # one tuple: a concurrent call cannot mix two n
        if tables[0] != n:                # tables for a batch of n (most calls repeat n)
            tables = self._batch_tables(n)
        _, scaled, arange, lo, hi = tables
        xc = clip(xt, lo, hi, order="C")  # full-size bounds: clip's fast loop
        has_nan = np.isnan(xc.sum())      # one pass; an inf - inf false alarm only costs time
        if has_nan:
            nan = np.isnan(xc)
            xc[nan] = np.broadcast_to(self.lo, xc.shape)[nan]
        # the breaks at or below x (LocalPartition.locate: counting beats a binary search for
        # a few breaks, whose branches mispredict on data that changes every call)
        if self.padded_breaks is not None:
            seg = (xc[:, None, :] >= self.padded_breaks).sum(axis=1)       # (I, N)
        else:
            seg = np.empty(xc.shape, dtype=np.intp)
            for i, part in enumerate(self.partitions):
                seg[i] = (xc[i] >= part.column_breaks).sum(axis=0) if part.count_breaks \
                    else np.searchsorted(part.breaks, xc[i], side="right")
        if has_nan:
            seg[nan] = 0
        cell = self.stride @ seg                                            # exact (integers)
        seg += self.segment_base
        row = self.segment_table.take(seg, axis=1)                          # (6, I, N)
        mu = (xc - row[0:2]) / row[2:4] + row[4:6]                          # (2, I, N)
        if has_nan:
            mu[:, nan] = 0.0
        # corner activations, first input's slot the most significant bit of the corner;
        # T(1, m) = m exactly for these memberships (0 <= m <= 1), so no row of ones
        act = mu[:, 0]
        for i in range(1, len(seg)):
            if self.product:
                act = (act[:, None] * mu[None, :, i]).reshape(2 * len(act), n)
            else:
                act = np.minimum(act[:, None], mu[None, :, i]).reshape(2 * len(act), n)
        if self.depth > 1:
            act = np.repeat(act, self.depth, axis=0)
        if not self.unit_weights:
            act = act * self.weights.take(cell, axis=1)
        act = firing(act)
        index = scaled.take(cell, axis=1)                                   # (O * K, N)
        index += arange
        alpha = np.full(self.width * n, self.accumulate.start)
        act = self.accumulate.values(act.reshape(-1))
        # one scatter per output: numpy 2.4's ufunc.at reads garbage when the values are
        # broadcast against a 2-D index, so the values are never broadcast
        for rows in index.reshape(len(self.slices), -1):
            self.accumulate.ufunc.at(alpha, rows, act)
        return self.accumulate.finish(alpha.reshape(self.width, n))
