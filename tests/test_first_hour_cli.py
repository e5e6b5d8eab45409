"""Issue 30, a control engineer's first hour: the small CLI findings, each with its known answer.

`eval` printed `ce = -0`; counts said `1 properties`; `simulate` did not say what ran the
controller; `tune --max-evaluations 80` ran 83 loops; progress bars could not be turned off;
`simulate --backend c` refused a scenario that schedules a `param`.
"""
from __future__ import annotations

import json
import os
import pty
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

FOPDT_PI = str(ROOT / "rulebases" / "fopdt_pi.fz")

ONE_PROPERTY = """controller heater {
  input x : degC in [0, 10]
  terms x : lo = lshoulder(2, 8), hi = rshoulder(2, 8)
  var y in [0, 1]
  terms y : singletons off = 0 on = 1
  rule if x is lo then y is on
  output u : W in [0, 100] = 100 * y
  verify { bounded y in [0, 1] }
}
"""


def fuzzyc(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "fuzzyc", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_eval_prints_zero_not_negative_zero():
    # y = 1 at the first step: delta(y) = 0, so ce = -0.0 / GCE = -0.0 in IEEE arithmetic
    run = fuzzyc("eval", FOPDT_PI, "y=1")
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines()[0] == "fopdt_pi: rule-base inputs e = 0, ce = 0"
    assert "-0" not in run.stdout
    from fuzzyc.cli.eval import _fmt, _short
    assert (_fmt(-0.0), _short(-0.0), _short(-1e-7), _fmt(-2.5)) == ("0.0", "0", "-1e-07", "-2.5")


def test_counts_agree_with_their_noun(tmp_path):
    path = tmp_path / "heater.fz"
    path.write_text(ONE_PROPERTY)
    check = fuzzyc("check", str(path))
    assert check.returncode == 0, check.stderr
    assert check.stdout.rstrip().endswith("; 4 terms; 1 rule; controller outputs u; 1 property")
    verify = fuzzyc("verify", str(path))
    assert "1 property: 1 proved, 0 held" in verify.stdout
    convert = fuzzyc("convert", str(path), str(tmp_path / "heater.fis"))
    assert convert.returncode == 0, convert.stderr
    assert "heater.fis: 1 rule, 1 input, 1 output" in convert.stdout
    from fuzzyc.display import plural
    assert [plural(n, "property", "properties") for n in (0, 1, 2)] == [
        "0 properties", "1 property", "2 properties"]


def test_simulate_names_its_back_end_and_runs_a_scheduled_param_in_c(tmp_path):
    """fopdt_step schedules the set point `r`, a param of fopdt_pi.fz: the C back end takes it
    as an input (the header compiles a param in as a constant) and follows the engine."""
    traces = {}
    for backend in ("numpy", "c"):
        out = tmp_path / backend
        run = fuzzyc("simulate", "--scenario", "fopdt_step", "--backend", backend,
                     "-o", str(out))
        assert run.returncode == 0, run.stderr
        said = {"numpy": "back end: numpy engine;", "c": "back end: generated C (float);"}
        assert said[backend] in run.stdout.splitlines()[1]
        assert json.loads((out / "summary.json").read_text())["backend"] == backend
        traces[backend] = np.genfromtxt(out / "trace.csv", delimiter=",", names=True)
    c, engine = traces["c"], traces["numpy"]
    assert c["r"][0] == 0 and c["r"][-1] == 1        # the schedule reached the C controller
    assert c["y"][-1] > 0.5                           # and it followed the step
    assert np.max(np.abs(c["u"] - engine["u"])) < 1e-5    # float C against the engine
    base = fuzzyc("simulate", "--scenario", "fopdt_step", "--baseline",
                  "-o", str(tmp_path / "base"))
    assert "controller: baseline; back end: Python (the scenario's baseline);" in base.stdout
    tool = fuzzyc("simulate", "--scenario", "fopdt_step", "--semantics", "matlab",
                  "-o", str(tmp_path / "matlab"))
    assert "; back end: numpy engine, matlab semantics; batch 1;" in tool.stdout


def test_scheduled_params_become_inputs_only_for_the_c_back_end():
    from fuzzyc.plants.scenario import load
    from fuzzyc.runtime.simulate import load_controller, scheduled_params_as_inputs
    scenario = load("fopdt_step")
    engine = load_controller(scenario, 1)
    assert "r" in engine.model.params and "r" not in engine.input_names
    model = fuzzyc_load(FOPDT_PI)
    assert scheduled_params_as_inputs(model, scenario) == ["r"]
    signal = model.signals[-1]
    assert (signal.name, signal.lo, signal.hi) == ("r", 0.0, 1.0) and "r" not in model.params


def fuzzyc_load(path):
    import fuzzyc as api
    return api.load(path)


def test_tune_budget_is_honoured_exactly():
    from fuzzyc.tune.loop import minimize_within
    calls = []

    def cost(theta):
        calls.append(np.array(theta))
        return float(np.sum((np.asarray(theta) - [0.3, -0.2, 0.7]) ** 2))
    lo, hi = np.full(3, -1.0), np.full(3, 1.0)
    best = minimize_within(cost, np.zeros(3), lo, hi, "powell", 7)
    assert len(calls) == 7                              # Powell alone would ask for more
    assert len({c.tobytes() for c in calls}) == 7       # no point run twice
    assert cost(best) == min(cost(c) for c in calls[:7]) < cost(np.zeros(3))
    calls.clear()
    best = minimize_within(cost, np.zeros(3), lo, hi, "powell", 200)
    assert len(calls) <= 200 and np.allclose(best, [0.3, -0.2, 0.7], atol=1e-3)
    calls.clear()       # nothing better than the start: the start is returned
    flat = minimize_within(lambda t: (calls.append(t), 1.0)[1], np.zeros(2), lo[:2], hi[:2],
                           "nelder-mead", 5)
    assert len(calls) == 5 and flat.tolist() == [0.0, 0.0]


def test_tune_cli_reports_the_budgeted_runs(tmp_path):
    run = fuzzyc("tune", FOPDT_PI, "--scenario", "fopdt_step", "--minimize", "iae(y)",
                 "--max-evaluations", "6", "--max-examples", "3", "-o", str(tmp_path / "t.fz"))
    assert run.returncode == 0, run.stderr
    assert "scipy powell within the bounds, 6 closed-loop runs" in run.stdout.splitlines()[0]
    assert "runs of the search, at most N" in " ".join(fuzzyc("tune", "--help").stdout.split())


def _stderr_on_a_terminal(*args: str, cwd) -> str:
    """What `fuzzyc ARGS` writes to stderr when stderr is a terminal (a pseudo-terminal)."""
    leader, follower = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "fuzzyc", *args], stdout=subprocess.PIPE,
                            stderr=follower, cwd=cwd)
    os.close(follower)
    chunks = []
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:       # the follower closed: EIO on Linux
            break
        if not chunk:
            break
        chunks.append(chunk)
    proc.communicate()
    os.close(leader)
    assert proc.returncode == 0
    return b"".join(chunks).decode(errors="replace")


def test_progress_bar_only_on_a_terminal_and_never_with_no_progress(tmp_path):
    args = ("simulate", "--scenario", "fopdt_step", "-o", "out")
    assert "simulating [" in _stderr_on_a_terminal(*args, cwd=tmp_path)
    assert "simulating [" not in _stderr_on_a_terminal(*args, "--no-progress", cwd=tmp_path)
    assert "simulating [" not in _stderr_on_a_terminal(*args, "--quiet", cwd=tmp_path)
    piped = fuzzyc(*args, cwd=tmp_path)
    assert piped.returncode == 0 and "simulating [" not in piped.stderr
    forced = fuzzyc(*args, "--progress", cwd=tmp_path)
    assert "simulating [" in forced.stderr
    both = fuzzyc(*args, "--progress", "--no-progress", cwd=tmp_path)
    assert both.returncode == 2 and "not allowed with" in both.stderr
    verify = fuzzyc("verify", FOPDT_PI, "--only", "consistent", "--no-progress")
    assert verify.returncode == 0 and verify.stderr == ""


def test_a_campaign_bar_counts_its_tasks_in_agreement(monkeypatch):
    import fuzzyc.runtime.campaign as campaign
    labels = []

    class Bar:
        def __init__(self, total, enabled, label):
            labels.append(label)

        def update(self, done):
            pass

        def close(self):
            pass
    monkeypatch.setattr(campaign, "Progress", Bar)
    cluster = campaign.Cluster(None, None, 10000)
    assert campaign.map_chunks(abs, [-3], cluster) == [3]
    assert campaign.map_chunks(abs, [-1, 2], cluster) == [1, 2]
    assert labels == ["chunks (1 task)", "chunks (2 tasks)"]
