"""Proofs over the continuous input space (method 2) for bounds and monotonicity.

- Peak-based defuzzifiers (center of area, weighted average) return a convex combination of
  the concluded terms' peaks, or the default where nothing fires: the hull of those values
  bounds the output everywhere (a weighted average's linear consequents: their values at the
  input box's corners). Area-based ones stay in the output's range.
- Multilinear rule bases (product t-norm, AND, trapezoid terms, no hedges): on each cell
  between consecutive break points every membership is linear in its own input, so every rule
  activation, and a weighted sum of them (the neuro-fuzzy controller), is a multilinear
  polynomial there. A weighted average (or center of area with sum aggregation) is one too
  when its denominator, the sum of the activations, is the same constant at every vertex of
  the break-point grid (then it is that constant everywhere: a multilinear function is fixed
  by its vertex values). A multilinear polynomial takes its extremes over a box at the box's
  vertices, and so does its increment along one input; evaluating the engine at the
  break-point grid therefore decides bounds and monotonicity exactly.
Min/max inference with center of area is piecewise rational with pieces cut by the lines where
two memberships cross: no proof method here, the search (method 3) decides it.
"""
from __future__ import annotations

import numpy as np

from ..engine import inference as engine
from ..engine.defuzz import FOLDED
from ..engine.membership import linear_coefficients
from ..semantics.model import Aggregation, Connective, Defuzzifier, RuleBase, TNorm, TermKind
from ..semantics.operators import DEFUZZIFIERS, HEDGES, IMPLICATIONS, S_NORMS, T_NORMS, members
from ..semantics.shapes import SHAPES, provable_kinds
from .result import Evidence, Status
from .space import break_points, hedge_free, restrict, tensor_points

TOL = 1e-9
MAX_CORNER_INPUTS = 12     # 4096 corners
AREA_BASED = members(DEFUZZIFIERS, lambda rec: rec.family == "area")
# What the proof methods (here, coverage.py, levelsets.py) were written for: the shapes whose
# registry record has closed-form level sets; the rest of the model (fuzzylite's extra norms,
# shapes and hedges, linear consequents) goes to the search.
PROVABLE_TERMS = provable_kinds()
# ... and the operators they were written for (the operator registry's `provable` and `exact`;
# hedges: the power ones)
PROVABLE_TNORMS = members(T_NORMS, lambda rec: rec.provable)
PROVABLE_SNORMS = members(S_NORMS, lambda rec: rec.provable)
PROVABLE_HEDGES = members(HEDGES, lambda rec: rec.exponent is not None)
EXACT_IMPLICATIONS = members(IMPLICATIONS, lambda rec: rec.exact)


def beyond_proofs(rb: RuleBase) -> str | None:
    """Why no proof method applies to this rule base at all, or None when they may."""
    inf = rb.inference
    if rb.conditions:
        return f"no proof method for nested conditions ({rb.nested_rules()})"
    chosen = [rb.inference_of(o) for o in range(len(rb.outputs))] or [inf]
    if any(DEFUZZIFIERS[c.defuzzifier].family == "inverse" for c in chosen):
        return "no proof method for the tsukamoto defuzzifiers"
    if inf.implication not in EXACT_IMPLICATIONS or \
            any(c.aggregation in FOLDED for c in chosen):
        return (f"no proof method for implication = {inf.implication.name.lower()}, "
                f"aggregation = {', '.join(sorted({c.aggregation.name.lower() for c in chosen}))}")
    if inf.and_ not in PROVABLE_TNORMS or inf.or_ not in PROVABLE_SNORMS:
        return f"no proof method for and={inf.and_.name.lower()} or={inf.or_.name.lower()}"
    if rb.hedges.size and not set(np.unique(rb.hedges).tolist()) <= set(PROVABLE_HEDGES):
        return "no proof method for the hedges " + "/".join(
            rec.word for h, rec in HEDGES.items() if h not in PROVABLE_HEDGES)
    kinds = {TermKind(int(k)) for v in rb.inputs + rb.outputs for k in v.kinds}
    if kinds - PROVABLE_TERMS:
        names = ", ".join(sorted(SHAPES[k].name for k in kinds - PROVABLE_TERMS))
        return f"no proof method for {names} terms"
    return None


def multilinear(rb: RuleBase, o: int) -> str | None:
    """Why output o is multilinear on every break-point cell, or None if it is not."""
    single_or_and = (rb.connective == Connective.AND) | ((rb.antecedents >= 0).sum(axis=1) <= 1)
    if not (rb.inference.and_ == TNorm.PRODUCT and bool(single_or_and.all()) and hedge_free(rb)
            and all((v.kinds == TermKind.TRAPEZOID).all() for v in rb.inputs)):
        return None
    d = rb.inference_of(o).defuzzifier
    if d == Defuzzifier.WEIGHTED_SUM:
        return "product t-norm, weighted sum: multilinear per cell"
    if d == Defuzzifier.WEIGHTED_AVERAGE or (d == Defuzzifier.CENTER_OF_AREA and
                                              rb.inference_of(o).aggregation == Aggregation.SUM):
        axes = [break_points(v) for v in rb.inputs]
        act = engine.activations(rb, tensor_points(axes))[:, rb.consequents[:, o] >= 0]
        total = act.sum(axis=1)
        if total.min() > 0 and np.ptp(total) <= TOL * total.max():
            return (f"product t-norm, averaged over activations that sum to "
                    f"{total.mean():.6g} everywhere: multilinear per cell")
    return None


def _vertex_values(rb: RuleBase, where) -> tuple[list[np.ndarray], np.ndarray]:
    axes = restrict(rb, where, [break_points(v) for v in rb.inputs])
    values = engine.evaluate(rb, tensor_points(axes))
    return axes, values.reshape([len(a) for a in axes] + [len(rb.outputs)])


def prove_bounded(rb: RuleBase, output: str, lo: float, hi: float) -> Evidence:
    o = rb.output_index(output)
    var = rb.outputs[o]
    d = rb.inference_of(o).defuzzifier
    linear = multilinear(rb, o)
    if linear:
        _, values = _vertex_values(rb, [])
        low, high = float(values[..., o].min()), float(values[..., o].max())
        how = f"{linear}: extremes at the break-point grid"
    elif d in AREA_BASED:
        low, high = min(var.lo, var.default), max(var.hi, var.default)
        how = "area-based defuzzifier: within the output's range or its default"
    elif d in (Defuzzifier.WEIGHTED_SUM, Defuzzifier.GROUPED_SUM):
        return Evidence("proof", Status.UNDECIDED, "weighted sum without a multilinear form")
    else:
        used = np.unique(rb.consequents[:, o][rb.consequents[:, o] >= 0])
        peaks = np.append(var.peaks()[used], var.default)
        low, high = float(peaks.min()), float(peaks.max())
        how = "convex combination of the concluded peaks (or the default)"
    if lo - TOL <= low and high <= hi + TOL:
        return Evidence("proof", Status.PROVED, f"{how}: {output} in [{low:.6g}, {high:.6g}]")
    if linear:
        return Evidence("proof", Status.VIOLATED, f"{how}: {output} reaches "
                        f"[{low:.6g}, {high:.6g}], outside [{lo:g}, {hi:g}]",
                        point=_extreme_point(rb, o, lo, hi))
    return Evidence("proof", Status.UNDECIDED, f"{how}: the hull [{low:.6g}, {high:.6g}] is "
                    f"wider than [{lo:g}, {hi:g}]; the search decides if it is reached")


def prove_bounded_linear(rb: RuleBase, output: str, lo: float, hi: float) -> Evidence | None:
    """A weighted average over singleton and linear consequents, whatever the antecedents: the
    output is a convex combination of the fired rules' consequent values (strengths and rule
    weights >= 0), or the default where none fires, and a linear consequent reads its inputs
    clamped to their ranges, so its extremes are at the input box's corners. PROVED when the
    hull of the corner values and the default is within [lo, hi]; else None (the search
    decides: the hull asks each rule alone what only the blend needs)."""
    o = rb.output_index(output)
    var = rb.outputs[o]
    used = np.unique(rb.consequents[:, o][rb.consequents[:, o] >= 0])
    kinds = var.kinds[used]
    if rb.inference_of(o).defuzzifier != Defuzzifier.WEIGHTED_AVERAGE or var.lock_previous \
            or np.any(np.asarray(rb.weights) < 0) or not np.any(kinds == TermKind.LINEAR) \
            or not np.all((kinds == TermKind.LINEAR) | (kinds == TermKind.SINGLETON)) \
            or len(rb.inputs) > MAX_CORNER_INPUTS:
        return None
    corners = tensor_points([np.array([v.lo, v.hi]) for v in rb.inputs])
    coef = linear_coefficients(var, len(rb.inputs))[used]
    z = np.where(kinds == TermKind.LINEAR, corners @ coef[:, 1:].T + coef[:, 0],
                 np.nan_to_num(var.peaks()[used]))
    low, high = min(float(z.min()), var.default), max(float(z.max()), var.default)
    if lo - TOL <= low and high <= hi + TOL:
        return Evidence("proof", Status.PROVED, f"convex combination of singleton and linear "
                        f"consequents (or the default), their extremes at the input box's "
                        f"{len(corners)} corners: {output} in [{low:.6g}, {high:.6g}]")
    return None


def _extreme_point(rb: RuleBase, o: int, lo: float, hi: float) -> dict[str, float]:
    axes, values = _vertex_values(rb, [])
    excess = np.maximum(values[..., o] - hi, lo - values[..., o])
    idx = np.unravel_index(int(np.argmax(excess)), excess.shape)
    return {v.name: float(a[k]) for v, a, k in zip(rb.inputs, axes, idx)}


def prove_monotone(rb: RuleBase, output: str, input_: str, direction: str, where) -> Evidence:
    o, k = rb.output_index(output), rb.input_index(input_)
    linear = multilinear(rb, o)
    if not linear:
        return Evidence("proof", Status.UNDECIDED, f"no proof method for "
                        f"{rb.inference.describe()} (not multilinear); the search decides")
    axes, values = _vertex_values(rb, where)
    step = np.diff(values[..., o], axis=k) * (1 if direction == "increasing" else -1)
    if step.size == 0 or step.min() >= -TOL:
        return Evidence("proof", Status.PROVED, f"{linear}: every increment along "
                        f"{input_} between break points has the right sign")
    idx = np.unravel_index(int(np.argmin(step)), step.shape)
    point = {v.name: float(a[j]) for v, a, j in zip(rb.inputs, axes, idx)}
    return Evidence("proof", Status.VIOLATED, f"{output} moves against `{direction}` by "
                    f"{float(step[idx]):.6g} from {input_}={axes[k][idx[k]]:g} to "
                    f"{axes[k][idx[k] + 1]:g}", point=point,
                    to_point={**point, input_: float(axes[k][idx[k] + 1])})
