"""A param the search steps once, at a time in [at_lo, at_hi] per box. The loop runs three
copies of every box (rows 0..B-1, B..2B-1, 2B..3B-1 of one batch, one set of symbols):

- U, the loops that have not stepped yet (the param is `before`);
- S, the loops that have (the param is `after`);
- C, every loop, the param a choice of the two in every period of the window (`per_period`).

A loop steps at the first period with t >= its step time (the runtime's schedule). In a period
where some loop of the box may step (t >= at_lo and t - period < at_hi), the loops stepping now
leave U with U's state: S := join(U, S) before the period runs (Girard's hull of the two
states, `affine.join`). Before the window S mirrors U (S := U: no loop has stepped); from
at_hi on every loop has, and U mirrors S (U := S).

U and S together hold every loop, and so does C: a check holds at a period when it holds on
both U and S, or on C (`fold_truth`). The joins lose what Girard's hull adds when one copy lies
at the edge of the other (up to half the distance of their centres per join), so over a long
window C, exact for a loop linear in the param, may be the tighter one; over a short window,
or a param the plant reads nonlinearly (the WEDM height), U and S are.

The join of a value that is not a form: a number is the same in every copy; a per-box array
(the WEDM arc clock's bounds) is joined by the function the plant names in its `SET_JOIN` (its
least or largest).
"""
from __future__ import annotations

import numpy as np

from .affine import Affine, Symbols, join, where
from .chain import Unsupported


class StepOnce:
    COPIES = 3

    def __init__(self, at: tuple[np.ndarray, np.ndarray], period: float, joins: dict):
        """at: the step time's (lo (B,), hi (B,)); joins: state key -> the join of a per-box
        array (np.minimum for a lower bound, np.maximum for an upper one)."""
        self.at_lo, self.at_hi = (np.asarray(a, float) for a in at)
        self.period, self.joins = period, joins
        n = self.boxes = len(self.at_lo)
        self.swap = np.concatenate([np.arange(n, 2 * n), np.arange(n), np.arange(2 * n, 3 * n)])
        copy = np.repeat(np.arange(self.COPIES), n)
        self.in_u, self.in_s, self.in_c = copy == 0, copy == 1, copy == 2
        # the symbols each row keeps when the run reduces: U's and S's rows of a box the same
        self.groups = np.concatenate([np.arange(n), np.arange(n), np.arange(n, 2 * n)])

    @classmethod
    def copied(cls, boxes: dict[str, tuple]) -> dict[str, tuple]:
        """Every box once per copy: the rows of U, of S, of C."""
        return {k: (np.tile(lo, cls.COPIES), np.tile(hi, cls.COPIES))
                for k, (lo, hi) in boxes.items()}

    def _rows(self, per_box: np.ndarray) -> np.ndarray:
        return np.tile(per_box, self.COPIES)

    def param(self, sym: Symbols, before: Affine, after: Affine, at: tuple, t: float) -> Affine:
        """The param in the period at t: in S from at_lo on (before it S mirrors U), in U
        from at_hi on (it mirrors S), in C the per-period choice."""
        stepped = self._rows(t >= self.at_hi) | (self.in_s & self._rows(t >= self.at_lo))
        return where(self.in_c, per_period(sym, before, after, at, t),
                     where(stepped, after, before))

    def advance(self, t: float, places: list[dict]) -> None:
        """Before the period at t: S := join(U, S) in the boxes where a loop may step now, S :=
        U before the window, U := S after it (in place, every value of every dict; the forms
        joined together, so they keep their correlations)."""
        window = self._rows((t >= self.at_lo) & (t - self.period < self.at_hi))
        past, pre = self._rows(t >= self.at_hi), self._rows(t < self.at_lo)
        take_join = window & (self.in_s | (self.in_u & past))
        take_other = (self.in_s & pre) | (self.in_u & past & ~window)
        forms = []                          # (dict, key, form, its U and S swapped)
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
        if isinstance(value, np.ndarray) and value.shape == self.swap.shape:
            other = value[self.swap]
            if np.array_equal(value, other):
                return value
            if key not in self.joins:
                raise Unsupported(f"per-box state `{key}` has no join for a step taken once "
                                  f"(the plant's SET_JOIN names none)")
            joined = self.joins[key](value, other)
            return np.where(take_join, joined, np.where(take_other, other, value))
        if np.ndim(value) == 0 or value is None:
            return value                   # a number: the same in every copy
        raise Unsupported(f"state `{key}` ({type(value).__name__}) has no join for a step "
                          f"taken once")

    def _copies(self, values) -> np.ndarray:
        return np.asarray(values).reshape(self.COPIES, self.boxes)

    def fold_truth(self, true, slack) -> tuple[np.ndarray, np.ndarray]:
        """Per box, whether a predicate holds for every loop (on U and S, or on C) and its
        least slack (lhs - rhs >= min(U's, S's) and >= C's; a NaN, a set that overflowed,
        leaves the other side)."""
        (t_u, t_s, t_c), (s_u, s_s, s_c) = self._copies(true), self._copies(slack)
        return (t_u & t_s) | t_c, np.fmax(np.minimum(s_u, s_s), s_c)

    def fold_bounds(self, low, high) -> tuple[np.ndarray, np.ndarray]:
        """Per box, bounds of a signal over every loop: the hull of U's and S's, cut to C's."""
        (l_u, l_s, l_c), (h_u, h_s, h_c) = self._copies(low), self._copies(high)
        return np.fmax(np.minimum(l_u, l_s), l_c), np.fmin(np.maximum(h_u, h_s), h_c)


def per_period(sym: Symbols, before: Affine, after: Affine, at: tuple, t: float) -> Affine:
    """A param that steps from `before` to `after` at a time in [at_lo, at_hi] (per box):
    before + s (after - before), s = 0 before at_lo, 1 from at_hi on, any of [0, 1] between
    (a new symbol per period: every step time of the range at once, and every sequence of
    the two values). The value is one of the two: where the product's cross term makes the
    form wider than the hull of their bounds, the hull (a new symbol) stands for it instead."""
    lo, hi = at
    s = np.where(t >= hi, 1.0, 0.0)
    between = (t >= lo) & (t < hi)
    if not between.any():
        return before + (after - before) * s
    s = Affine.interval(sym, s, np.where(between, 1.0, s))
    stepped = before + (after - before) * s
    (b_lo, b_hi), (a_lo, a_hi) = before.bounds(), after.bounds()
    hull = Affine.interval(sym, np.minimum(b_lo, a_lo), np.maximum(b_hi, a_hi))
    return where(stepped.radius() <= hull.radius(), stepped, hull)
