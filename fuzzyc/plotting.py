"""Pictures of a rule base: membership functions and control surfaces, as PNG."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .atomic import save_figure  # noqa: E402
from .engine import evaluate  # noqa: E402
from .escape import OutputFolder, plot_text  # noqa: E402
from .membership import memberships  # noqa: E402
from .model import Model, TermKind, Variable  # noqa: E402


def save(fig, path: Path) -> Path:
    return save_figure(fig, path, dpi=110)


def plot_variable(var: Variable, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(6, 2.6))
    x = np.linspace(var.lo, var.hi, 801)
    mu = memberships(var, x)
    for t, name in enumerate(var.names):
        if var.kinds[t] == TermKind.SINGLETON:
            ax.vlines(var.params[t, 0], 0, 1, lw=2, label=plot_text(name))
        else:
            ax.plot(x, mu[:, t], lw=1.6, label=plot_text(name))
    unit = f" [{var.unit}]" if var.unit else ""
    ax.set(xlabel=plot_text(var.name + unit), ylabel="membership", ylim=(-0.03, 1.08),
           xlim=(var.lo, var.hi))
    if var.n_terms <= 12:
        ax.legend(loc="upper center", ncol=min(var.n_terms, 7), fontsize=7, frameon=False,
                  bbox_to_anchor=(0.5, 1.25))
    fig.tight_layout()
    return save(fig, path)


def plot_surface(model: Model, output: str, axes: tuple[str, str], fixed: dict[str, float],
                 path: Path, n: int = 61) -> Path:
    """The output over two rule-base inputs, the others held at `fixed` values."""
    rb = model.rulebase
    names = [v.name for v in rb.inputs]
    i, j = names.index(axes[0]), names.index(axes[1])
    gx = np.linspace(rb.inputs[i].lo, rb.inputs[i].hi, n)
    gy = np.linspace(rb.inputs[j].lo, rb.inputs[j].hi, n)
    X, Y = np.meshgrid(gx, gy)
    x = np.empty((X.size, len(names)))
    for k, v in enumerate(rb.inputs):
        x[:, k] = fixed.get(v.name, 0.5 * (v.lo + v.hi))
    x[:, i], x[:, j] = X.ravel(), Y.ravel()
    z = evaluate(rb, x)[:, rb.output_index(output)].reshape(X.shape)
    fig = plt.figure(figsize=(6, 4.6))
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(X, Y, z, cmap="viridis", linewidth=0, antialiased=True)
    held = ", ".join(f"{k}={v:g}" for k, v in fixed.items() if k not in axes)
    ax.set(xlabel=plot_text(axes[0]), ylabel=plot_text(axes[1]), zlabel=plot_text(output),
           title=plot_text(f"{model.name}: {output}" + (f" ({held})" if held else "")))
    fig.tight_layout()
    return save(fig, path)


def plot_model(model: Model, out_dir: Path, axes: tuple[str, str] | None = None,
               fixed: dict[str, float] | None = None) -> list[Path]:
    """Writes MODEL_VAR_terms.png per variable and MODEL_OUTPUT_surface.png per output into
    out_dir, the names made safe (`OutputFolder`): variable names come from the input file."""
    rb = model.rulebase
    folder = OutputFolder(out_dir)
    written = [plot_variable(v, folder.file(f"{model.name}_{v.name}_terms", ".png"))
               for v in rb.inputs + rb.outputs if v.n_terms <= 12]
    if len(rb.inputs) >= 2:
        axes = axes or (rb.inputs[-2].name, rb.inputs[-1].name)
        fixed = fixed or {v.name: v.hi if v.hi <= 1 else 0.5 * (v.lo + v.hi) for v in rb.inputs}
        for v in rb.outputs:
            written.append(plot_surface(model, v.name, axes, fixed,
                                        folder.file(f"{model.name}_{v.name}_surface", ".png")))
    return written
