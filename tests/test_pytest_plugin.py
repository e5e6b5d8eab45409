"""The pytest plugin installs itself (entry point pytest11 `fuzzyc`): in a separate project that
only has .fz files, `pytest --fuzzyc-verify` (or `fuzzyc_verify = true` in its configuration)
collects every verify property as a test, with JUnit XML through pytest's own --junitxml.
test_packaging runs the same project against the installed wheel."""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

# cold = 1 up to 20, 0 from 60; hot = 0 up to 40, 1 from 80. `complete`: both cells of the
# one-input table have a rule (passes). `covers temp at least 0.5`: cold >= 0.5 only for
# temp <= 40 and hot >= 0.5 only for temp >= 60, so (40, 60) is a gap (fails).
HEATER = """controller heater {
  input temp in [0, 100]
  terms temp : cold = lshoulder(20, 60), hot = rshoulder(40, 80)
  var power in [0, 1]
  terms power : singletons low = 0 high = 1
  rule if temp is cold then power is high
  rule if temp is hot then power is low
  verify {
    complete
    covers temp at least 0.5
  }
}
"""


def make_project(folder: Path, ini: str = "") -> Path:
    """A project of its own: a pytest.ini (so no outer configuration applies) and one .fz."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "pytest.ini").write_text("[pytest]\n" + ini)
    (folder / "controllers").mkdir(exist_ok=True)
    (folder / "controllers" / "heater.fz").write_text(HEATER)
    return folder


def run_pytest(python: str, project: Path, *args: str, env: dict | None = None):
    env = {k: v for k, v in (env or os.environ).items()
           if not k.startswith("PYTEST_") and k != "PYTHONPATH"}
    return subprocess.run([python, "-m", "pytest", "-p", "no:cacheprovider", "-rA", *args],
                          cwd=project, capture_output=True, text=True, timeout=300, env=env)


def check_passing_and_failing(python: str, project: Path, env: dict | None = None) -> None:
    """Collected only when asked; then one pass, one failure with its counterexample, and the
    JUnit report says the same."""
    quiet = run_pytest(python, project, env=env)
    assert quiet.returncode == 5, quiet.stdout + quiet.stderr      # 5: no tests collected
    result = run_pytest(python, project, "--fuzzyc-verify", "--junitxml=report.xml", env=env)
    out = result.stdout
    assert result.returncode == 1, out + result.stderr
    assert "1 failed, 1 passed" in out, out
    assert "PASSED controllers/heater.fz::complete" in out
    assert "FAILED controllers/heater.fz::covers temp at least 0.5" in out
    assert "no rule fires >= 0.5 here" in out          # the verifier's report, no traceback
    cases = {c.get("name"): c for c in ET.parse(project / "report.xml").iter("testcase")}
    assert set(cases) == {"complete", "covers temp at least 0.5"}
    assert cases["complete"].find("failure") is None
    assert cases["covers temp at least 0.5"].find("failure") is not None


def test_plugin_collects_only_when_asked_and_reports_pass_and_failure(tmp_path):
    check_passing_and_failing(sys.executable, make_project(tmp_path / "project"))


def test_ini_key_turns_it_on_and_a_bad_file_is_reported_with_its_place(tmp_path):
    project = make_project(tmp_path / "project", "fuzzyc_verify = true\n")
    (project / "controllers" / "heater.fz").write_text(HEATER.replace("temp is cold",
                                                                      "temp is cool"))
    result = run_pytest(sys.executable, project)
    assert result.returncode == 2, result.stdout + result.stderr   # 2: collection error
    assert "heater.fz:6:19: error: unknown term `cool` of `temp`" in result.stdout
    assert "Traceback" not in result.stdout
