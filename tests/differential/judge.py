"""Many Systems of one tool judged at once: written to files, read by fuzzyc, run by the tool
(one batch), classified (`Verdict`)."""
from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import tools, toolbugs
from .compare import TOOLS, Ours, disagreeing_rows, ours, tolerances, worst
from .render import SUFFIX, render
from .spec import System


@dataclass
class Verdict:
    # refused, crashed, tool-error (the tool gave no number), agree, disagree, tool-bug (every
    # row agrees but rows that a known bug of the tool explains, with its evidence: toolbugs)
    status: str
    message: str         # fuzzyc's refusal or crash, the tool's error, or the worst distance
    text: str            # the file
    x: np.ndarray
    ours: np.ndarray | None = None
    tool: np.ndarray | None = None
    tolerance: np.ndarray | None = None
    worst: float = 0.0

    def rows(self) -> np.ndarray:
        """The rows where fuzzyc and the tool disagree."""
        return disagreeing_rows(self.ours, self.tool, self.tolerance)


def judge(tool_key: str, systems: list[System], xs: list[np.ndarray],
          folder: Path | None = None) -> list[Verdict]:
    tool, semantics, _ = TOOLS[tool_key]
    with tempfile.TemporaryDirectory() as tmp:
        where = Path(folder or tmp)
        paths, mine = [], []
        for k, (system, x) in enumerate(zip(systems, xs)):
            path = where / f"{system.name}_{k}{SUFFIX[system.fmt]}"
            path.write_text(render(system))
            paths.append(path)
            mine.append(ours(path, x, semantics))
        wanted = [k for k, got in enumerate(mine) if got.status == "imported"]
        results = tools.run(tool, [(paths[k], xs[k], [v.name for v in systems[k].inputs],
                                    [v.name for v in systems[k].outputs]) for k in wanted])
        by_index = dict(zip(wanted, results))
        verdicts = [_verdict(systems[k], paths[k], xs[k], mine[k], by_index.get(k), tool_key)
                    for k in range(len(systems))]
        if tool_key == "pyfuzzylite-fll":
            _semi_ellipse_numbers(tool, systems, paths, mine, verdicts)
        return verdicts


def _semi_ellipse_numbers(tool: str, systems: list[System], paths: list[Path],
                          mine: list[Ours], verdicts: list[Verdict]) -> None:
    """pyfuzzylite's SemiEllipse NaN where the tool still gives a number (the NaN membership
    drops its rule from the aggregation, whose fmax skips NaN): claimed where at every
    disagreeing row an input sits at a SemiEllipse end and the tool's own number a few ulps
    inside that end (its formula a number there) agrees with fuzzyc's at the row."""
    pending = []
    for k, verdict in enumerate(verdicts):
        if verdict.status != "disagree":
            continue
        rows = verdict.rows()
        terms = toolbugs.input_terms(systems[k])
        nudged = [toolbugs.semi_ellipse_nudged(terms, verdict.x[r]) for r in rows]
        if len(rows) and all(n is not None for n in nudged):
            pending.append((k, rows, np.array(nudged)))
    results = tools.run(tool, [(paths[k], nudged, [v.name for v in systems[k].inputs],
                                [v.name for v in systems[k].outputs])
                               for k, _, nudged in pending])
    for (k, rows, nudged), got in zip(pending, results):
        verdict, names = verdicts[k], [v.name for v in systems[k].outputs]
        if isinstance(got, Exception):
            continue
        got = got[:, [names.index(n) for n in mine[k].outputs]]
        if worst(verdict.ours[rows], got, verdict.tolerance) > 1:
            continue
        i = int(np.flatnonzero(nudged[0] != verdict.x[rows[0]])[0])
        verdict.status = "tool-bug"
        verdict.message = (
            "pyfuzzylite 8 bug: SemiEllipse membership NaN at its end drops its rule (sqrt "
            f"of a negative r^2 - (x - c)^2 by rounding){toolbugs.EVIDENCE}{len(rows)} "
            f"row(s); the tool a few ulps inside the end agrees, e.g. "
            f"{systems[k].inputs[i].name} = {float(verdict.x[rows[0]][i])!r} -> "
            f"{float(nudged[0][i])!r}")


def _verdict(system: System, path: Path, x: np.ndarray, mine: Ours, tool_y,
             tool_key: str = "") -> Verdict:
    """The file's class: a tool error that a known tool bug explains (with its evidence,
    differential.toolbugs) says so; a file whose rows agree but those such a bug explains
    (the tool's wrong numbers, or rows it fails on alone) is `tool-bug`, saying which."""
    text = path.read_text()
    if mine.status != "imported":
        return Verdict(mine.status, mine.message, text, x)
    failed_rows = ""
    if isinstance(tool_y, tools.RowsFailed):
        # the tool evaluated some rows: where a known bug explains exactly the others, the
        # file is judged on the rows the tool gives (agreeing there: tool-bug)
        bug = toolbugs.explain_failed_rows(tool_key, str(tool_y), path, x, tool_y.rows)
        if not bug:
            return Verdict("tool-error", f"{tool_y} (on {len(tool_y.rows)} of {len(x)} rows)",
                           text, x)
        kept = np.setdiff1d(np.arange(len(x)), tool_y.rows)
        failed_rows = bug
        x, tool_y = x[kept], tool_y.y[kept]
        mine = Ours(mine.status, mine.message, mine.y[kept], mine.inputs, mine.outputs)
    elif isinstance(tool_y, Exception):
        bug = toolbugs.explain_error(tool_key, str(tool_y), path, x)
        return Verdict("tool-error", bug or str(tool_y), text, x)
    order = [system.outputs.index(next(v for v in system.outputs if v.name == n))
             for n in mine.outputs]
    spans = np.array([system.outputs[o].hi - system.outputs[o].lo for o in order])
    tolerance = tolerances(spans, [system.sugeno] * len(order))
    tool_y = tool_y[:, [[v.name for v in system.outputs].index(n) for n in mine.outputs]]
    far = worst(mine.y, tool_y, tolerance)
    status = "agree" if far <= 1 else "disagree"
    defaults = [next(v for v in system.outputs if v.name == n).default for n in mine.outputs]
    bug = toolbugs.explain_disagreement(
        tool_key, toolbugs.input_terms(system), x, mine.y, tool_y, tolerance,
        disagreeing_rows(mine.y, tool_y, tolerance), defaults) if status == "disagree" else None
    if status == "disagree" and not bug and tool_key == "octave-fis":
        bug = toolbugs.explain_octave_disagreement(path, x, mine.y, tool_y, tolerance,
                                                   disagreeing_rows(mine.y, tool_y, tolerance))
    if bug:
        return Verdict("tool-bug", bug, text, x, mine.y, tool_y, tolerance, far)
    if failed_rows and status == "agree":
        return Verdict("tool-bug", failed_rows + "; the rows it evaluates agree", text, x,
                       mine.y, tool_y, tolerance, far)
    other = f" (other rows: {failed_rows.split(toolbugs.EVIDENCE)[0]})" if failed_rows else ""
    apart = f"{far:.3g} tolerances apart{other}"
    return Verdict(status, apart, text, x, mine.y, tool_y, tolerance, far)
