"""Replays every case the differential fuzzer kept (tests/differential/cases/TOOL/NAME.*):
fuzzyc under the tool's semantics against the tool's recorded numbers (always), and the live
tool against its recorded numbers and fuzzyc (where installed; skipped with the reason
otherwise).  A case fuzzyc does not match yet is a strict xfail whose reason is its cause
(found by undoing the construct: tests/differential/shrink.py); a crash case must now give
numbers or a located refusal; a case whose record names a `tool_bug` must still be explained by
that bug, with its evidence (tests/differential/toolbugs.py)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tests.differential import toolbugs, tools
from tests.differential.cases import CASES, read_numbers
from tests.differential.compare import disagreeing_rows, ours, worst

CASE_FILES = sorted(p for p in CASES.rglob("*") if p.suffix in (".fll", ".fcl", ".fis"))


def _record(path: Path) -> dict:
    return json.loads(path.with_suffix(".json").read_text())


def _params():
    for path in CASE_FILES:
        record = _record(path)
        marks = [pytest.mark.xfail(strict=True, reason=record["open"])] if record.get("open") \
            else []
        yield pytest.param(path, record, marks=marks, id=f"{path.parent.name}/{path.stem}")


def test_cases_exist():
    assert CASE_FILES, "no kept case: run `cd tests && python -m differential --keep`"


@pytest.mark.parametrize("path, record", list(_params()))
def test_recorded(path, record):
    x = np.array(record["x"], dtype=float)
    got = ours(path, x, record["semantics"])
    assert got.status in ("imported", "refused"), got.message     # never a traceback
    if record["tool_y"] is None:         # a crash case: no numbers were recorded
        return
    assert got.status == "imported", got.message
    tool_y = read_numbers(record["tool_y"])
    if record.get("tool_bug"):      # the tool's numbers are wrong there: the bug, with evidence
        tolerance = np.array(record["tolerance"])
        why = toolbugs.explain_disagreement(
            {"pyfuzzylite": "pyfuzzylite-fll"}.get(record["tool"], record["tool"]),
            toolbugs.fll_input_terms(path.read_text()), x, got.y, tool_y, tolerance,
            disagreeing_rows(got.y, tool_y, tolerance),
            toolbugs.fll_output_defaults(path.read_text()))
        assert why and why.startswith(record["tool_bug"]), why
        return
    far = worst(got.y, tool_y, np.array(record["tolerance"]))
    assert far <= 1, f"{far:.3g} tolerances from {record['tool']}: ours {got.y.tolist()}, " \
                     f"tool {tool_y.tolist()}"


@pytest.mark.parametrize("path", CASE_FILES, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_live_tool_still_says_so(path):
    """The tool's numbers were recorded from the tool itself: still its numbers today."""
    record = _record(path)
    why = tools.available(record["tool"])
    if why:
        pytest.skip(why)
    if record["tool_y"] is None:
        pytest.skip("a crash case: the tool's numbers were not needed")
    x = np.array(record["x"], dtype=float)
    (y,) = tools.run(record["tool"], [(path, x, record["inputs"], record["outputs"])])
    assert not isinstance(y, Exception), y
    far = worst(y, read_numbers(record["tool_y"]), np.array(record["tolerance"]))
    assert far <= 1e-3, f"{record['tool']} now gives {y.tolist()}"
