"""PNG plots of traces: one panel per signal, with its unit; every loop of a (small) batch
overlaid, and several runs (fuzzy against baseline) in one figure, a colour per run."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

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
    its batch in its own colour. Several: a colour per run, its loops all in it. The first run
    (the rule base) is drawn last, on top; the others (a noisy baseline) lighter beneath it.
    A panel with more than one kind of line (runs, the set point) has a legend; the time axis
    ends where the data does."""
    first = next(iter(runs.values()))
    names = signals or list(first.signals)
    references, units = references or {}, units or {}
    several = len(runs) > 1
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 1.8 * len(names) + 0.6), sharex=True,
                             squeeze=False)
    start, end = _time_span(runs.values(), names)
    for ax, name in zip(axes[:, 0], names):
        for k, (label, trace) in enumerate(runs.items()):    # zorder: the first run on top
            if name not in trace:
                continue
            kept = trace.time <= end
            shown = trace[name][kept, :SHOWN_LOOPS]
            style = {"lw": 1.0, "zorder": 3} if k == 0 else {"lw": 0.8, "alpha": 0.55,
                                                               "zorder": 2}
            for loop in range(shown.shape[1]):
                colour = f"C{k}" if several else f"C{loop % 10}"
                legend = plot_text(label or "run") if loop == 0 else None
                ax.plot(trace.time[kept], shown[:, loop], color=colour, label=legend, **style)
        _running_mean(ax, first, name, end)
        ref = references.get(name)
        if isinstance(ref, str) and ref in first:
            kept = first.time <= end
            ax.plot(first.time[kept], first[ref][kept, 0], "k--", lw=0.8, zorder=4,
                    label=plot_text(f"set point {ref}"))
        elif ref is not None:
            ax.axhline(float(ref), color="k", ls="--", lw=0.8, zorder=4,
                       label=f"set point {float(ref):g}")
        ax.set_ylabel(trace_label(name, units.get(name)), fontsize=8)
        ax.grid(alpha=0.3)
        if len(ax.lines) > 1:
            ax.legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel("time [s]")
    axes[-1, 0].set_xlim(start, end)
    if title:
        axes[0, 0].set_title(plot_text(title), fontsize=9)
    fig.tight_layout()
    return fig


CHATTER = 0.3        # mean |step| over the range: a signal above it fills a band
MEAN_WINDOW = 0.5    # s: such a signal is shown with its running mean over this window


def _running_mean(ax, trace: Trace, name: str, end: float) -> None:
    """Over a signal that chatters, its lines filling a band (CartPole's push jumps by about
    half its range every 20-ms step: 0.48; its pole angle 0.18, the cart 0.016), the first
    loop's centred running mean over MEAN_WINDOW, labelled: what it does on average."""
    kept = trace.time <= end
    y = trace[name][kept, 0] if name in trace else np.zeros(0)
    if len(y) < 8 or not np.all(np.isfinite(y)) or np.ptp(y) == 0:
        return
    dt = float(np.median(np.diff(trace.time[kept])))
    window = int(round(MEAN_WINDOW / dt)) if dt > 0 else 0
    if np.mean(np.abs(np.diff(y))) <= CHATTER * np.ptp(y) or not 2 <= window < len(y):
        return
    mean = np.convolve(y, np.ones(window) / window, mode="valid")
    t = trace.time[kept][window // 2: window // 2 + len(mean)]
    ax.plot(t, mean, color="k", lw=1.2, zorder=5,
            label=f"running mean over {MEAN_WINDOW:g} s")


def _time_span(traces, names: list[str]) -> tuple[float, float]:
    """From the first sample to the last one where a drawn signal is a number and, for a plant
    with a `done` output (the corner path's end), where the last drawn loop is done: over
    every run. The corner scenario ran to 12,600 s with its path over near 3,000 s."""
    start, end = float("inf"), float("-inf")
    for trace in traces:
        if not len(trace.time):
            continue
        start = min(start, float(trace.time[0]))
        finite = np.zeros(len(trace.time), bool)
        for name in names:
            if name in trace:
                finite |= np.isfinite(trace[name][:, :SHOWN_LOOPS]).any(axis=1)
        if "done" in trace:
            done = trace["done"][:, :SHOWN_LOOPS] > 0
            finite &= ~np.concatenate([[False], done.all(axis=1)[:-1]])   # the sample it ends
        last = np.flatnonzero(finite)
        end = max(end, float(trace.time[last[-1] if len(last) else -1]))
    if not start < end:
        return (0.0, 1.0) if start == float("inf") else (start - 0.5, start + 0.5)
    return start, end


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
