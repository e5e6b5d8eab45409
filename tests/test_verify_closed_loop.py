"""The closed-loop checker on a toy gap plant (first order, known answer) around the shipped
EDM sinking servo: held when correct, and a sign error in the gain is caught, shrunk, plotted."""
import dataclasses
import sys
import types

import numpy as np
import pytest

from fuzzyc.parser import parse
from fuzzyc.verify import Options, Status, verify_model

SERVO = open("rulebases/edm_sink_gap.fz").read()


@dataclasses.dataclass
class ToyGapParams:
    gap0: float = 80.0        # um at the start: voltage 50 + (80 - 50) = 80 V
    erosion: float = 5.0      # um/s the gap opens by itself
    gain: float = 1000.0      # um per mm of electrode advance


def _voltage(gap):
    return np.clip(50.0 + (gap - 50.0), 0.0, 120.0)   # 1 V per um around 50 um


def initial_state(params, batch, rng=None):
    return {"gap": np.full(batch, params.gap0, dtype=float)}


def step(params, state, inputs, t, dt, rng=None):
    # advancing (velocity > 0, mm/s) closes the gap; erosion opens it
    gap = state["gap"] + (params.erosion - params.gain * inputs["velocity"]) * dt
    return {"gap": gap}, {"gap_voltage": _voltage(gap), "gap": gap}


@pytest.fixture
def toy_plant(monkeypatch):
    import fuzzyc.plants
    module = types.ModuleType("fuzzyc.plants.toy_gap")
    ToyGapParams.__module__ = module.__name__
    module.ToyGapParams, module.initial_state, module.step = ToyGapParams, initial_state, step
    module.INPUTS, module.OUTPUTS = ("velocity",), ("gap_voltage", "gap")
    monkeypatch.setitem(sys.modules, module.__name__, module)
    monkeypatch.setattr(fuzzyc.plants, "toy_gap", module, raising=False)
    return module


@pytest.fixture
def scenario(tmp_path, monkeypatch):
    from fuzzyc.plants import scenario as scenarios
    monkeypatch.setattr(scenarios, "SCENARIO_DIR", tmp_path)
    path = tmp_path / "toy.yaml"
    path.write_text("title: toy gap\nplant:\n  model: toy_gap\n  params: {erosion: 5}\n"
                    "duration: 2\nperiod: 0.001\n")
    return "toy"


def _model(scenario_name, vmax="2 mm/s", checks=None):
    checks = checks or ("always gap_voltage < 100\n"
                        "      settles gap_voltage to Vset within 5 by 1.5 s\n")
    loop = (f"  verify {{\n    closed_loop {scenario_name} for 2 s {{\n"
            f"      vary plant.erosion in [0, 20]\n      {checks}    }}\n  }}\n}}\n")
    text = SERVO.split("  # Findings")[0].replace("param Vmax = 2 mm/s", f"param Vmax = {vmax}")
    return parse(text.rstrip().rstrip("}") + loop, "servo.fz")


def test_correct_servo_holds_on_every_case(toy_plant, scenario):
    # From 80 V the servo advances at up to 2 mm/s (2000 um/s) against at most 20 um/s of
    # erosion: the gap reaches 50 um +- 5 long before 1.5 s, and never opens to 100 V.
    results = verify_model(_model(scenario), Options(max_examples=12, seed=1))
    assert [r.status for r in results] == [Status.HELD, Status.HELD]
    assert all(r.evidence[0].cases == 12 for r in results)


def test_sign_error_in_the_gain_is_caught_and_shrunk(toy_plant, scenario, tmp_path):
    # Vmax = -2: the servo retracts when the gap is too wide, so the voltage runs to 120 V.
    report = tmp_path / "report"
    results = verify_model(_model(scenario, vmax="-2 mm/s"),
                           Options(max_examples=12, seed=1, report_dir=str(report)))
    always, settles = results
    assert always.status == Status.VIOLATED and settles.status == Status.VIOLATED
    evidence = always.violation
    # every erosion rate fails, so the shrinker lands on the scenario's nominal 5 um/s
    assert evidence.trace["case"] == {"plant.erosion": 5.0}
    # it starts at 80 V and runs away: 100 V is crossed after the first few samples
    assert 0 < evidence.trace["violated_at"] < 0.1
    assert (report / evidence.trace["plot"].split("/")[-1]).exists()
    assert "--only 'always gap_voltage < 100'" in always.reproduce


def test_unknown_signal_is_undecided_not_a_pass(toy_plant, scenario):
    results = verify_model(_model(scenario, checks="always spark_freq < 3\n"),
                           Options(max_examples=2))
    assert results[0].status == Status.UNDECIDED
    assert "spark_freq" in results[0].evidence[0].detail


def test_c_backend_gives_the_same_verdicts(toy_plant, scenario):
    pytest.importorskip("fuzzyc.backends.cload")
    options = dict(max_examples=6, seed=2, shrink_rounds=1)
    for vmax in ("2 mm/s", "-2 mm/s"):
        numpy_side = verify_model(_model(scenario, vmax=vmax), Options(**options))
        c_side = verify_model(_model(scenario, vmax=vmax), Options(backend="c", **options))
        assert [r.status for r in c_side] == [r.status for r in numpy_side]
        assert [r.evidence[0].detail for r in c_side] == [r.evidence[0].detail for r in numpy_side]


def test_wedm_sign_error_in_the_error_gain_is_caught_in_closed_loop():
    # GE2 = -10 instead of 10: e2 > 0 now means "abnormal ratio too high", so the controller
    # slows the feed when it should speed up and the ratio never climbs from 25 % to Yr2.
    from fuzzyc.parser import load
    model = load("rulebases/wedm_three_region.fz")
    loop = next(p for p in model.properties if p.kind == "closed_loop")
    check = next(c for c in loop.args["checks"] if c.kind == "eventually")
    model.properties = [dataclasses.replace(
        loop, args={**loop.args, "duration": 160.0, "checks": [check]})]
    correct = verify_model(model, Options(max_examples=4, seed=0, shrink_rounds=0))
    assert correct[0].status == Status.HELD
    model.params["GE2"].value = -10.0
    (result,) = verify_model(model, Options(max_examples=4, seed=0, shrink_rounds=0))
    assert result.status == Status.VIOLATED and result.finding is None
    assert "4 of 4 loops break it" in result.violation.detail
