"""Exact checks on the rule tables (method 1): consistency, completeness, continuity, monotone
tables. A "cell" is one combination of input terms; a rule covers the cells its premise names
(a wildcard covers every term of that input, `not T` every term but T). Term order is the order
of the terms' peaks, so `adjacent` means neighbours on the axis, whatever order the file used.
"""
from __future__ import annotations

import itertools

import numpy as np

from ..semantics.model import Connective, RuleBase
from .result import Evidence, Status


def term_rank(values: np.ndarray) -> np.ndarray:
    """rank[t] = position of term t when the terms are sorted by peak."""
    return np.argsort(np.argsort(values, kind="stable"), kind="stable")


def _allowed(rb: RuleBase, i: int) -> np.ndarray:
    """(R, T_i) bool: which terms of input i each rule's premise accepts."""
    n_terms = rb.inputs[i].n_terms
    terms = rb.antecedents[:, i]
    named = terms[:, None] == np.arange(n_terms)[None, :]
    allowed = np.where(rb.negated[:, i, None], ~named, named)
    return np.where((terms < 0)[:, None], True, allowed)


def cell_cover(rb: RuleBase) -> np.ndarray:
    """(R, T_1, ..., T_n) bool: rule r covers the cell. OR rules cover where any clause does."""
    n_in = len(rb.inputs)
    shape = [rb.n_rules] + [v.n_terms for v in rb.inputs]
    and_cover = np.ones(shape, dtype=bool)
    or_cover = np.zeros(shape, dtype=bool)
    for i in range(n_in):   # loop over inputs (a handful), broadcast over rules and cells
        view = [rb.n_rules] + [1] * n_in
        view[i + 1] = rb.inputs[i].n_terms
        allowed = _allowed(rb, i).reshape(view)
        and_cover = and_cover & allowed
        named = (rb.antecedents[:, i] >= 0).reshape([rb.n_rules] + [1] * n_in)
        or_cover = or_cover | (allowed & named)
    is_or = (rb.connective == Connective.OR).reshape([rb.n_rules] + [1] * n_in)
    return np.where(is_or, or_cover, and_cover)


def cell_text(rb: RuleBase, cell: tuple[int, ...]) -> str:
    return " and ".join(f"{v.name} is {v.names[t]}" for v, t in zip(rb.inputs, cell))


def place(rb: RuleBase, cover: np.ndarray, o: int, cell: tuple[int, ...]) -> str:
    """A cell and where the file writes it: the origin of the rules that conclude there."""
    rules = np.nonzero(cover[(slice(None),) + tuple(cell)] & (rb.consequents[:, o] >= 0))[0]
    where = [_origin_for(rb.origins[r] if r < len(rb.origins) else f"rule {r + 1}",
                         rb.outputs[o].name) for r in rules]
    text = f"({cell_text(rb, cell)})"
    return text + (f" [{'; '.join(where)}]" if where else "")


def _origin_for(origin: str, output: str) -> str:
    """A merged rule's origin lists one table per output: keep the one for this output."""
    parts = origin.split("; ")
    return next((p for p in parts if p.startswith(f"table {output} ")), origin)


def _outputs(rb: RuleBase, name: str | None) -> list[int]:
    return list(range(len(rb.outputs))) if name is None else [rb.output_index(name)]


def consistent(rb: RuleBase) -> Evidence:
    """No two rules with the same premise conclude different terms on one output."""
    premise = np.concatenate([rb.antecedents, rb.negated.astype(np.int64), rb.hedges,
                              rb.connective[:, None]], axis=1)
    same = (premise[:, None, :] == premise[None, :, :]).all(axis=2)
    cells = []
    for o, var in enumerate(rb.outputs):
        c = rb.consequents[:, o]
        clash = same & (c[:, None] >= 0) & (c[None, :] >= 0) & (c[:, None] != c[None, :])
        for r, s in zip(*np.nonzero(np.triu(clash, 1))):
            cells.append(f"{rb.origins[r]} says {var.name} is {var.names[c[r]]} but "
                         f"{rb.origins[s]} says {var.names[c[s]]} ({rb.describe_rule(r)})")
    if cells:
        return Evidence("table", Status.VIOLATED, f"{len(cells)} pair(s) of rules contradict",
                        cells=cells)
    return Evidence("table", Status.PROVED, f"{rb.n_rules} rules, no premise concludes twice")


def complete(rb: RuleBase, output: str | None) -> Evidence:
    """Every combination of input terms is covered by a rule concluding on the output(s)."""
    cover = cell_cover(rb)
    missing = []
    for o in _outputs(rb, output):
        concludes = rb.consequents[:, o] >= 0
        covered = cover[concludes].any(axis=0)
        missing += [f"no rule concluding {rb.outputs[o].name} covers the cell "
                    f"({cell_text(rb, tuple(cell))})" for cell in np.argwhere(~covered)]
    n_cells = int(np.prod(cover.shape[1:]))
    if missing:
        return Evidence("table", Status.VIOLATED, f"{len(missing)} cell(s) without a rule",
                        cells=missing)
    return Evidence("table", Status.PROVED, f"all {n_cells} cells covered")


def _cell_ranks(rb: RuleBase, cover: np.ndarray, o: int) -> tuple[np.ndarray, np.ndarray]:
    """Lowest and highest output rank concluded in each cell (-1 / -1 where none)."""
    out_rank = term_rank(rb.outputs[o].peaks())
    c = rb.consequents[:, o]
    concludes = c >= 0
    ranks = np.where(concludes, out_rank[np.maximum(c, 0)], -1)
    shape = (-1,) + (1,) * (cover.ndim - 1)
    hit = cover & concludes.reshape(shape)
    big = np.iinfo(np.int64).max
    lo = np.where(hit, ranks.reshape(shape), big).min(axis=0)
    hi = np.where(hit, ranks.reshape(shape), -1).max(axis=0)
    return np.where(lo == big, -1, lo), hi


def _sorted_axes(rb: RuleBase, arr: np.ndarray) -> np.ndarray:
    """Reorder each input axis of a cell array into peak order."""
    for i, v in enumerate(rb.inputs):
        arr = np.take(arr, np.argsort(v.peaks(), kind="stable"), axis=i)
    return arr


def _sorted_cell(rb: RuleBase, sorted_cell) -> tuple[int, ...]:
    return tuple(int(np.argsort(v.peaks(), kind="stable")[k])
                 for v, k in zip(rb.inputs, sorted_cell))


def continuous(rb: RuleBase, output: str | None) -> Evidence:
    """Neighbouring cells (adjacent terms of one input, others equal) conclude output terms at
    most one step apart in the output's term order."""
    cover = cell_cover(rb)
    cells, pairs = [], 0
    for o in _outputs(rb, output):
        lo, hi = (_sorted_axes(rb, a) for a in _cell_ranks(rb, cover, o))
        names = np.array(rb.outputs[o].names)[np.argsort(rb.outputs[o].peaks(), kind="stable")]
        for axis in range(lo.ndim):
            a_lo, b_lo = _split(lo, axis)
            a_hi, b_hi = _split(hi, axis)
            both = (a_lo >= 0) & (b_lo >= 0)
            pairs += int(both.sum())
            jump = np.maximum(np.abs(b_hi - a_lo), np.abs(a_hi - b_lo))
            for k in np.argwhere(both & (jump > 1)):
                left = tuple(k)
                right = tuple(k[:axis]) + (k[axis] + 1,) + tuple(k[axis + 1:])
                cells.append(
                    f"{rb.outputs[o].name} is {names[a_lo[left]]} in "
                    f"{place(rb, cover, o, _sorted_cell(rb, left))} but {names[b_hi[left]]} "
                    f"one {rb.inputs[axis].name} term up in "
                    f"{place(rb, cover, o, _sorted_cell(rb, right))}")
    if cells:
        return Evidence("table", Status.VIOLATED,
                        f"{len(cells)} neighbouring pair(s) jump more than one term", cells=cells)
    return Evidence("table", Status.PROVED, f"{pairs} neighbouring pairs differ by <= 1 term")


def _split(arr: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    n = arr.shape[axis]
    return np.take(arr, range(n - 1), axis=axis), np.take(arr, range(1, n), axis=axis)


def guard_cells(rb: RuleBase, where: list[tuple[str, int, bool]]) -> np.ndarray:
    """(T_1, ..., T_n) bool: the cells where the guard's clauses hold."""
    mask = np.ones([v.n_terms for v in rb.inputs], dtype=bool)
    for name, term, negated in where:
        i = rb.input_index(name)
        ok = (np.arange(rb.inputs[i].n_terms) == term) != negated
        view = [1] * len(rb.inputs)
        view[i] = -1
        mask = mask & ok.reshape(view)
    return mask


def monotone(rb: RuleBase, output: str, input_: str, direction: str,
             where: list[tuple[str, int, bool]]) -> Evidence:
    """Along the input's terms (others fixed, inside the guard) the concluded output term never
    moves against the declared direction."""
    o, axis = rb.output_index(output), rb.input_index(input_)
    cover = cell_cover(rb)
    lo, hi = (_sorted_axes(rb, a) for a in _cell_ranks(rb, cover, o))
    guard = _sorted_axes(rb, guard_cells(rb, where))
    sign = 1 if direction == "increasing" else -1
    names = np.array(rb.outputs[o].names)[np.argsort(rb.outputs[o].peaks(), kind="stable")]
    n = lo.shape[axis]
    cells, pairs = [], 0
    # compare every pair of defined cells along the axis, not only neighbours, so a gap
    # (an empty cell) does not hide a reversal
    for i, j in itertools.combinations(range(n), 2):
        a_lo, a_hi, b_lo, b_hi = (np.take(x, k, axis=axis) for x, k in
                                  ((lo, i), (hi, i), (lo, j), (hi, j)))
        g = np.take(guard, i, axis=axis) & np.take(guard, j, axis=axis)
        both = g & (a_lo >= 0) & (b_lo >= 0)
        pairs += int(both.sum())
        wrong = b_lo < a_hi if sign > 0 else b_hi > a_lo
        for k in np.argwhere(both & wrong):
            a = tuple(k[:axis]) + (i,) + tuple(k[axis:])
            b = tuple(k[:axis]) + (j,) + tuple(k[axis:])
            kk = tuple(k)
            later = b_lo[kk] if sign > 0 else b_hi[kk]
            earlier = a_hi[kk] if sign > 0 else a_lo[kk]
            cells.append(f"{output} is {names[earlier]} in {place(rb, cover, o, _sorted_cell(rb, a))}"
                         f" but {names[later]} at a higher {input_} in "
                         f"{place(rb, cover, o, _sorted_cell(rb, b))}")
    if cells:
        return Evidence("table", Status.VIOLATED,
                        f"{len(cells)} pair(s) of cells go against `{direction}`",
                        cells=cells)
    return Evidence("table", Status.PROVED, f"{pairs} ordered pairs of cells agree")

