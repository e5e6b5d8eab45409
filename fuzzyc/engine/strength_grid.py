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

The per-cell tables hold cells * 2**I entries (6**I for three triangles per input), too many
beyond a few inputs (`fits`).  Past that the columns and weights are tabled per term tuple
instead (per row of the engine's rule lookup), and each sample finds its 2**I corners' rows
itself: the term ids of each input's two slots, scaled by the input's place in the tuple code,
summed over the corners by broadcasting as the activations are multiplied.  The per-sample work
stays about 2**I, the table as big as the engine's lookup, and the activations, their order and
the scatter are the same as with per-cell tables.
"""
from __future__ import annotations

import numpy as np

from .expressions import clip
from .membership import LocalPartition
from .defuzz import SCATTERS
from ..semantics.model import Aggregation, RuleBase, TNorm


def place_values(radix: np.ndarray) -> np.ndarray:
    """Per digit, its place value in a mixed-radix code (digit 0 slowest): the code of a
    tuple of term ids (or segments, or slots) is the tuple @ place_values(radix)."""
    return np.concatenate([np.cumprod(radix[::-1])[::-1][1:], [1]])
from .norms import firing_in_place
from .workspace import Workspace

MAX_TABLE_ENTRIES = 1 << 22


class GridStrengths:
    """The strengths of all outputs' terms for a rule base whose inputs are local partitions."""

    def __init__(self, rb: RuleBase, partitions: list[LocalPartition], lookup: np.ndarray,
                 radix: np.ndarray, codes: np.ndarray | None, aggregation: Aggregation):
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
        self.n_candidates = len(n_terms) * self.depth << len(partitions)    # O * K per sample
        self.codes = codes
        self.unit_weights = bool(np.all(rb.weights == 1.0))
        weights = np.append(rb.weights.astype(float), 0.0)
        consequents = np.vstack([rb.consequents, np.full(len(rb.outputs), -1)])
        # rule (R = none) -> its consequent's column in the strength row, per output (O, R + 1)
        self.rule_columns = (self.offsets[:-1] + np.where(
            consequents >= 0, consequents, np.array(n_terms))).T
        self.columns = None
        if codes is None and self.fits(rb, partitions, self.depth):
            self._build(lookup, radix, weights)
        else:
            self._build_tuple_tables(lookup, radix, weights)
        self._fuse_partitions()

    @staticmethod
    def fits(rb: RuleBase, partitions: list[LocalPartition], depth: int) -> bool:
        cells = np.prod([len(p.breaks) + 1 for p in partitions], dtype=float)
        return cells * (2 ** len(partitions)) * depth * max(1, len(rb.outputs)) \
            <= MAX_TABLE_ENTRIES

    def work_per_sample(self) -> int:
        """Floats per sample: memberships and segments, activations, scatter indices, alpha."""
        return 4 * (8 * len(self.partitions) + 2 * self.n_candidates + self.width)

    def _build(self, lookup: np.ndarray, radix: np.ndarray, weights: np.ndarray) -> None:
        n_in = len(self.partitions)
        # term id of input i in slot s of segment k: table column 6 + s (see LocalPartition)
        seg = np.stack(np.meshgrid(*[np.arange(n) for n in self.n_seg], indexing="ij"),
                       axis=-1).reshape(-1, n_in)                           # (cells, I)
        corner_slots = (np.arange(2 ** n_in)[:, None] >> np.arange(n_in)[::-1]) & 1   # (2^I, I)
        term = np.stack([self.partitions[i].table[seg[:, None, i], 6 + corner_slots[None, :, i]]
                         for i in range(n_in)], axis=-1).astype(np.intp)    # (cells, 2^I, I)
        place = place_values(radix)
        rules = lookup[term @ place].reshape(len(seg), -1)                  # (cells, K)
        # candidate-major tables so every gather and every loop runs along the batch
        column = self.rule_columns[:, rules]                                # (O, cells, K)
        self.columns = np.ascontiguousarray(column.transpose(0, 2, 1).reshape(-1, len(seg)))
        self.weights = np.ascontiguousarray(weights[rules].T)               # (K, cells)
        self.stride = place_values(self.n_seg)

    def _build_tuple_tables(self, lookup: np.ndarray, radix: np.ndarray,
                            weights: np.ndarray) -> None:
        """Per lookup row (term tuple) and depth: the columns (O, rows * depth) and weights;
        per segment of every input (in the fused segment order) and slot: the slot's term id
        times the input's place in the tuple code (2, segments)."""
        # the smallest integer type: the samples' gathers from this table are scattered over
        # 4**I rows for three terms per input, 1 MB at 10 inputs at 1 byte a row (8 as intp)
        self.tuple_columns = np.ascontiguousarray(
            self.rule_columns[:, lookup.ravel()].astype(np.min_scalar_type(self.width)))
        self.tuple_weights = weights[lookup.ravel()]
        place = place_values(radix)
        self.slot_codes = np.concatenate(
            [p.table[:, 6:8].T.astype(np.intp) * place[i] for i, p in enumerate(self.partitions)],
            axis=1)

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

    def _bounds(self, work: Workspace, n: int) -> tuple[np.ndarray, np.ndarray]:
        """The clip bounds at full size (I, n), kept in the workspace while n repeats."""
        lo = work.array("lo", (len(self.lo), n))
        hi = work.array("hi", (len(self.lo), n))
        if work.tables.get("bounds") != n:
            np.copyto(lo, self.lo)
            np.copyto(hi, self.hi)
            work.tables["bounds"] = n
        return lo, hi

    def _scaled(self, work: Workspace, n: int) -> np.ndarray:
        """The per-cell columns as flat positions in a batch of n (O * K, cells)."""
        scaled = work.array("scaled", self.columns.shape, np.intp)
        if work.tables.get("scaled") != n:
            np.multiply(self.columns, n, out=scaled)
            work.tables["scaled"] = n
        return scaled

    def _arange(self, work: Workspace, n: int) -> np.ndarray:
        """arange(n), the first n of arange(capacity) built once per workspace."""
        arange = work.array("arange", (work.capacity,), np.intp)
        if work.tables.get("arange") != work.capacity:
            arange[:] = np.arange(work.capacity)
            work.tables["arange"] = work.capacity
        return arange[:n]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """x (N, I) -> alpha (width, N): strength of every output term, term-major."""
        return self.rows(np.asarray(x, dtype=float).T)

    def rows(self, xt: np.ndarray, work: Workspace | None = None) -> np.ndarray:
        """xt (I, N), one row per input -> alpha (width, N) (see __call__).  With a workspace
        (n <= its capacity) every temporary is one of its buffers and so is alpha: read it
        before the workspace goes back to its pool."""
        n_in, n = xt.shape
        work = work if work is not None else Workspace(n)
        # As LocalPartition.locate: clipping to the outermost break points changes no
        # membership and keeps infinities out; a NaN sits in segment 0 with memberships 0.
        lo, hi = self._bounds(work, n)    # full-size bounds: clip's fast loop
        xc = clip(xt, lo, hi, out=work.array("xc", (n_in, n)))
        has_nan = np.isnan(xc.sum())      # one pass; an inf - inf false alarm only costs time
        if has_nan:
            nan = np.isnan(xc)
            xc[nan] = np.broadcast_to(self.lo, xc.shape)[nan]
        # the breaks at or below x (LocalPartition.locate: counting beats a binary search for
        # a few breaks, whose branches mispredict on data that changes every call)
        seg = work.array("seg", (n_in, n), np.intp)
        if self.padded_breaks is not None:
            at_or_above = np.greater_equal(xc[:, None, :], self.padded_breaks, out=work.array(
                "at_or_above", (n_in, self.padded_breaks.shape[1], n), bool))
            at_or_above.sum(axis=1, out=seg)                                 # (I, N)
        else:
            for i, part in enumerate(self.partitions):
                seg[i] = (xc[i] >= part.column_breaks).sum(axis=0) if part.count_breaks \
                    else np.searchsorted(part.breaks, xc[i], side="right")
        if has_nan:
            seg[nan] = 0
        cell = None
        if self.columns is not None:      # exact (integers)
            cell = np.matmul(self.stride, seg, out=work.array("cell", (n,), np.intp))
        seg += self.segment_base
        # mode "clip" (the indices are in range): "raise" with out= copies through a buffer
        row = np.take(self.segment_table, seg, axis=1, mode="clip",
                      out=work.array("row", (6, n_in, n)))                  # (6, I, N)
        mu = work.array("mu", (2, n_in, n))
        np.subtract(xc, row[0:2], out=mu)                   # (x - anchor) / width + offset
        np.divide(mu, row[2:4], out=mu)
        np.add(mu, row[4:6], out=mu)                                        # (2, I, N)
        if has_nan:
            mu[:, nan] = 0.0
        # corner activations, first input's slot the most significant bit of the corner;
        # T(1, m) = m exactly for these memberships (0 <= m <= 1), so no row of ones
        act = mu[:, 0]
        norm = np.multiply if self.product else np.minimum
        for i in range(1, n_in):
            out = work.array(f"act{i % 2}", (2 * len(act), n))
            norm(act[:, None], mu[None, :, i], out=out.reshape(len(act), 2, n))
            act = out
        if self.depth > 1:                # np.repeat(act, depth, axis=0)
            repeated = work.array("repeated", (len(act) * self.depth, n))
            repeated.reshape(len(act), self.depth, n)[:] = act[:, None, :]
            act = repeated
        if cell is not None:                # per-cell tables
            index = np.take(self._scaled(work, n), cell, axis=1, mode="clip",
                            out=work.array("index", (len(self.columns), n), np.intp))
            weights = None if self.unit_weights else np.take(
                self.weights, cell, axis=1, mode="clip",
                out=work.array("weights", (len(self.weights), n)))
        else:                               # per-tuple tables
            key = self._corner_rows(seg, n)                                 # (K, N)
            index = self.tuple_columns.take(key, axis=1).reshape(-1, n).astype(np.intp)
            index *= n                                                      # (O * K, N)
            weights = None if self.unit_weights else self.tuple_weights.take(key)
        if weights is not None:
            act = np.multiply(act, weights, out=work.array("weighted", act.shape))
        act = firing_in_place(act, work.array("below", act.shape, bool))
        index += self._arange(work, n)
        alpha = work.array("alpha", (self.width * n,))
        alpha.fill(self.accumulate.start)
        act = self.accumulate.values(act.reshape(-1))
        # one scatter per output: numpy 2.4's ufunc.at reads garbage when the values are
        # broadcast against a 2-D index, so the values are never broadcast
        for rows in index.reshape(len(self.slices), -1):
            self.accumulate.ufunc.at(alpha, rows, act)
        alpha = alpha.reshape(self.width, n)
        if self.accumulate.bounded and not self.accumulate.complement:   # Scatter.finish
            return np.minimum(alpha, 1.0, out=alpha)
        return self.accumulate.finish(alpha)

    def _corner_rows(self, seg: np.ndarray, n: int) -> np.ndarray:
        """seg (I, N) in the fused segment order -> the per-tuple table position (K, N) of
        every candidate, in the order of the activations (corner-major, then depth)."""
        slot = self.slot_codes.take(seg, axis=1)                            # (2, I, N)
        code = slot[:, 0]
        for i in range(1, len(seg)):
            code = (code[:, None] + slot[None, :, i]).reshape(2 * len(code), n)
        if self.codes is not None:
            code = lookup_rows(self.codes, code)
        if self.depth > 1:
            code = (code[:, None] * self.depth + np.arange(self.depth)[:, None]).reshape(-1, n)
        return code


def lookup_rows(codes: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """The engine's lookup row of each term-tuple code where the rules' codes are kept sorted:
    the code's rank among them, or the extra last row (no rule) for a code that is not there."""
    row = np.minimum(np.searchsorted(codes, cell), len(codes) - 1)
    return np.where(codes[row] == cell, row, len(codes))
