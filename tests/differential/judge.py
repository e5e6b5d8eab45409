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
    status: str          # refused, crashed, tool-error, agree, disagree
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
        return [_verdict(systems[k], paths[k], xs[k], mine[k], by_index.get(k), tool_key)
                for k in range(len(systems))]


def _verdict(system: System, path: Path, x: np.ndarray, mine: Ours, tool_y,
             tool_key: str = "") -> Verdict:
    """The file's class; a tool error or disagreement that a known tool bug explains (with
    its evidence, differential.toolbugs) is a tool error saying so."""
    text = path.read_text()
    if mine.status != "imported":
        return Verdict(mine.status, mine.message, text, x)
    if isinstance(tool_y, Exception):
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
        return Verdict("tool-error", bug, text, x, mine.y, tool_y, tolerance, far)
    return Verdict(status, f"{far:.3g} tolerances apart", text, x, mine.y, tool_y, tolerance,
                   far)
