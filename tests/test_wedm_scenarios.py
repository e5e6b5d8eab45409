"""The WEDM plant in closed loop with the three-region rule base, held to Yan & Liao (1998).

Each scenario runs once per module (batch 1, 300-380 s of 40-ms periods). The abnormal ratio
is judged on its 2-s moving average: a 40-ms count carries ~1.4 % of counting noise, and the
paper's figures are read by eye at the same scale. Targets the physics-based plant does not
meet are marked xfail(strict) with what it does instead: they are findings, not tuned away.
"""
import numpy as np
import pytest

from fuzzyc.plants.scenario import load
from fuzzyc.runtime import metrics
from fuzzyc.runtime.simulate import simulate, summarize

WINDOW = 50   # samples: 2 s at 40 ms


def smooth(x: np.ndarray) -> np.ndarray:
    kernel = np.ones(WINDOW) / WINDOW
    return np.stack([np.convolve(col, kernel, mode="valid") for col in x.T], axis=1)


def run(name, baseline=False):
    scenario = load(name)
    return scenario, simulate(scenario, baseline=baseline)


@pytest.fixture(scope="module")
def finish():
    return run("wedm_finish")


@pytest.fixture(scope="module")
def finish_baseline():
    return run("wedm_finish", baseline=True)


@pytest.fixture(scope="module")
def rough():
    return run("wedm_rough")


@pytest.fixture(scope="module")
def setpoint():
    return run("wedm_setpoint")


def ratio_view(trace):
    t = trace.time[WINDOW - 1:]
    return t, smooth(trace["abnormal_ratio"])[:, 0], smooth(trace["Yr2"])[:, 0]


def test_finish_starts_near_25_percent():
    # the plant's own start (0.2524), without the 40-ms counting noise: one noisy sample has
    # a std of ~0.013 (2,000 loops) and the first one of seed 0 lies 3.4 sigma off
    quiet = load("wedm_finish", {"duration": "0.04", "plant.params.noise": "0"})
    assert simulate(quiet)["abnormal_ratio"][0, 0] == pytest.approx(0.25, abs=0.04)


def finish_settling_time(finish) -> float:
    _, trace = finish
    t, ratio, ref = ratio_view(trace)
    return metrics.settling_time(t, ratio[:, None], ref[:, None], 0.03)[0]


def test_finish_reaches_40_percent_within_200_s(finish):
    # Fig. 7a: 25 % -> 40 % (band +- 3 %) within about 150 s; no later than 150 + 50 s
    assert finish_settling_time(finish) <= 150.0 + 50.0


def test_finish_settling_time_is_the_papers_150_s(finish):
    # Fig. 7a: about 150 s; the 150 +- 50 s. Here about 113 s (112.7 s at
    # seed 0): the time is the integrators' travel in the e1 = P block, where du1 = du2 move
    # feed and 1/t_off together. 40 % is reached at feed 0.67 mm/min, t_off 6.0 us: +0.37
    # mm/min at up to 1.8e-4 per 40 ms (4.5e-3 mm/min per s) is at least 82 s at the full
    # rate, longer as e2 falls from PB to PS near the set point. The finish cut's ratio
    # depends on the off-time as e^(-t/24 us) (plant docstring, round 4), so the feed must
    # climb this far; with round 3's law (e^(-t/12 us)) it stopped at +0.28 mm/min and 72 s.
    assert 150.0 - 50.0 <= finish_settling_time(finish) <= 150.0 + 50.0


def test_finish_no_overshoot_beyond_3_percent(finish):
    _, trace = finish
    _, ratio, ref = ratio_view(trace)
    assert metrics.overshoot(ratio[:, None], ref[:, None])[0] < 0.03


def test_finish_spark_frequency_below_reference(finish):
    _, trace = finish
    assert np.max(smooth(trace["spark_freq"])) < 30.0


@pytest.mark.xfail(strict=True, reason="finding: the loop ends at 40 % with t_off 5.9 us and "
                   "19 kHz, so the mean gap voltage over the cycle reads 97 V. 45 V under 30 kHz "
                   "needs t_off >= 19.4 us at the end and a spark frequency near Yr1, i.e. a feed "
                   "near 1.0 mm/min (eq. 8, 1.16 mm2/min per kHz at 30 mm); from test 1's start "
                   "(0.3 mm/min, 32 us) the rule table's e1 = P block moves 1/t_off with the feed "
                   "(0.32 per us per mm/min measured), so +0.7 mm/min ends near 3.9 us "
                   "(docs/plants.md)")
def test_finish_mean_gap_voltage_about_45_v(finish):
    _, trace = finish
    assert np.mean(trace["gap_voltage"][-2000:, 0]) == pytest.approx(45.0, abs=10.0)


def test_finish_steady_feed_change_within_0_1(finish):
    # the finish-cut constraint |delta f| <= 0.1 mm/min over the last 30 % of the run
    _, trace = finish
    assert metrics.steady_change(trace["feed"], tail=0.3)[0] <= 0.1


def test_finish_no_wire_rupture(finish):
    _, trace = finish
    assert trace["ruptures"][-1, 0] == 0


def test_fuzzy_beats_voltage_p_baseline(finish, finish_baseline):
    # Steady-state error of the abnormal ratio from Yr2 (what both should deliver) and feed
    # chattering = mean |f(k) - f(k-1)| per sample over the second half (runtime.metrics).
    _, fuzzy = finish
    _, base = finish_baseline
    assert (metrics.steady_state_error(fuzzy["abnormal_ratio"], fuzzy["Yr2"], 0.3)[0]
            < metrics.steady_state_error(base["abnormal_ratio"], base["Yr2"], 0.3)[0])
    assert metrics.chattering(fuzzy["feed"])[0] < 0.1 * metrics.chattering(base["feed"])[0]


def test_baseline_voltage_p_has_a_steady_voltage_error(finish_baseline):
    # a P law needs V - Vref = feed / gain to feed at all: 0.05 mm/min/V gives ~10 V per 0.5
    scenario, trace = finish_baseline
    err = np.mean(trace["gap_voltage"][-2000:, 0]) - 40.0
    feed = np.mean(trace["feed"][-2000:, 0])
    assert err == pytest.approx(feed / 0.05, rel=0.1)


def test_rough_starts_near_40_percent():
    # Fig. 8a: "from the initial level of 40 %". One 40-ms count is noisy (its sd across loops
    # is about 0.015, single counts reach 0.35), so the start is judged over 8 loops: the mean
    # first count, and the mean over the first 2 s (the controller has begun to move it).
    trace = simulate(load("wedm_rough", {"duration": "2"}), batch=8)
    assert np.mean(trace["abnormal_ratio"][0]) == pytest.approx(0.40, abs=0.03)
    assert np.mean(trace["abnormal_ratio"][:WINDOW]) == pytest.approx(0.40, abs=0.06)


def test_rough_reaches_60_percent_and_off_time_near_19_2(rough):
    _, trace = rough
    t, ratio, ref = ratio_view(trace)
    assert abs(ratio[-1] - 0.60) < 0.03
    assert trace["t_off"][-1, 0] == pytest.approx(19.2, rel=0.2)


def test_rough_has_no_oscillation(rough):
    # "without oscillation": the smoothed ratio rises without crossing back by more than 3 %
    _, trace = rough
    _, ratio, _ = ratio_view(trace)
    running_max = np.maximum.accumulate(ratio)
    assert np.max(running_max - ratio) < 0.06


def test_setpoint_change_tracked_both_ways(setpoint):
    _, trace = setpoint
    t, ratio, ref = ratio_view(trace)
    for t0, t1 in ((150, 180), (250, 280), (350, 380)):
        window = (t >= t0) & (t < t1)
        assert np.mean(np.abs(ratio[window] - ref[window])) < 0.03


@pytest.mark.xfail(strict=True, reason="finding: the last 30 s average 52.8 % at 28-30 kHz: the "
                   "plant's 55 % point at test 2's off-times (16-20 us) sits at 30.9-32.6 kHz, "
                   "above Yr1 = 30 kHz (Yan & Liao's reading, mean + 3 sd, puts it at <= 27.5), so "
                   "e1 leaves P and the critical region's rules hold the ratio under its set point")
def test_setpoint_ends_at_its_55_percent(setpoint):
    # "good tracking ability ... without causing ... steady error": the last 30 s within 1 point
    _, trace = setpoint
    t, ratio, _ = ratio_view(trace)
    assert np.mean(ratio[t >= 350]) == pytest.approx(0.55, abs=0.01)


def test_setpoint_summary_is_reported(setpoint):
    scenario, trace = setpoint
    summary = summarize(scenario, trace)
    assert summary["wire ruptures"]["mean"] == 0


def test_c_backend_runs_the_same_closed_loop():
    # the artefact that goes to the machine, in the loop: the generated C (double) against
    # the numpy engine on 20 s of test 1, same plant noise
    pytest.importorskip("fuzzyc.backends.c.load")
    import shutil
    if shutil.which("gcc") is None:
        pytest.skip("no C compiler")
    scenario = load("wedm_finish", {"duration": "20"})
    numpy_trace = simulate(scenario)
    c_trace = simulate(scenario, backend="c")
    assert c_trace["feed"][:, 0] == pytest.approx(numpy_trace["feed"][:, 0], rel=1e-4)
    assert c_trace["t_off"][:, 0] == pytest.approx(numpy_trace["t_off"][:, 0], rel=1e-4)


def test_c_backend_refuses_a_set_point_schedule_it_cannot_follow():
    pytest.importorskip("fuzzyc.backends.c.load")
    from fuzzyc.errors import FuzzycError
    from fuzzyc.runtime.simulate import build, load_controller
    scenario = load("wedm_setpoint")

    class Compiled:   # a controller without a params dict, like the C back end
        def __init__(self, model):
            self.model = model
            self.input_names, self.output_names = ["spark_freq"], ["feed"]

    model = load_controller(scenario, 1).model
    with pytest.raises(FuzzycError, match="compiles `Yr2` in"):
        build(scenario, Compiled(model))


@pytest.mark.xfail(strict=True, reason="finding: the rough loop settles at 1.1 mm/min x 50 mm "
                   "= 56 mm2/min at 19 kHz, the plant's 60 % point at t_off 20 us; about 100 "
                   "needs it near 2.0 mm/min and 30 kHz. A viscous flushing law (debris ~ v H^2 / "
                   "(g^3 p), tried) puts it at 2.16 mm/min, 29.5 kHz, 108 mm2/min, but the loop "
                   "then follows the e1 = P block to t_off 2.7 us and test 2 runs away "
                   "(docs/plants.md)")
def test_rough_machining_speed_about_100_mm2_per_min(rough):
    _, trace = rough
    assert np.mean(trace["removal_rate"][-1000:, 0]) == pytest.approx(100.0, rel=0.2)


def test_a_randomized_batch_runs_in_one_call():
    # 200 test-1 loops with their own plant parameters (10 % spread), 20 s: every loop
    # finite, and the loops differ
    scenario = load("wedm_finish", {"duration": "20"})
    trace = simulate(scenario, batch=200, randomize=True, record=["abnormal_ratio", "feed"])
    assert trace["feed"].shape == (500, 200)
    assert np.all(np.isfinite(trace["abnormal_ratio"]))
    assert np.std(trace["feed"][-1]) > 0
