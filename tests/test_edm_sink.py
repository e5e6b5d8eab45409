"""EDM sinking plant and gap servos (Roberts 2014): hand-computed physics and closed loops.

Stability metric (stated as the brief asks): the standard deviation of the gap width (um)
after settling (t > 0.5 s), over a batch of 4 loops with independent mains phases and spark
noise; hunting of the servo (the thesis's symptom of instability: +-20 um at 20 Hz on the
commercial machine) shows up there first. A second check: no short circuit after settling.
"""
import numpy as np
import pytest

from fuzzyc.plants import edm_sink, scenario
from fuzzyc.runtime.simulate import simulate, summarize

P = edm_sink.EdmSinkParams()


def test_gap_voltage_levels_from_the_thesis():
    g = np.array([0.0, 0.005, 0.0051, 0.005 + 0.095 / np.sqrt(6), 0.100, 0.300])
    # short 0 V; just above the short, burning at 40 V; 40 + 60 * (1/sqrt 6)^2 = 50 V; open 100 V
    np.testing.assert_allclose(edm_sink.gap_voltage(P, g),
                               [0.0, 0.0, 40.0 + 60 * (0.0001 / 0.095) ** 2, 50.0, 100.0, 100.0])


def test_erosion_law():
    # dWSH/dt = max(0, C - k|V - 50|), k = C/30: full at 50 V, half at 65 V, none at a short
    c = 0.2 / 60
    np.testing.assert_allclose(edm_sink.erosion_speed(P, np.array([50.0, 65.0, 35.0, 0.0, 100.0])),
                               [c, c / 2, c / 2, 0.0, 0.0])


def test_actuator_steady_velocity():
    # Kf (Kv (vc - v) - Kb v) / R = c v  ->  v = Kf Kv vc / (R c + Kf (Kv + Kb))
    #  = 7*400*0.5e-3 / (12.4*5 + 7*408) = 1.4 / 2918 m/s = 0.4798 mm/s
    quiet = edm_sink.EdmSinkParams(mains=0.0, harmonic=0.0, spark_noise=0.0, gap0=5.0)
    state = edm_sink.initial_state(quiet, 1)
    for k in range(200):
        state, out = edm_sink.step(quiet, state, {"velocity": np.array([0.5])}, k * 1e-3, 1e-3)
    assert out["velocity_actual"][0] == pytest.approx(7 * 400 * 0.5 / (12.4 * 5 + 7 * 408),
                                                      rel=1e-6)


def test_pi_does_not_wind_up_in_saturation():
    pi = edm_sink.PIGapServo()
    pi.reset(1)
    # 1 s at -120 V error: Kp e = -2.4 mm/s is saturated, so the integral must not grow
    for _ in range(1000):
        out = pi.step({"gap_voltage": np.array([-70.0])})
    assert out["velocity"][0] == -2.0
    assert pi.integral[0] == 0.0
    # back at the set point the command is immediately ~0 (a wound-up PI would hold -1.2 mm/s)
    assert pi.step({"gap_voltage": np.array([50.0])})["velocity"][0] == 0.0


def run(baseline=False, **plant):
    overrides = {"duration": "1.5", **{f"plant.{k}": str(v) for k, v in plant.items()}}
    sc = scenario.load("edm_sink", overrides)
    trace = simulate(sc, batch=4, baseline=baseline)
    tail = trace.time > 0.5
    return {"mean": trace["mean_voltage"][tail].mean(),
            "gap_std": trace["gap"][tail].std(axis=0).mean(),
            "shorts": np.count_nonzero(trace["gap"][tail] <= P.g_short * 1e3)}


@pytest.fixture(scope="module")
def pi_noisy():
    return run(baseline=True)


def test_pi_baseline_holds_the_set_point_with_noise(pi_noisy):
    assert abs(pi_noisy["mean"] - 50.0) <= 5.0
    assert pi_noisy["shorts"] == 0


def test_shipped_fuzzy_servo_holds_50V_and_is_as_stable_as_pi(pi_noisy):
    """rulebases/edm_sink_gap.fz with noise on: mean gap voltage within 5 V of 50 V, no short,
    and a gap spread no larger than the PI baseline's (the stability metric above); without the
    spark noise (mains pick-up still on) it hunts less than PI as well."""
    fuzzy = run()
    assert abs(fuzzy["mean"] - 50.0) <= 5.0
    assert fuzzy["shorts"] == 0
    assert fuzzy["gap_std"] <= pi_noisy["gap_std"]
    assert run(spark_noise=0.0)["gap_std"] <= run(baseline=True, spark_noise=0.0)["gap_std"]


def test_the_scenario_note_on_pi_and_fuzzy_holds():
    """edm_sink.yaml's note, checked on the demo's own run: PI has the smaller mean voltage
    error, the fuzzy servo the smaller gap spread, neither shorts, equal erosion rates (1 %)."""
    sc = scenario.load("edm_sink")
    fuzzy = summarize(sc, simulate(sc))
    pi = summarize(sc, simulate(sc, baseline=True))
    err, spread = "mean gap voltage error", "gap spread (std after 1 s)"
    assert pi[err]["mean"] < fuzzy[err]["mean"]
    assert fuzzy[spread]["mean"] < pi[spread]["mean"]
    assert fuzzy["short circuits"]["mean"] == pi["short circuits"]["mean"] == 0
    assert fuzzy["erosion rate"]["mean"] == pytest.approx(pi["erosion rate"]["mean"], rel=0.01)
