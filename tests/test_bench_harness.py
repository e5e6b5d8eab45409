"""`make bench`'s harness works end to end: `benchmarks/run_all.py --quick` runs every figure of
issue 29 in a fresh process each and writes one summary table with a row per figure, its
reference, ratio, target, met or not and the load average.  Speeds are not asserted (a quick
run on a shared machine is not a measurement): the run completes, no figure fails, the table
has every row."""
from __future__ import annotations

import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None,
                                reason="the C figures need gcc")


# its Dask row starts a local cluster: run with the other `cluster` tests, alone (Makefile)
@pytest.mark.cluster
def test_quick_bench_writes_every_figure(tmp_path):
    pytest.importorskip("distributed")
    out = tmp_path / "summary.md"
    run = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "run_all.py"), "--quick",
                          "--out", str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    text = out.read_text()
    assert text.splitlines()[0].endswith("(QUICK: harness check, not figures)")
    rows = [line for line in text.splitlines() if line.startswith("| ") and "---" not in line]
    labels = [r.split(" | ")[0] for r in rows[1:]]
    assert "FAILED" not in text
    expected = ["engine COA, WEDM, batch 20,000 (glibc's default thresholds)",
                "engine COA, WEDM, batch 20,000 (MALLOC_TRIM_THRESHOLD_=65536)",
                "engine exact centroid", "compiled header", "scalar path", "fuzzyc.evaluate(model, dict)",
                "Controller.step", "threads=2", "alternating batch 1 / batch 1000, WEDM",
                "alternating batch 1 / batch 1000, full table of 6 inputs",
                "generated float header", "generated q15 header", "closed loop",
                "Dask campaign, --workers 2"]
    for piece in expected:
        assert any(piece in label for label in labels), (piece, labels)
    assert len(rows) - 1 == 17, labels
    for r in rows[1:]:
        cells = [c.strip() for c in r.strip("|").split(" | ")]
        assert len(cells) == 9, r
        assert "->" in cells[6], r                        # the load average before -> after
        assert cells[5] in ("met", "**not met**", "-"), r


def test_docs_take_the_summary_between_the_markers_and_refuse_a_quick_run(tmp_path):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import run_all
    doc = tmp_path / "benchmarks.md"
    doc.write_text(f"# Benchmarks\n\nbefore\n\n{run_all.BEGIN}\nold\n{run_all.END}\n\nafter\n")
    table = "| figure | value |\n|---|---|\n| engine | 1 M/s |\n"
    full = tmp_path / "summary.md"
    full.write_text("# make bench: issue 29's figures\n\nRun 2026-01-01, commit abc.\n\n" + table)
    quick = tmp_path / "summary-quick.md"
    quick.write_text("# make bench: issue 29's figures (QUICK: harness check, not figures)\n\n"
                     + table)
    assert run_all.docs(quick, doc) == 1
    assert "\nold\n" in doc.read_text()
    assert run_all.docs(full, doc) == 0
    assert run_all.docs(full, doc) == 0                    # again: the same page
    assert doc.read_text() == (f"# Benchmarks\n\nbefore\n\n{run_all.BEGIN}\nRun 2026-01-01, "
                               f"commit abc.\n\n{table.strip()}\n{run_all.END}\n\nafter\n")
