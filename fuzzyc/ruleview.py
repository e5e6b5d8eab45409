"""The rule viewer: why one evaluation gave its outputs, as a picture (`fuzzyc eval --plot`).

One row per fired rule (strongest first): per input the clause's term with the input marked,
per output the consequent term cut by the rule's activation (the implication). The last row
holds each output's aggregate with the defuzzified value (the engine's) marked in red.
Singleton terms are stems; peak-based defuzzifiers (center of area, Takagi-Sugeno) aggregate
each term's strength alpha_j at its peak, as the engine does.
"""
from __future__ import annotations

import numpy as np

from .engine.inference import activations, evaluate
from .display import plural
from .escape import plot_text
from .engine.membership import memberships
from .semantics.model import Aggregation, Defuzzifier, Hedge, Implication, Model, RuleBase, TermKind, Variable
from .plotting import MEMBERSHIP_LABEL, axis_label, plt, term_colour

MAX_RULES = 12          # a picture of 75 rows would be unreadable: the strongest are drawn
AREA_METHODS = (Defuzzifier.CENTROID, Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM)
DEFUZZIFIED_COLOUR = "red"


def aggregate(levels: np.ndarray, aggregation: Aggregation) -> np.ndarray:
    """levels (R, ...) -> their aggregate over the rules (axis 0), as fuzzyc.semantics.model defines."""
    if len(levels) == 0:
        return np.zeros(levels.shape[1:])
    if aggregation == Aggregation.MAX:
        return levels.max(axis=0)
    if aggregation == Aggregation.SUM:
        return levels.sum(axis=0)
    if aggregation == Aggregation.PROBSUM:
        return 1.0 - np.prod(1.0 - levels, axis=0)
    return np.minimum(1.0, levels.sum(axis=0))          # BOUNDED_SUM


def implied(act: float, mu: np.ndarray, implication: Implication) -> np.ndarray:
    return np.minimum(act, mu) if implication == Implication.MIN else act * mu


def term_positions(var: Variable, x: np.ndarray) -> np.ndarray:
    """Where each term stands as a point: its peak, or a LINEAR term's value at the rule
    base's inputs x (I,)."""
    peaks = var.peaks()
    for t in np.flatnonzero(var.kinds == TermKind.LINEAR):
        c = (var.coefficients or {}).get(int(t), var.params[t, :len(x) + 1])
        peaks[t] = c[0] + np.dot(c[1:len(x) + 1], x)
    return peaks


def _clause_text(rb: RuleBase, r: int, i: int) -> str:
    var, t = rb.inputs[i], int(rb.antecedents[r, i])
    hedge = Hedge(int(rb.hedges[r, i]))
    words = ("not " if rb.negated[r, i] else "") + (hedge.name.lower() + " " if hedge else "")
    return f"{var.name} is {words}{var.names[t]}"


def _draw_term(ax, var: Variable, t: int, grid: np.ndarray, level: float | None,
               implication: Implication, position: float) -> None:
    """Term t of var: a curve (or a stem at `position` for a point term), and, with `level`,
    the part the implication keeps, filled."""
    colour = term_colour(t)
    if var.kinds[t] in (TermKind.SINGLETON, TermKind.LINEAR):
        ax.vlines(position, 0, 1 if level is None else level, color=colour, lw=2.5)
        return
    mu = memberships(var, grid)[:, t]
    ax.plot(grid, mu, color=colour, lw=1.2)
    if level is not None:
        ax.fill_between(grid, implied(level, mu, implication), color=colour, alpha=0.45)


def _draw_aggregate(ax, rb: RuleBase, o: int, act: np.ndarray, x: np.ndarray,
                    grid: np.ndarray) -> None:
    """The aggregated output membership (area methods) or term strengths at their positions
    (peak methods, singletons)."""
    var, inference = rb.outputs[o], rb.inference_of(o)      # an output may have its own
    concl = rb.consequents[:, o]
    on = np.flatnonzero((concl >= 0) & (act > 0))
    point_terms = np.isin(var.kinds, (TermKind.SINGLETON, TermKind.LINEAR)).all()
    if inference.defuzzifier in AREA_METHODS and not point_terms:
        mu = memberships(var, grid)
        levels = np.array([implied(act[r], mu[:, concl[r]], inference.implication) for r in on])
        total = aggregate(levels.reshape(len(on), len(grid)), inference.aggregation)
        ax.fill_between(grid, total, color="0.6")
        ax.plot(grid, total, color="k", lw=1.2)
        return
    positions = term_positions(var, x)
    for t in range(var.n_terms):
        alpha = aggregate(act[on[concl[on] == t]], inference.aggregation)
        if alpha > 0:
            ax.vlines(positions[t], 0, alpha, color=term_colour(t), lw=2.5)


def draw_rule_view(model: Model, point: dict[str, float], max_rules: int = MAX_RULES):
    """The figure for one evaluation of the rule base at `point` (its own inputs, by name)."""
    rb = model.rulebase
    x = np.array([float(point[v.name]) for v in rb.inputs])
    act = activations(rb, x[None, :])[0]
    y = evaluate(rb, x[None, :])[0]
    fired = [int(r) for r in np.argsort(-act, kind="stable") if act[r] > 0]
    shown = fired[:max_rules]
    n_in, n_out = len(rb.inputs), len(rb.outputs)
    fig, axes = plt.subplots(len(shown) + 1, n_in + n_out, squeeze=False,
                             figsize=(2.3 * (n_in + n_out), 1.15 * (len(shown) + 1) + 1.2))
    in_grid = [np.linspace(v.lo, v.hi, 401) for v in rb.inputs]
    out_grid = [np.linspace(v.lo, v.hi, 401) for v in rb.outputs]
    positions = [term_positions(v, x) for v in rb.outputs]
    for row, r in enumerate(shown):
        if r in rb.conditions:      # a nested and/or/not condition: no one term per input
            axes[row, 0].set_title(plot_text(f"#{r + 1}: {rb.describe_rule(r)}"), fontsize=6,
                                   loc="left")
        for i, var in enumerate(rb.inputs):
            ax = axes[row, i]
            if rb.antecedents[r, i] >= 0:
                _draw_term(ax, var, int(rb.antecedents[r, i]), in_grid[i], None,
                           rb.inference.implication, 0.0)
                ax.set_title(plot_text(_clause_text(rb, r, i)), fontsize=7)
            ax.axvline(x[i], color="k", lw=0.8, ls="--")
        for o, var in enumerate(rb.outputs):
            ax = axes[row, n_in + o]
            t = int(rb.consequents[r, o])
            if t >= 0:
                _draw_term(ax, var, t, out_grid[o], act[r], rb.inference.implication,
                           positions[o][t])
                ax.set_title(plot_text(f"#{r + 1}: {var.name} is {var.names[t]} "
                                       f"({act[r]:.3g})"), fontsize=7)
    last = axes[len(shown)]
    for i, var in enumerate(rb.inputs):
        last[i].axvline(x[i], color="k", lw=0.8, ls="--")
        last[i].set_title(plot_text(f"{var.name} = {x[i]:.4g}"), fontsize=7)
    for o, var in enumerate(rb.outputs):
        ax = last[n_in + o]
        _draw_aggregate(ax, rb, o, act, x, out_grid[o])
        ax.axvline(y[o], color=DEFUZZIFIED_COLOUR, lw=1.6)
        ax.set_title(plot_text(f"{var.name} = {y[o]:.4g}"), fontsize=8,
                     color=DEFUZZIFIED_COLOUR)
    for col, var in enumerate(rb.inputs + rb.outputs):
        for ax in axes[:, col]:
            ax.set_xlim(var.lo, var.hi)
            ax.set_ylim(0, max(1.05, ax.get_ylim()[1]))   # a SUM aggregate may pass 1
            ax.tick_params(labelsize=6)
        axes[-1, col].set_xlabel(axis_label(var.name, var.unit), fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel(MEMBERSHIP_LABEL, fontsize=7)
    more = f"; the {len(shown)} strongest drawn" if len(fired) > len(shown) else ""
    inputs = ", ".join(f"{v.name}={x[i]:.4g}" for i, v in enumerate(rb.inputs))
    fig.suptitle(plot_text(f"{model.name} at {inputs}: {plural(len(fired), 'rule')} fired{more}"),
                 fontsize=9)
    fig.tight_layout()
    return fig
