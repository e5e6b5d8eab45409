"""One evaluation from Python without the batch machinery: the grid path on Python floats.

A controller stepped sample by sample pays numpy's fixed cost per call (tens of microseconds for
the dozens of small array operations of a batch of one); this path does the same arithmetic on
Python floats instead.  It applies where the grid path takes its per-cell tables and every
output is a ratio of its peaks (`CompiledRuleBase.peak_ratio`: center of area, weighted
average) aggregated by MAX, SUM or BOUNDED_SUM; elsewhere, and at a NaN input, callers take the
batch engine.

Same operations in the same order as `GridStrengths.rows` and `CompiledRuleBase._peak_ratios`,
so the same bits (IEEE doubles both): clip as numpy's (x > lo ? x : lo, then < hi ? : hi), the
segment = breaks at or below x, mu = (x - anchor) / width + offset per slot, the corners'
activations folded input by input (first input's slot the most significant bit), weights, the
activation floor, the scatter per candidate in order, then num and den summed term by term.
The per-cell candidate lists are built on first use of a cell.
"""
from __future__ import annotations

from bisect import bisect_right
from typing import Sequence

import numpy as np

from ..semantics.model import ACTIVATION_FLOOR


class ScalarGrid:
    """The grid path of one compiled rule base for one sample at a time."""

    @classmethod
    def build(cls, engine) -> "ScalarGrid | None":
        """For a CompiledRuleBase where the path applies, else None."""
        grid = engine.grid
        if grid is None or not engine.peak_ratio or grid.columns is None \
                or grid.accumulate.complement:
            return None
        return cls(engine)

    def __init__(self, engine):
        grid = engine.grid
        self._grid = grid
        self.n_inputs = len(grid.partitions)
        self.breaks = [p.breaks.tolist() for p in grid.partitions]
        self.bounds = [(b[0], b[-1]) for b in self.breaks]
        # per input and segment: anchor, width, offset of slot 0, then of slot 1
        self.segments = [[(c[0], c[2], c[4], c[1], c[3], c[5]) for c in p.columns.T.tolist()]
                         for p in grid.partitions]
        self.stride = [int(s) for s in grid.stride]
        self.product = grid.product
        self.maximum = grid.accumulate.ufunc is np.maximum
        self.bounded = grid.accumulate.bounded
        self.start = float(grid.accumulate.start)
        self.width = grid.width
        self.depth = grid.depth
        self.n_outputs = len(grid.slices)
        self.slices = [(s.start, s.stop) for s in grid.slices]
        self.peaks = [d.peaks.tolist() for d in engine.defuzzifiers]
        self.defaults = [float(d[0]) for d in engine.defaults]
        self._cells: dict[int, list[tuple]] = {}
        self.per_input = list(zip([lo for lo, _ in self.bounds], [hi for _, hi in self.bounds],
                                  self.breaks, self.stride, self.segments))
        # per output: (its strength-row column, its peak) per term, and its default
        self.ratios = [(list(zip(range(first, stop), peaks)), default) for (first, stop), peaks,
                       default in zip(self.slices, self.peaks, self.defaults)]

    def _candidates(self, cell: int) -> list[tuple]:
        """Per candidate k of the cell, in the batch path's order: (corner, weight or None,
        the strength-row column of its consequent per output)."""
        grid, n_candidates = self._grid, len(self._grid.columns) // self.n_outputs
        entries = []
        for k in range(n_candidates):
            weight = None if grid.unit_weights else float(grid.weights[k, cell])
            columns = tuple(int(grid.columns[o * n_candidates + k, cell])
                            for o in range(self.n_outputs))
            entries.append((k // self.depth, weight, columns))
        self._cells[cell] = entries
        return entries

    def __call__(self, values: Sequence[float]) -> list[float] | None:
        """The outputs at one point (one float per input), or None at a NaN input (the batch
        engine's business)."""
        cell = 0
        act: list[float] = []
        product = self.product
        for i, (lo, hi, breaks, stride, segments) in enumerate(self.per_input):
            v = float(values[i])         # as the batch engine's float64 (not float32 math)
            if v != v:
                return None
            v = v if v > lo else lo                  # numpy's clip: max, then min
            v = v if v < hi else hi
            seg = bisect_right(breaks, v)            # the breaks at or below v
            cell += stride * seg
            a0, w0, f0, a1, w1, f1 = segments[seg]
            m0 = (v - a0) / w0 + f0
            m1 = (v - a1) / w1 + f1
            if i == 0:
                act = [m0, m1]
            elif product:
                act = [a * m for a in act for m in (m0, m1)]
            else:
                act = [a if a <= m else m for a in act for m in (m0, m1)]
        alpha = [self.start] * self.width
        candidates = self._cells.get(cell) or self._candidates(cell)
        # a level below the floor is 0: adds nothing to a sum, and max(alpha >= 0, 0) = alpha
        if self.maximum:
            for corner, weight, columns in candidates:
                a = act[corner] if weight is None else act[corner] * weight
                if a >= ACTIVATION_FLOOR:
                    for col in columns:
                        if a > alpha[col]:
                            alpha[col] = a
        else:
            for corner, weight, columns in candidates:
                a = act[corner] if weight is None else act[corner] * weight
                if a >= ACTIVATION_FLOOR:
                    for col in columns:
                        alpha[col] = alpha[col] + a
        if self.bounded:
            alpha = [a if a < 1.0 else 1.0 for a in alpha]
        out = []
        for terms, default in self.ratios:
            num = den = 0.0
            if terms:
                (first, z), rest = terms[0], terms[1:]
                num, den = alpha[first] * z, alpha[first]
                for t, z in rest:
                    num = num + alpha[t] * z
                    den = den + alpha[t]
            out.append(num / den if den > 0 else default)
        return out
