"""PNG plots of traces: one panel per signal, with its unit; every loop of a (small) batch
overlaid, and several runs (fuzzy against baseline) in one figure, a colour per run."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fuzzyc.atomic import save_figure  # noqa: E402
from fuzzyc.escape import plot_text  # noqa: E402

from .trace import SHOWN_LOOPS, Trace  # noqa: E402


def trace_label(name: str, unit: str | None) -> str:
    """`name [unit]`; a signal whose unit nobody declared is shown by name alone (not as
    dimensionless: nothing says it is)."""
    return plot_text(f"{name} [{unit}]" if unit else name)


def draw_runs(runs: dict[str, Trace], signals: list[str] | None = None,
              references: dict[str, str | float] | None = None, title: str = "",
              units: dict[str, str] | None = None):
    """The figure of one or more runs of the same loop (label -> trace). One run: each loop of
    its batch in its own colour. Several: a colour per run, its loops all in it, a legend."""
    first = next(iter(runs.values()))
    names = signals or list(first.signals)
    references, units = references or {}, units or {}
    several = len(runs) > 1
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 1.8 * len(names) + 0.6), sharex=True,
                             squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        for k, (label, trace) in enumerate(runs.items()):
            if name not in trace:
                continue
            shown = trace[name][:, :SHOWN_LOOPS]
            if several:
                for loop in range(shown.shape[1]):
                    ax.plot(trace.time, shown[:, loop], lw=0.8, color=f"C{k}",
                            label=plot_text(label) if loop == 0 else None)
            else:
                ax.plot(trace.time, shown, lw=0.8)
        ref = references.get(name)
        if isinstance(ref, str) and ref in first:
            ax.plot(first.time, first[ref][:, 0], "k--", lw=0.8, label=plot_text(ref))
        elif ref is not None:
            ax.axhline(float(ref), color="k", ls="--", lw=0.8)
        ax.set_ylabel(trace_label(name, units.get(name)), fontsize=8)
        ax.grid(alpha=0.3)
    if several:
        axes[0, 0].legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel("time [s]")
    if title:
        axes[0, 0].set_title(plot_text(title), fontsize=9)
    fig.tight_layout()
    return fig


def plot_runs(runs: dict[str, Trace], path: str | Path, signals: list[str] | None = None,
              references: dict[str, str | float] | None = None, title: str = "",
              units: dict[str, str] | None = None) -> Path:
    """draw_runs written to path (atomically)."""
    return save_figure(draw_runs(runs, signals, references, title, units), path, dpi=100)


def plot_trace(trace: Trace, path: str | Path, signals: list[str] | None = None,
               references: dict[str, str | float] | None = None,
               title: str = "", units: dict[str, str] | None = None) -> Path:
    """One run. signals: the panels (default all); references: name -> a set-point drawn
    dashed, either a number or the name of another signal in the trace; units: name -> unit."""
    return plot_runs({"": trace}, path, signals, references, title, units)
