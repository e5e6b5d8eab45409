"""A param the search steps once, at a time in [at_lo, at_hi] per box: the loop runs two copies
of every box (rows 0..B-1 and B..2B-1 of one batch, one set of symbols):

- U, the loops that have not stepped yet (the param is `before`);
- S, the loops that have (the param is `after`).

A loop steps at the first period with t >= its step time (the runtime's schedule). In a period
where some loop of the box may step (t >= at_lo and t - period < at_hi), the loops stepping now
leave U with U's state: S := join(U, S) before the period runs. Before the window S mirrors U
(S := U: no loop has stepped); from at_hi on every loop has, and U mirrors S (U := S). Every
copy stands for the loops it holds, so a check holds in a box when it holds in both copies.

The join of a value (`affine.join` for forms) is per box either copy's: a number is the same in
both; a per-box array (the WEDM arc clock's bounds) is joined by the function the plant names in
its `SET_JOIN` (its least or largest).
"""
from __future__ import annotations

import numpy as np

from .affine import Affine, join, where
from .chain import Unsupported


class StepOnce:
    def __init__(self, at: tuple[np.ndarray, np.ndarray], period: float, joins: dict):
        """at: the step time's (lo (B,), hi (B,)); joins: state key -> the join of a per-box
        array (np.minimum for a lower bound, np.maximum for an upper one)."""
        self.at_lo, self.at_hi = (np.asarray(a, float) for a in at)
        self.period, self.joins = period, joins
        self.boxes = len(self.at_lo)
        self.swap = np.concatenate([np.arange(self.boxes, 2 * self.boxes),
                                    np.arange(self.boxes)])
        self.in_s = np.arange(2 * self.boxes) >= self.boxes

    @staticmethod
    def doubled(boxes: dict[str, tuple]) -> dict[str, tuple]:
        """Every box twice: the rows of U, then the rows of S."""
        return {k: (np.concatenate([lo, lo]), np.concatenate([hi, hi]))
                for k, (lo, hi) in boxes.items()}

    def stepped(self, t: float) -> np.ndarray:
        """Per row, whether the copy's param is `after` in the period at t: S from at_lo on
        (before it S mirrors U), U from at_hi on (it mirrors S)."""
        return np.tile(t >= self.at_hi, 2) | (self.in_s & np.tile(t >= self.at_lo, 2))

    def param(self, before: Affine, after: Affine, t: float) -> Affine:
        return where(self.stepped(t), after, before)

    def advance(self, t: float, places: list[dict]) -> None:
        """Before the period at t: S := join(U, S) in the boxes where a loop may step now, S :=
        U before the window, U := S after it (in place, every value of every dict; the forms
        joined together, so they keep their correlations)."""
        window = (t >= self.at_lo) & (t - self.period < self.at_hi)
        past, pre = t >= self.at_hi, t < self.at_lo
        take_join = np.tile(window, 2) & (self.in_s | np.tile(past, 2))
        take_other = (self.in_s & np.tile(pre, 2)) | (~self.in_s & np.tile(past & ~window, 2))
        forms = []                          # (dict, key, form, its copies swapped)
        for d in places:
            for key, value in d.items():
                if isinstance(value, Affine):
                    other = Affine(value.sym, value.c[self.swap], value.g[self.swap])
                    if not (np.array_equal(value.c, other.c)
                            and np.array_equal(value.g, other.g)):
                        forms.append((d, key, value, other))
                else:
                    d[key] = self._array(key, value, take_join, take_other)
        joined = join([(value, other) for _, _, value, other in forms]) \
            if forms and take_join.any() else [value for _, _, value, _ in forms]
        for (d, key, value, other), both in zip(forms, joined):
            d[key] = where(take_join, both, where(take_other, other, value))

    def _array(self, key, value, take_join, take_other):
        if isinstance(value, np.ndarray) and value.shape == (2 * self.boxes,):
            other = value[self.swap]
            if np.array_equal(value, other):
                return value
            if key not in self.joins:
                raise Unsupported(f"per-box state `{key}` has no join for a step taken once "
                                  f"(the plant's SET_JOIN names none)")
            joined = self.joins[key](value, other)
            return np.where(take_join, joined, np.where(take_other, other, value))
        if np.ndim(value) == 0 or value is None:
            return value                   # a number: the same in both copies
        raise Unsupported(f"state `{key}` ({type(value).__name__}) has no join for a step "
                          f"taken once")

    def fold(self, values: np.ndarray, how) -> np.ndarray:
        """Per box, the copies' values (rows) folded into one (np.all, np.min, ...)."""
        return how(np.asarray(values).reshape(2, self.boxes), axis=0)
