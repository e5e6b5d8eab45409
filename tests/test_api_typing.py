"""The API is typed (py.typed): a type checker sees through the lazy exports of fuzzyc/__init__
to the real signatures, so a user's mistake is caught before the code runs."""
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

USER_CODE = '''
import numpy as np
import fuzzyc

model = fuzzyc.load("controller.fz")
outputs: dict[str, np.ndarray] = fuzzyc.evaluate(model, {"e1": np.zeros(3)})
report: fuzzyc.VerifyReport = fuzzyc.verify(model, max_examples=10)
passed: bool = report.passed
header: fuzzyc.Header = fuzzyc.compile_c(model, "q15")
run: fuzzyc.Simulation = fuzzyc.simulate("wedm_rough", settings={"duration": 1})
wrong: int = fuzzyc.load("controller.fz")
fuzzyc.verify(model, max_examples="many")
'''


def test_a_type_checker_sees_the_api_signatures(tmp_path):
    pytest.importorskip("mypy", reason="mypy (the `test` extra) checks the API's types")
    (tmp_path / "user.py").write_text(USER_CODE)
    result = subprocess.run(
        [sys.executable, "-m", "mypy", "--follow-imports=silent", "--ignore-missing-imports",
         "--cache-dir", str(tmp_path / "cache"), "user.py"],
        cwd=tmp_path, capture_output=True, text=True, timeout=600,
        env={"MYPYPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    errors = [line for line in result.stdout.splitlines() if ": error:" in line]
    # exactly the two planted mistakes (lines 11 and 12 of USER_CODE), nothing else
    assert len(errors) == 2, result.stdout + result.stderr
    assert errors[0].startswith("user.py:11:") and '"Model"' in errors[0]
    assert errors[1].startswith("user.py:12:") and "max_examples" in errors[1]
