"""Pictures of a rule base: membership functions and control surfaces, as PNG.

Each picture has a `draw_*` function returning the matplotlib Figure (what the tests inspect)
and a `plot_*` one writing it atomically. Every axis names its unit: a variable declared
without one is dimensionless in the language, shown `[-]`.
"""
from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from .atomic import save_figure  # noqa: E402
from .engine.inference import evaluate  # noqa: E402
from .escape import OutputFolder, plot_text  # noqa: E402
from .engine.membership import memberships  # noqa: E402
from .semantics.model import Model, TermKind, Variable  # noqa: E402

MEMBERSHIP_LABEL = "membership [-]"


def axis_label(name: str, unit: str | None) -> str:
    """`name [unit]`; no unit declared is dimensionless, `[-]`."""
    return plot_text(f"{name} [{unit or '-'}]")


def term_colour(t: int) -> str:
    """One colour per term, the same in every picture of the variable (singletons included)."""
    return f"C{t % 10}"


def save(fig, path: Path) -> Path:
    return save_figure(fig, path, dpi=110)


def draw_variable(var: Variable):
    """The variable's terms over its range: a curve per term, a stem per singleton."""
    fig, ax = plt.subplots(figsize=(6, 2.6))
    x = np.linspace(var.lo, var.hi, 801)
    mu = memberships(var, x)
    for t, name in enumerate(var.names):
        if var.kinds[t] == TermKind.SINGLETON:
            ax.vlines(var.params[t, 0], 0, 1, lw=2, color=term_colour(t), label=plot_text(name))
        else:
            ax.plot(x, mu[:, t], lw=1.6, color=term_colour(t), label=plot_text(name))
    ax.set(xlabel=axis_label(var.name, var.unit), ylabel=MEMBERSHIP_LABEL, ylim=(-0.03, 1.08),
           xlim=(var.lo, var.hi))
    if 0 < var.n_terms <= 12:      # a variable may have no terms (read by linear consequents)
        ax.legend(loc="upper center", ncol=min(var.n_terms, 7), fontsize=7, frameon=False,
                  bbox_to_anchor=(0.5, 1.25))
    fig.tight_layout()
    return fig


def plot_variable(var: Variable, path: Path) -> Path:
    return save(draw_variable(var), path)


def _grid(lo_hi: list[tuple[float, float]], names: list[str], axes: tuple[str, str],
          fixed: dict[str, float], n: int):
    """The (n, n) mesh over the two `axes` and every column of the batch: the axes from the
    mesh, the others at `fixed` (default: the middle of the range)."""
    i, j = names.index(axes[0]), names.index(axes[1])
    X, Y = np.meshgrid(np.linspace(*lo_hi[i], n), np.linspace(*lo_hi[j], n))
    columns = {name: np.full(X.size, fixed.get(name, 0.5 * (lo + hi)))
               for name, (lo, hi) in zip(names, lo_hi)}
    columns[axes[0]], columns[axes[1]] = X.ravel(), Y.ravel()
    return X, Y, columns


def _surface_figure(X, Y, z, labels: tuple[str, str, str], title: str):
    """A 3D surface with a colour bar naming the output, at most 5 ticks per axis in a small
    font (the physical inputs' 4-digit ticks crammed into each other)."""
    from matplotlib.ticker import MaxNLocator
    fig = plt.figure(figsize=(7.2, 5.4))
    ax = fig.add_subplot(projection="3d")
    surface = ax.plot_surface(X, Y, z, cmap="viridis", linewidth=0, antialiased=True)
    ax.set_xlabel(labels[0], fontsize=8, labelpad=6)
    ax.set_ylabel(labels[1], fontsize=8, labelpad=6)
    ax.set_zlabel(labels[2], fontsize=8, labelpad=6)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(5))
    ax.tick_params(labelsize=7)
    bar = fig.colorbar(surface, ax=ax, shrink=0.6, pad=0.12)
    bar.set_label(labels[2], fontsize=8)
    bar.ax.tick_params(labelsize=7)
    ax.set_title(plot_text(title), fontsize=9)
    return fig


def _held(fixed: dict[str, float], axes: tuple[str, str]) -> str:
    held = ", ".join(f"{k}={v:g}" for k, v in fixed.items() if k not in axes)
    return f" ({held})" if held else ""


def draw_surface(model: Model, output: str, axes: tuple[str, str], fixed: dict[str, float],
                 n: int = 61):
    """The rule-base output over two rule-base (scaled) inputs, the others held at `fixed`."""
    rb = model.rulebase
    names = [v.name for v in rb.inputs]
    X, Y, columns = _grid([(v.lo, v.hi) for v in rb.inputs], names, axes, fixed, n)
    z = evaluate(rb, np.column_stack([columns[name] for name in names]))
    out = rb.outputs[rb.output_index(output)]
    by_name = {v.name: v for v in rb.inputs}
    labels = (axis_label(axes[0], by_name[axes[0]].unit),
              axis_label(axes[1], by_name[axes[1]].unit), axis_label(output, out.unit))
    return _surface_figure(X, Y, z[:, rb.output_index(output)].reshape(X.shape), labels,
                           f"{model.name}: {output}" + _held(fixed, axes))


def raw_surface(model: Model, output: str, axes: tuple[str, str], fixed: dict[str, float],
                n: int = 61) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(X, Y, Z) meshes: the rule-base output over two raw (physical) inputs of the
    controller, through one step of the signal chain from its initial state (delta() is 0,
    filters start at the input), the other raw inputs at `fixed` (default: mid-range)."""
    from .engine.chain import Controller
    names = [s.name for s in model.signals]
    X, Y, columns = _grid([(s.lo, s.hi) for s in model.signals], names, axes, fixed, n)
    controller = Controller(model, batch=X.size)
    controller.step(columns)
    return X, Y, np.asarray(controller.signals[output]).reshape(X.shape)


def draw_signal_surface(model: Model, output: str, axes: tuple[str, str],
                        fixed: dict[str, float], n: int = 61):
    """The figure of `raw_surface`."""
    X, Y, z = raw_surface(model, output, axes, fixed, n)
    by_name = {s.name: s for s in model.signals}
    out = model.rulebase.outputs[model.rulebase.output_index(output)]
    labels = (axis_label(axes[0], by_name[axes[0]].unit),
              axis_label(axes[1], by_name[axes[1]].unit), axis_label(output, out.unit))
    return _surface_figure(X, Y, z, labels, f"{model.name}: {output} over the raw inputs, "
                                            f"first step" + _held(fixed, axes))


def default_fixed(lo_hi: dict[str, tuple[float, float]]) -> dict[str, float]:
    """Where a surface holds the inputs it does not draw: the upper end of a range within
    [-1, 1] (a scaled error: its saturated end), else the middle."""
    return {name: hi if hi <= 1 else 0.5 * (lo + hi) for name, (lo, hi) in lo_hi.items()}


def has_physical_view(model: Model) -> bool:
    """Two raw inputs at least, and not simply the rule base's own inputs."""
    signals = [s.name for s in model.signals]
    return len(signals) >= 2 and set(signals) != {v.name for v in model.rulebase.inputs}


def draw_model(model: Model, axes: tuple[str, str] | None = None,
               fixed: dict[str, float] | None = None) -> dict[str, Figure]:
    """Every picture of `plot_model`, by file name (without .png): MODEL_VAR_terms per
    variable, MODEL_OUTPUT_surface per output over two rule-base inputs, and
    MODEL_OUTPUT_surface_raw over the last two raw inputs (`has_physical_view`). `fixed`
    holds the other inputs, rule-base or raw, by name."""
    rb = model.rulebase
    fixed = fixed or {}
    figures = {f"{model.name}_{v.name}_terms": draw_variable(v)
               for v in rb.inputs + rb.outputs if v.n_terms <= 12}
    if len(rb.inputs) >= 2:
        axes = axes or (rb.inputs[-2].name, rb.inputs[-1].name)
        held = default_fixed({v.name: (v.lo, v.hi) for v in rb.inputs})
        held.update((k, v) for k, v in fixed.items() if k in held)
        for v in rb.outputs:
            figures[f"{model.name}_{v.name}_surface"] = draw_surface(model, v.name, axes, held)
    if has_physical_view(model):
        raw_axes = (model.signals[-2].name, model.signals[-1].name)
        held = {s.name: 0.5 * (s.lo + s.hi) for s in model.signals}
        held.update((k, v) for k, v in fixed.items() if k in held)
        for v in rb.outputs:
            figures[f"{model.name}_{v.name}_surface_raw"] = draw_signal_surface(
                model, v.name, raw_axes, held)
    return figures


def plot_model(model: Model, out_dir: Path, axes: tuple[str, str] | None = None,
               fixed: dict[str, float] | None = None) -> list[Path]:
    """`draw_model`'s pictures written into out_dir as NAME.png, the names made safe
    (`OutputFolder`: variable names come from the input file)."""
    folder = OutputFolder(out_dir)
    return [save(fig, folder.file(name, ".png"))
            for name, fig in draw_model(model, axes, fixed).items()]


def draw_learning(pi: np.ndarray, title: str) -> Figure:
    """The performance index of each learning (cutting) cycle (`fuzzyc learn`): PI sums
    squares of the scaled, dimensionless error and change of force."""
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(np.arange(1, len(pi) + 1), pi, "o-")
    ax.set_xlabel("learning (cutting) cycle [-]")
    ax.set_ylabel("performance index PI [-]")
    ax.set_xlim(0.5, len(pi) + 0.5)
    ax.set_title(plot_text(title))
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def release(figures: Iterable[Figure]) -> None:
    """Hand figures to the caller: pyplot forgets them (no window in Jupyter or a GUI, no
    pile-up over a long session); they still draw and save."""
    for fig in figures:
        plt.close(fig)
