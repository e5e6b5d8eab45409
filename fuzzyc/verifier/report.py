"""Reports: readable text for the terminal, JSON and JUnit XML for CI, PNG plots of
counterexample traces. Every writer is atomic (temp file in the same folder, then rename)."""
from __future__ import annotations

import json
import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..atomic import save_figure, write_text
from ..display import plural
from ..escape import plot_text
from .result import Result, Status

MARK = {Status.PROVED: "PROVED  ", Status.HELD: "HELD    ", Status.VIOLATED: "VIOLATED",
        Status.UNDECIDED: "UNDECIDED"}
MAX_CELLS = 8


def format_result(r: Result) -> str:
    mark = "FINDING " if r.status == Status.VIOLATED and r.finding else MARK[r.status]
    lines = [f"{mark} {r.name}  [{r.summary()}, {r.seconds:.2f} s]"]
    for e in r.evidence:
        cases = f" ({e.cases} cases)" if e.cases else ""
        lines.append(f"    {e.method}: {e.status.value}{cases} - {e.detail}")
        for cell in e.cells[:MAX_CELLS]:
            lines.append(f"      cell: {cell}")
        if len(e.cells) > MAX_CELLS:
            lines.append(f"      ... and {len(e.cells) - MAX_CELLS} more")
        if e.point and e.status == Status.VIOLATED:
            lines.append("      at " + ", ".join(f"{k}={v:.6g}" for k, v in e.point.items()))
        if e.to_point and e.status == Status.VIOLATED:
            lines.append("      then " + ", ".join(f"{k}={v:.6g}"
                                                   for k, v in e.to_point.items()))
        if e.trace and e.status == Status.VIOLATED:
            lines.append(f"      trace: {trace_summary(e.trace)}")
    if r.status == Status.VIOLATED:
        if r.finding:
            lines.append(f"    recorded in the file: {r.finding}")
        lines.append(f"    reproduce: {r.reproduce}")
    return "\n".join(lines)


def trace_summary(trace: dict) -> str:
    parts = [f"{k}={v:g}" for k, v in trace.get("case", {}).items()]
    if trace.get("step"):
        name, at, value = trace["step"]
        parts.append(f"{name} steps to {value:g} at t={at:g} s")
    if trace.get("fault"):
        signal, kind, start, length = trace["fault"]
        parts.append(f"{signal} sensor {'stuck' if kind == 'stuck' else 'reads NaN'} from "
                     f"t={start:g} s for {length:g} s")
    if trace.get("plot"):
        parts.append(f"plot {trace['plot']}")
    if "violated_at" in trace:
        parts.append(f"first violated at t={trace['violated_at']:g} s")
    return ", ".join(parts)


def format_text(results: list[Result]) -> str:
    body = "\n".join(format_result(r) for r in results)
    counts = {s: sum(r.status == s for r in results) for s in Status}
    known = sum(r.status == Status.VIOLATED and r.finding is not None for r in results)
    tail = (f"{plural(len(results), 'property', 'properties')}: {counts[Status.PROVED]} "
            f"proved, {counts[Status.HELD]} held, {counts[Status.VIOLATED] - known} violated, {known} known findings, "
            f"{counts[Status.UNDECIDED]} undecided")
    return f"{body}\n{tail}"


def _plain(value):
    """numpy arrays and scalars inside nested dicts/lists -> JSON-ready Python values."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()
    return value


def _evidence_json(e) -> dict:
    return {"method": e.method, "status": e.status.value, "detail": e.detail, "cases": e.cases,
            "cells": e.cells, "point": e.point, "to_point": e.to_point,
            "trace": _plain(e.trace)}


def to_json(results: list[Result]) -> dict:
    return {"properties": [
        {"name": r.name, "kind": r.prop.kind, "text": r.prop.text,
         "location": str(r.prop.loc) if r.prop.loc else None, "status": r.status.value,
         "summary": r.summary(), "finding": r.finding, "failure": r.is_failure,
         "reproduce": r.reproduce, "seconds": r.seconds,
         "evidence": [_evidence_json(e) for e in r.evidence]} for r in results]}


def to_junit(results: list[Result]) -> str:
    suites = ET.Element("testsuites", name="fuzzyc verify")
    by_file: dict[str, list[Result]] = {}
    for r in results:
        by_file.setdefault(r.name.split("::")[0], []).append(r)
    for file, rs in by_file.items():
        suite = ET.SubElement(suites, "testsuite", name=file, tests=str(len(rs)),
                              failures=str(sum(r.is_failure for r in rs)),
                              skipped=str(sum(r.finding is not None and
                                              r.status == Status.VIOLATED for r in rs)))
        for r in rs:
            case = ET.SubElement(suite, "testcase", classname=file, name=r.name.split("::", 1)[1],
                                 time=f"{r.seconds:.3f}")
            if r.is_failure:
                ET.SubElement(case, "failure", message=r.summary()).text = format_result(r)
            elif r.status == Status.VIOLATED:
                ET.SubElement(case, "skipped", message=f"known finding: {r.finding}")
            else:
                ET.SubElement(case, "system-out").text = format_result(r)
    return ET.tostring(suites, encoding="unicode")


def write_reports(results: list[Result], folder: str | os.PathLike) -> list[Path]:
    folder = Path(folder)
    json_path, junit_path = folder / "verify.json", folder / "verify.junit.xml"
    write_text(json_path, json.dumps(to_json(results), indent=1))
    write_text(junit_path, to_junit(results))
    return [json_path, junit_path]


@dataclass
class VerifyReport:
    """The results of `fuzzyc.verify`, one per property, in the file's order."""
    results: list[Result]

    @property
    def passed(self) -> bool:
        """No property violated except the findings the file records."""
        return not self.failures

    @property
    def failures(self) -> list[Result]:
        """The violations nobody recorded (what fails CI)."""
        return [r for r in self.results if r.is_failure]

    def text(self) -> str:
        """What `fuzzyc verify` prints."""
        return format_text(self.results)

    def to_json(self) -> dict:
        return to_json(self.results)

    def to_junit(self) -> str:
        return to_junit(self.results)

    def write(self, folder: str | os.PathLike) -> list[Path]:
        """verify.json and verify.junit.xml in folder (atomically); returns their paths."""
        return write_reports(self.results, folder)

    def __repr__(self) -> str:          # the verdict counts and the failures
        from ..display import report_text
        return report_text(self)

    def _repr_html_(self) -> str:       # Jupyter: a row per property
        from ..display import report_html
        return report_html(self)


def trace_marks(check, scenario, model, params: dict[str, float]) -> dict:
    """What a counterexample plot needs beyond the signals, kept in the trace (so a report
    read later draws the same): `units` (signal -> unit: the plant's, the observers', the rule
    files'; sensed_X and baseline_X as X) and `marks`, horizontal lines [signal, value, label]
    for each limit of the check (`always y < 35`, `abs(y - r) < 0.05`, `settles y to r within
    0.1`) and the set point it names."""
    from fuzzyc.runtime.simulate import signal_units
    units = signal_units(scenario)
    for item in (*model.signals, *model.steps, *model.outputs):
        if item.unit:
            units.setdefault(item.name, item.unit)
    for name in list(units):
        for prefix in ("sensed_", "baseline_"):
            units.setdefault(prefix + name, units[name])
    # a param the scenario schedules (fopdt's set point r) is a signal of the trace
    constants = {k: v for k, v in params.items() if k not in scenario.schedules}
    return {"units": units, "marks": _limit_marks(check, constants)}


def _constant(expr, params: dict[str, float]) -> float | None:
    """expr's value when it holds only numbers and params, else None."""
    import sympy
    value = sympy.sympify(expr).subs({sympy.Symbol(k): v for k, v in params.items()})
    return float(value) if value.is_number and value.is_real else None


def _limit_marks(check, params: dict[str, float]) -> list[list]:
    import sympy
    a, marks = check.args, []
    if check.kind == "settles":
        target = _constant(a["target"], params)
        if target is not None:
            tol = float(a["tolerance"])
            marks += [[a["signal"], target, f"set point {target:g}"],
                      [a["signal"], target - tol, f"band ±{tol:g}"],
                      [a["signal"], target + tol, None]]
        return marks
    predicate = a.get("predicate")
    parts = predicate.args if isinstance(predicate, (sympy.And, sympy.Or)) else [predicate]
    for rel in parts:
        if not isinstance(rel, sympy.core.relational.Relational):
            continue
        lhs, rhs = rel.lhs, rel.rhs
        if _constant(lhs, params) is not None:
            lhs, rhs = rhs, lhs
        limit = _constant(rhs, params)
        if limit is None:
            continue
        text = plot_text(f"limit: {rel}")
        if isinstance(lhs, sympy.Symbol):
            marks.append([lhs.name, limit, text])
        elif isinstance(lhs, sympy.Abs):
            marks += _band_marks(lhs.args[0], limit, text, params, check.text)
    return marks


def _band_marks(inner, limit: float, text: str, params: dict[str, float],
                written: str) -> list[list]:
    """abs(y - r) < limit: on y's panel, r (a number, or a signal drawn as a line) and r +-
    limit; nothing for other shapes."""
    import sympy
    # the panel: a signal (not a param) of coefficient +-1, the first in the check's text
    # (abs(y - r): y, its set point r; sympy may have reordered it to Abs(r - y))
    signals = [s for s in inner.free_symbols
               if s.name not in params and inner.coeff(s) in (1, -1)]
    if not signals:
        return []
    signals.sort(key=lambda s: (re.search(rf"\b{re.escape(s.name)}\b", written) or
                                re.search("$", written)).start())
    rest = signals[0] - inner / inner.coeff(signals[0])
    centre = _constant(rest, params)
    if centre is not None:
        return [[signals[0].name, centre, f"set point {centre:g}"],
                [signals[0].name, centre - limit, text], [signals[0].name, centre + limit, None]]
    if isinstance(rest, sympy.Symbol):
        return [[signals[0].name, rest.name, f"set point {rest.name}"],
                [signals[0].name, [rest.name, limit], text]]
    return []


def draw_trace(trace: dict, signals: list[str], title: str):
    """A counterexample trace: each named signal against time (its unit from the trace's
    `units`), its limits and set point as labelled lines, the first violation marked."""
    from ..plotting import plt
    from fuzzyc.runtime.plots import trace_label
    shown = [s for s in signals if s in trace["signals"]] or list(trace["signals"])[:1]
    fig, axes = plt.subplots(len(shown), 1, sharex=True, figsize=(8, 1.9 * len(shown) + 0.9),
                             squeeze=False)
    t = np.asarray(trace["t"])
    units = trace.get("units", {})
    for ax, name in zip(axes[:, 0], shown):
        ax.plot(t, trace["signals"][name], lw=1, color="C0", label=plot_text(name))
        for signal, value, label in trace.get("marks", []):
            if signal == name:
                _draw_mark(ax, t, trace["signals"], value, label)
        if trace.get("violated_at") is not None:
            ax.axvline(trace["violated_at"], color="r", ls="--", lw=1,
                       label=f"first violated, t = {trace['violated_at']:.4g} s")
        ax.set_ylabel(trace_label(name, units.get(name)), fontsize=8)
        if len(ax.get_legend_handles_labels()[1]) > 1:
            ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    if len(t):
        axes[-1, 0].set_xlim(t[0], t[-1])
    fig.suptitle(plot_text(title), fontsize=9)
    fig.tight_layout()
    return fig


def _draw_mark(ax, t: np.ndarray, signals: dict, value, label: str | None) -> None:
    """A mark: a number (a horizontal line), a signal's name (that signal, a set point) or
    [signal, limit] (the band signal +- limit)."""
    colour = "C2" if label and label.startswith("set") else "C3"
    if isinstance(value, str):
        if value in signals:
            ax.plot(t, signals[value], color=colour, ls="--", lw=1, label=plot_text(label))
    elif isinstance(value, (list, tuple)):
        if value[0] in signals:
            centre = np.asarray(signals[value[0]], float)
            ax.plot(t, centre - value[1], color=colour, ls=":", lw=1, label=plot_text(label))
            ax.plot(t, centre + value[1], color=colour, ls=":", lw=1)
    else:
        ax.axhline(value, color=colour, ls=":", lw=1, label=label and plot_text(label))


def plot_trace(trace: dict, signals: list[str], title: str, path: str | os.PathLike) -> Path:
    """draw_trace written to path (atomically)."""
    return save_figure(draw_trace(trace, signals, title), path, dpi=90)


def counterexample_figures(results: list[Result]) -> dict:
    """property name -> the figure of its closed-loop counterexample (as `verify
    --report-dir` writes them)."""
    figures = {}
    for r in results:
        for e in r.evidence:
            if e.trace and e.status == Status.VIOLATED:
                shown = e.trace.get("shown") or list(e.trace["signals"])
                figures[r.name] = draw_trace(e.trace, shown, r.name)
    return figures
