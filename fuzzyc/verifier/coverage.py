"""Coverage proof (method 2): max over rules of the activation >= level at every input point.

Min t-norm (or a single clause, or max s-norm): each rule fires >= level exactly on a union of
boxes (levelsets.py). Per axis, the box edges and the midpoints between them are the only
places where coverage can change, so testing that finite grid of points decides the question.
Product t-norm: decided when the rules form the full grid of the inputs' terms (the
neuro-fuzzy table): max_r prod_i mu = prod_i max_t mu_t, and each factor's minimum is found
exactly on piecewise-linear terms (at break points or where two linear pieces cross).
"""
from __future__ import annotations

import itertools

import numpy as np

from ..engine.membership import term_values
from ..semantics.model import Connective, RuleBase, SNorm, TNorm, TermKind
from .levelsets import clause_intervals
from .result import Evidence, Status

TOL = 1e-12      # box edges computed by different arithmetic may differ by rounding


def prove_covers(rb: RuleBase, inputs: list[str], level: float) -> Evidence:
    axes = [rb.input_index(n) for n in inputs]
    product_and = rb.inference.and_ == TNorm.PRODUCT
    boxes = _rule_boxes(rb, axes, level, product_and)
    if boxes is None:
        if product_and:
            return _separable_product(rb, axes, level)
        return Evidence("proof", Status.UNDECIDED, "no proof method for this premise "
                        "(probabilistic or, or `not` on a singleton)")
    lows, highs = boxes
    candidates = [_axis_candidates(rb, i, lows[:, k], highs[:, k]) for k, i in enumerate(axes)]
    n_points = int(np.prod([len(c) for c in candidates]))
    uncovered = _first_uncovered(lows, highs, candidates)
    if uncovered is not None:
        return Evidence("proof", Status.VIOLATED, f"no rule fires >= {level:g} here",
                        point=dict(zip(inputs, map(float, uncovered))))
    return Evidence("proof", Status.PROVED, f"exact: {len(lows)} rule boxes cover the {n_points} "
                    f"cell edges and midpoints that decide it")


def _first_uncovered(lows: np.ndarray, highs: np.ndarray, candidates: list[np.ndarray]):
    """The first grid point (axis 0 outermost) that no box holds, or None: the grid is swept
    axis by axis, keeping the boxes that hold the coordinates so far. Whether the rest of the
    grid is covered depends only on the axis and those boxes, so each (axis, boxes) is decided
    once: a full table of I inputs costs about (terms per input)**I sets, not the
    (points per axis)**I points the grid has (7 inputs: 9**7 = 4.8M points x 2,187 boxes)."""
    covered: set[tuple[int, bytes]] = set()
    # an explicit stack of (axis, boxes still holding, prefix point, next candidate index)
    stack = [(0, np.ones(len(lows), dtype=bool), [], 0)]
    while stack:
        axis, boxes, prefix, j = stack.pop()
        if j == len(candidates[axis]):
            covered.add((axis, boxes.tobytes()))
            continue
        stack.append((axis, boxes, prefix, j + 1))
        c = candidates[axis][j]
        holding = boxes & (lows[:, axis] - TOL <= c) & (highs[:, axis] + TOL >= c)
        if not holding.any():
            return [*prefix, c, *(cands[0] for cands in candidates[axis + 1:])]
        if axis + 1 < len(candidates) and (axis + 1, holding.tobytes()) not in covered:
            stack.append((axis + 1, holding, [*prefix, c], 0))
    return None


def _rule_boxes(rb: RuleBase, axes: list[int], level: float, product_and: bool):
    """(lows, highs) of shape (B, len(axes)), or None when no box decomposition applies."""
    lows, highs = [], []
    full = [(rb.inputs[i].lo, rb.inputs[i].hi) for i in axes]
    for r in range(rb.n_rules):
        lam = level / rb.weights[r] if rb.weights[r] > 0 else np.inf
        named = [k for k, i in enumerate(axes) if rb.antecedents[r, i] >= 0]
        is_or = rb.connective[r] == Connective.OR and len(named) > 1
        if (is_or and rb.inference.or_ != SNorm.MAX) or (product_and and not is_or
                                                         and len(named) > 1):
            return None
        per_axis = []
        for k, i in enumerate(axes):
            t = rb.antecedents[r, i]
            ivs = [full[k]] if t < 0 else clause_intervals(
                rb.inputs[i], int(t), int(rb.hedges[r, i]), bool(rb.negated[r, i]), lam)
            if ivs is None:
                return None
            per_axis.append(ivs)
        if is_or:   # a slab per named clause: that clause alone >= level, the rest free
            combos = [tuple(per_axis[k][j] if k == m else full[k] for k in range(len(axes)))
                      for m in named for j in range(len(per_axis[m]))]
        else:
            combos = list(itertools.product(*per_axis))
        for box in combos:
            lows.append([iv[0] for iv in box])
            highs.append([iv[1] for iv in box])
    shape = (len(lows), len(axes))
    return np.array(lows, dtype=float).reshape(shape), np.array(highs, dtype=float).reshape(shape)


def _axis_candidates(rb: RuleBase, i: int, lows: np.ndarray, highs: np.ndarray) -> np.ndarray:
    lo, hi = rb.inputs[i].lo, rb.inputs[i].hi
    edges = np.concatenate([[lo, hi], lows, highs])
    edges = np.unique(edges[np.isfinite(edges) & (edges >= lo) & (edges <= hi)])
    return np.concatenate([edges, 0.5 * (edges[:-1] + edges[1:])])


def _separable_product(rb: RuleBase, axes: list[int], level: float) -> Evidence:
    ante = rb.antecedents[:, axes]
    sizes = [rb.inputs[i].n_terms for i in axes]
    single = (ante >= 0).all() and not rb.negated[:, axes].any() and not rb.hedges[:, axes].any()
    full_grid = single and len({tuple(row) for row in ante}) == int(np.prod(sizes))
    same_weight = np.all(rb.weights == rb.weights[0])
    pl = all(np.isin(rb.inputs[i].kinds, [TermKind.TRAPEZOID]).all() for i in axes)
    if not (full_grid and same_weight and pl and len(axes) == len(rb.inputs)):
        return Evidence("proof", Status.UNDECIDED, "product t-norm on a partial table: no "
                        "proof method (the grid search decides)")
    worst = [_envelope_minimum(rb.inputs[i]) for i in axes]
    floor = float(rb.weights[0] * np.prod([w[1] for w in worst]))
    if floor + TOL < level:
        point = {rb.inputs[i].name: w[0] for i, w in zip(axes, worst)}
        return Evidence("proof", Status.VIOLATED, f"the strongest rule fires only {floor:.6g} "
                        f"here (< {level:g})", point=point)
    return Evidence("proof", Status.PROVED, f"exact: full product grid, min of the strongest "
                    f"firing = {floor:.6g} >= {level:g}")


def _envelope_minimum(var) -> tuple[float, float]:
    """(x, value) minimizing max_t mu_t(x) over [lo, hi], for piecewise-linear terms: the
    minimum of an upper envelope of lines lies at a break point or at a crossing of two lines."""
    p = var.params
    knots = np.unique(np.concatenate([[var.lo, var.hi], p[np.isfinite(p)]]))
    knots = knots[(knots >= var.lo) & (knots <= var.hi)]
    left, right = knots[:-1], knots[1:]
    mu_l, mu_r = term_values(var.kinds, p, left), term_values(var.kinds, p, right)
    diff_l = mu_l[:, :, None] - mu_l[:, None, :]          # (S, T, T)
    diff_r = mu_r[:, :, None] - mu_r[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = diff_l / (diff_l - diff_r)
    ok = np.isfinite(s) & (s > 0) & (s < 1)
    crossings = (left[:, None, None] + s * (right - left)[:, None, None])[ok]
    points = np.concatenate([knots, crossings])
    envelope = term_values(var.kinds, p, points).max(axis=1)
    k = int(np.argmin(envelope))
    return float(points[k]), float(envelope[k])
