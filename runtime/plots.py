"""PNG plots of a trace: one panel per signal, every loop of a (small) batch overlaid."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fuzzyc.atomic import save_figure  # noqa: E402
from fuzzyc.escape import plot_text  # noqa: E402

from .trace import SHOWN_LOOPS, Trace  # noqa: E402


def plot_trace(trace: Trace, path: str | Path, signals: list[str] | None = None,
               references: dict[str, str | float] | None = None,
               title: str = "") -> Path:
    """signals: the panels (default all); references: name -> a set-point drawn dashed, either
    a number or the name of another signal in the trace."""
    names = signals or list(trace.signals)
    references = references or {}
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 1.8 * len(names) + 0.6), sharex=True,
                             squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        ax.plot(trace.time, trace[name][:, :SHOWN_LOOPS], lw=0.8)
        ref = references.get(name)
        if isinstance(ref, str) and ref in trace:
            ax.plot(trace.time, trace[ref][:, 0], "k--", lw=0.8, label=plot_text(ref))
        elif ref is not None:
            ax.axhline(float(ref), color="k", ls="--", lw=0.8)
        ax.set_ylabel(plot_text(name), fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    if title:
        axes[0, 0].set_title(plot_text(title), fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=100)
