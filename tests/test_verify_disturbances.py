"""Closed-loop envelopes beyond plant parameters: set-point changes (`vary controller.P`) and
sensor faults (`fault SIGNAL nan|stuck for T`), on the toy gap plant with known answers.

The toy servo (the shipped EDM servo, Vmax = 2 mm/s) against a gap whose voltage is 1 V per um:
from 80 V the error e = (80 - 50) / 20 = 1.5 clamps to 1 (row PB) and ce is 0 (column Z), so the
servo advances at PB = 0.3 x 2 mm/s = 0.6 mm/s = 600 um/s, against 5 um/s of erosion.
"""
import numpy as np
import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import parse
from fuzzyc.verifier import Options, Status, verify_model
from fuzzyc.verifier import closed_loop
from toy_gap import SERVO, scenario, toy_plant, toy_servo  # noqa: F401  (fixtures)
from conftest import ROOT

FAST = dict(max_examples=20, seed=1)


def test_a_drawn_set_point_reaches_the_controller(toy_plant, scenario):
    # Set points below 45 V break `always gap_voltage > 45`; the shrinker walks toward the
    # file's Vset = 50 (holds) and keeps the simplest failing case. The trace settles at the
    # DRAWN set point (+ the ~0.3 V the servo needs to balance 5 um/s of erosion: 0.005 mm/s =
    # dv 0.0025, e = 0.0156 on the ZO-PS slope, 0.31 V), so the value reached the controller.
    results = verify_model(toy_servo(scenario, checks="vary controller.Vset in [40, 60] steps "
                                     "before 1 s\n      always gap_voltage > 45\n"),
                           Options(**FAST))
    (result,) = results
    assert result.status == Status.VIOLATED
    trace = result.violation.trace
    final_setpoint = trace["step"][2] if trace["step"] else trace["case"]["controller.Vset"]
    assert final_setpoint < 45
    signals = trace["signals"]
    assert signals["Vset"][-1] == final_setpoint
    assert signals["gap_voltage"][-1] == pytest.approx(final_setpoint + 0.31, abs=0.1)


def test_set_point_steps_inside_their_window_are_tracked(toy_plant, scenario):
    # Steps anywhere in 46..60 V before 1 s: the servo (600 um/s at full error) is back within
    # 3 V long before 1.8 s, and never dips under 35 V.
    checks = ("vary controller.Vset in [46, 60] steps before 1 s\n"
              "      settles gap_voltage to Vset within 3 by 1.8 s\n"
              "      always gap_voltage > 35\n")
    results = verify_model(toy_servo(scenario, checks=checks), Options(**FAST))
    assert [r.status for r in results] == [Status.HELD, Status.HELD]


class _Envelope:
    duration = 2.0

    @staticmethod
    def steppable(key):
        return True


def test_drawn_cases_respect_ranges_windows_and_faults():
    args = {"vary": {"controller.Vset": (46.0, 60.0)}, "steps_before": {"controller.Vset": 1.0},
            "faults": [("gap_voltage", "stuck", 0.3)]}
    cases = closed_loop._draw_cases(_Envelope(), args, 60, seed=3)
    steps = [c["step"] for c in cases if c["step"]]
    faults = [c["fault"] for c in cases if c["fault"]]
    assert steps and faults and len(steps) < 60 and len(faults) < 60
    assert all(k == "controller.Vset" and 0 <= t <= 1.0 and 46 <= v <= 60 for k, t, v in steps)
    assert all(f[:2] == ("gap_voltage", "stuck") and 0 <= f[2] <= 2.0 and f[3] == 0.3
               for f in faults)
    assert all(46 <= c["controller.Vset"] <= 60 for c in cases)


def test_a_nan_sensor_stops_the_servo_and_the_gap_stays_safe(toy_plant, scenario):
    # A NaN voltage fires no rule: dv falls back to its default 0, the electrode holds, and the
    # gap only opens by erosion, so `always gap > 5` holds with NaN faults anywhere.
    results = verify_model(toy_servo(scenario, checks="fault gap_voltage nan for 0.3 s\n"
                                     "      always gap > 5\n"), Options(**FAST))
    assert results[0].status == Status.HELD


def _loop(model, scenario_name):
    from fuzzyc.plants import scenario as scenarios
    return closed_loop._Loop(model, scenarios.load(scenario_name), 2.0, "numpy", 0)


def test_fault_windows_by_hand(toy_plant, scenario):
    model = toy_servo(scenario)
    nominal = {"plant.erosion": 5.0, "step": None}
    cases = [{**nominal, "fault": ("gap_voltage", "nan", 1.0, 0.3)},
             {**nominal, "fault": ("gap_voltage", "stuck", 0.0, 0.1)}]
    time, signals = _loop(model, scenario).run(cases)
    t = time - 0.001                              # the trace row of period k is at (k + 1) dt
    nan_window = (t >= 1.0) & (t < 1.3)
    # NaN: the servo holds still (velocity 0 exactly) and the gap opens by 5 um/s x 0.3 s; the
    # plant sees the controller's output one period later, so the 300 still periods are the
    # ones after the first faulty sample up to the first healthy one
    assert np.all(signals["velocity"][nan_window, 0] == 0.0)
    assert np.all(np.isnan(signals["sensed_gap_voltage"][nan_window, 0]))
    gap, first = signals["gap"][:, 0], int(np.argmax(nan_window))
    assert gap[first + 300] - gap[first] == pytest.approx(1.5, abs=1e-9)
    # stuck from the first sample: the sensor keeps reading the first 80-ish V, the servo keeps
    # advancing at 600 um/s, the true gap falls at 595 um/s for 0.1 s
    stuck = t < 0.1
    sensed = signals["sensed_gap_voltage"][stuck, 1]
    assert np.all(sensed == sensed[0]) and sensed[0] > 75
    slope = np.diff(signals["gap"][stuck, 1])[5:] / 0.001
    assert slope == pytest.approx(-595.0, abs=1e-6)
    assert np.all(np.isfinite(signals["gap_voltage"]))           # checks read the true value


def test_a_stuck_sensor_is_found_and_shrunk(toy_plant, scenario, tmp_path):
    # Stuck while the servo still closes the gap: the sensor keeps saying "wide", the servo
    # keeps advancing at 600 um/s and drives the electrode into the work.
    results = verify_model(toy_servo(scenario, checks="fault gap_voltage stuck for 0.3 s\n"
                                     "      always gap > 5\n"),
                           Options(report_dir=str(tmp_path), **FAST))
    (result,) = results
    assert result.status == Status.VIOLATED
    trace = result.violation.trace
    signal, kind, start, length = trace["fault"]
    assert (signal, kind, length) == ("gap_voltage", "stuck", 0.3)
    # from 80 um at 595 um/s the gap reaches 5 um after 75 / 595 = 0.126 s of the fault
    assert trace["violated_at"] == pytest.approx(start + 0.126, abs=0.01)
    assert trace["case"] == {"plant.erosion": 5.0}            # shrunk to the nominal plant
    assert "gap_voltage sensor stuck from t=" in result.violation.detail
    assert "sensed_gap_voltage" in trace["signals"]
    assert (tmp_path / trace["plot"].split("/")[-1]).exists()


def test_a_set_point_the_scenario_changes_cannot_also_vary():
    from fuzzyc.language.parser import load
    model = load(f"{ROOT}/rulebases/wedm_three_region.fz")
    loop = next(p for p in model.properties if p.kind == "closed_loop")
    loop.args.update(scenario="wedm_setpoint", vary={"controller.Yr2": (0.4, 0.6)})
    model.properties = [loop]
    results = verify_model(model, Options(max_examples=2))
    assert all(r.status == Status.UNDECIDED for r in results)
    assert "already changes `Yr2` on a schedule" in results[0].evidence[0].detail


def test_a_fault_on_a_signal_the_plant_does_not_measure_is_undecided(toy_plant, scenario):
    results = verify_model(toy_servo(scenario, checks="fault spark_freq nan for 1 s\n"
                                     "      always gap > 5\n"), Options(max_examples=2))
    assert results[0].status == Status.UNDECIDED
    assert "`fault spark_freq`" in results[0].evidence[0].detail


def test_the_c_backend_follows_a_varying_set_point(toy_plant, scenario):
    # the header compiles params in; a drawn or stepped set point becomes an input of the C
    # controller, fed from the bus: the same verdicts and details as the numpy engine
    pytest.importorskip("fuzzyc.backends.c.load")
    checks = ("vary controller.Vset in [40, 60] steps before 1 s\n"
              "      always gap_voltage > 45\n      settles gap_voltage to Vset within 5 by 1.8 s\n")
    options = dict(max_examples=6, seed=1, shrink_rounds=1)
    numpy_side = verify_model(toy_servo(scenario, checks=checks), Options(**options))
    c_side = verify_model(toy_servo(scenario, checks=checks), Options(backend="c", **options))
    assert [r.status for r in c_side] == [r.status for r in numpy_side]
    # set points below 45 V break the first (test_a_drawn_set_point_reaches_the_controller)
    assert [r.status for r in c_side] == [Status.VIOLATED, Status.HELD]
    assert [r.evidence[0].detail for r in c_side] == [r.evidence[0].detail for r in numpy_side]


def _with_loop(items: str) -> str:
    loop = f"  verify {{\n    closed_loop edm_sink for 2 s {{\n{items}    }}\n  }}\n}}\n"
    return SERVO.split("  # Findings")[0].rstrip().rstrip("}") + loop


@pytest.mark.parametrize("item, column, message", [
    ("      vary controller.Vref in [40, 60]\n", 12,
     "`controller.Vref`: this file has no param `Vref`; known: Vset, Vmax"),
    ("      vary gap0 in [1, 2]\n", 12,
     "`vary gap0`: vary a plant parameter (plant.NAME) or a param of this file"),
    ("      fault gap_voltage nan for 0 s\n", 33, "a fault must last a positive time"),
    ("      fault gap_voltage nan for 2 V\n", 33, "a fault needs a time unit"),
    ("      vary plant.gap0 in [1, 2] steps before 3 V\n", 46,
     "`steps before` needs a time unit"),
])
def test_bad_envelopes_are_refused_at_their_place(item, column, message):
    text = _with_loop(item)
    line = text.splitlines().index(item.rstrip("\n")) + 1
    with pytest.raises(FuzzycError) as err:
        parse(text, "servo.fz")
    assert f"servo.fz:{line}:{column}: error: {message}" in str(err.value)


def test_an_unknown_fault_kind_is_a_syntax_error():
    with pytest.raises(FuzzycError, match=r"servo.fz:\d+:\d+: error"):
        parse(_with_loop("      fault gap_voltage broken for 1 s\n"), "servo.fz")


def test_a_shrunk_case_fails_alone_with_its_own_noise():
    # the EDM servo with spark noise and a stuck sensor: the shrunk case, re-run as a batch of
    # one, sees the noise of the loop it came from and fails at the same moment
    from fuzzyc.language.parser import load
    from fuzzyc.plants import scenario as scenarios
    from fuzzyc.verifier import temporal
    model = load(f"{ROOT}/rulebases/edm_sink_gap.fz")
    model.properties = [p for p in model.properties
                        if p.kind == "closed_loop" and p.args["faults"]]
    (result,) = verify_model(model, Options(max_examples=20, seed=0))
    assert result.status == Status.VIOLATED
    trace = result.violation.trace
    loop = closed_loop._Loop(model, scenarios.load("edm_sink"), 3.0, "numpy", 0)
    case = {**trace["case"], "step": trace["step"], "fault": trace["fault"],
            "noise": trace["noise"]}
    time, signals = loop.run([case])
    violated, when = temporal.evaluate(result.prop, time, signals, loop.params)
    assert violated[0] and when[0] == trace["violated_at"]
    # the same noisy voltage, sample for sample, as in the reported trace: what a replay
    # promises (docs/verification.md) is the verdict and its time, and the signals to 1e-9
    # relative -- a batch of one may round differently from the batch (numpy's SIMD kernels)
    reported = trace["signals"]["measured_voltage"]
    np.testing.assert_allclose(signals["measured_voltage"][:, 0], reported, rtol=1e-9,
                               atol=1e-9 * np.max(np.abs(reported)))
