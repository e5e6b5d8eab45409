"""The comparison table of `make demo`: every paper scenario, rule base against baseline.

Iterates over the shipped scenario files (each one's rule base and baseline), runs both at
batch 1, and prints one row per scenario and controller with the scenario's own metrics.
out/simulate/NAME/trace.png draws both runs on one figure; the summaries go to
out/simulate/NAME/{fuzzy,baseline}/summary.txt.
"""
from __future__ import annotations

import time
from pathlib import Path

from ..atomic import write_text
from ..cli.simulate import controller_notes, format_summary

OUT = Path("out") / "simulate"


def _cell(value: dict) -> str:
    mean = value["mean"]
    return "-" if mean != mean else f"{mean:.4g}"


def run_one(scenario, baseline: bool):
    """One run at batch 1: its trace and summary (the summary also written out)."""
    from fuzzyc.runtime.simulate import simulate, summarize
    trace = simulate(scenario, baseline=baseline)
    summary = summarize(scenario, trace)
    folder = OUT / scenario.name / ("baseline" if baseline else "fuzzy")
    write_text(folder / "summary.txt", format_summary(
        scenario.title, "baseline" if baseline else "fuzzy", summary, trace,
        controller_notes(scenario, baseline) + scenario.notes))
    return trace, summary


def plot_comparison(scenario, traces: dict) -> None:
    from fuzzyc.runtime.plots import plot_runs
    from fuzzyc.runtime.simulate import references, signal_units
    first = next(iter(traces.values()))
    panels = [n for n in scenario.plots if n in first] or None
    plot_runs(traces, OUT / scenario.name / "trace.png", panels, references(scenario),
              scenario.title, signal_units(scenario))


def main(names: list[str] | None = None) -> int:
    from fuzzyc.plants.scenario import available, load
    start = time.perf_counter()
    for name in names or available():
        scenario = load(name)
        traces, runs = {}, {}
        traces["fuzzy"], runs["fuzzy"] = run_one(scenario, False)
        if scenario.baseline and scenario.rulebase_path() is not None:
            traces["baseline"], runs["baseline"] = run_one(scenario, True)
        plot_comparison(scenario, traces)
        labels = list(runs["fuzzy"])
        print(f"\n{scenario.title}")
        width = max(len(label) for label in labels) + 2
        print(f"  {'metric':{width}s}" + "".join(f"{k:>12s}" for k in runs))
        for label in labels:
            unit = runs["fuzzy"][label]["unit"]
            cells = "".join(f"{_cell(r[label]):>12s}" for r in runs.values())
            print(f"  {label:{width}s}{cells}  {unit}")
        for note in controller_notes(scenario, False) + scenario.notes:
            print(f"  note: {note}")
    print(f"\n(plots and summaries in {OUT}; {time.perf_counter() - start:.0f} s)")
    return 0
