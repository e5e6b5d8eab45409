"""The README's proof rows come from the installed `fuzzyc`: the console script of the venv
that holds the wheel runs `verify --prove` on a copy made by `fuzzyc examples`, and the bound the
README prints is the bound the proof prints (marker `proofs`: `make proofs`, about 80 s CPU)."""
import re
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT

FUZZYC = Path(sys.executable).parent / "fuzzyc"
ROW = "| EDM sinking: voltage settles within 10 V by 1 s |"


@pytest.mark.proofs
def test_edm_settling_row_is_what_verify_prove_prints(tmp_path):
    subprocess.run([FUZZYC, "examples", "project"], cwd=tmp_path, check=True, capture_output=True)
    result = subprocess.run([FUZZYC, "verify", "rulebases/edm_sink_gap.fz", "--prove", "--only",
                             "within 10 by 1 s"], cwd=tmp_path / "project", capture_output=True,
                            text=True, timeout=1800)
    assert result.returncode == 0, result.stdout + result.stderr
    verdict, reach = result.stdout.splitlines()[:2]
    assert verdict.startswith("PROVED") and "[proved (reach)" in verdict, result.stdout
    bound = float(re.search(r"Abs\(Vset - mean_voltage\) <= ([\d.]+) for all loops "
                            r"with plant.gap0 in \[0.03, 0.1\] over 3 s", reach).group(1))
    row = next(l for l in (ROOT / "README.md").read_text().splitlines() if l.startswith(ROW))
    answer, shown = row.split("|")[2:4]
    assert answer.strip() == "PROVED"
    assert shown.strip() == f"≤ {bound:.2f} V", (row, bound)
