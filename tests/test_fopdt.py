"""The first-order-plus-dead-time plant: step responses computed by hand, the shipped scenario."""
import numpy as np
import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.plants import fopdt, scenario
from fuzzyc.runtime import PlantBlock, ScheduleBlock, run
from fuzzyc.runtime.simulate import simulate, summarize


def step_response(params, period=0.1, duration=3.0, batch=1):
    """u = 1 from t = 0 (the input before it is u0)."""
    blocks = [ScheduleBlock("u", [(0, 1.0)]), PlantBlock(fopdt, params, ["u"], ["y"])]
    return run(blocks, period, duration, batch)


def test_step_response_by_hand():
    # y(t) = K (1 - exp(-(t - L) / T)) for t >= L, 0 before; K = 2, T = 1 s, L = 0.5 s:
    # t = 0.5: 0; t = 1.5: 2 (1 - e^-1) = 1.264241; t = 3.0: 2 (1 - e^-2.5) = 1.835830
    trace = step_response(fopdt.FopdtParams(gain=2.0, time_constant=1.0, dead_time=0.5))
    y = dict(zip(np.round(trace.time, 6), trace["y"][:, 0]))
    assert y[0.4] == 0.0 and y[0.5] == 0.0
    assert y[1.5] == pytest.approx(2 * (1 - np.exp(-1)), abs=1e-12)
    assert y[3.0] == pytest.approx(2 * (1 - np.exp(-2.5)), abs=1e-12)


def test_dead_time_between_samples_is_exact():
    # L = 0.25 s with 0.1-s periods (2.5 periods): K = 1, T = 0.5 s; at t = 0.3 the input has
    # acted for 0.05 s: 1 - e^(-0.05/0.5) = 0.0951626; at t = 1.0: 1 - e^(-0.75/0.5) = 0.7768698
    trace = step_response(fopdt.FopdtParams(gain=1.0, time_constant=0.5, dead_time=0.25))
    y = dict(zip(np.round(trace.time, 6), trace["y"][:, 0]))
    assert y[0.2] == 0.0
    assert y[0.3] == pytest.approx(1 - np.exp(-0.1), abs=1e-12)
    assert y[1.0] == pytest.approx(1 - np.exp(-1.5), abs=1e-12)


def test_a_batch_of_dead_times_and_a_start_from_rest_at_u0():
    # three loops: L = 0, 0.3, 1 s (0.3 / 0.1 is 2.9999999999999996: three whole periods);
    # y0 = 1, u0 = 1 is rest for K = 1; u = 3 from t = 0, T = 1 s: y(t) = 3 - 2 exp(-(t - L))
    params = fopdt.FopdtParams(gain=1.0, time_constant=1.0, dead_time=np.array([0.0, 0.3, 1.0]),
                               y0=1.0, u0=1.0)
    blocks = [ScheduleBlock("u", [(0, 3.0)]), PlantBlock(fopdt, params, ["u"], ["y"])]
    trace = run(blocks, 0.1, 2.0, batch=3)
    at = {round(t, 6): row for t, row in zip(trace.time, trace["y"])}
    np.testing.assert_allclose(at[0.3], [3 - 2 * np.exp(-0.3), 1.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(at[2.0], 3 - 2 * np.exp(-(2.0 - np.array([0, 0.3, 1.0]))),
                               atol=1e-12)


def test_disturbance_adds_at_the_input():
    # u = 1, disturbance = -0.5, no dead time, K = 4, T = 2 s: y(2 s) = 4 * 0.5 (1 - e^-1)
    params = fopdt.FopdtParams(gain=4.0, time_constant=2.0)
    blocks = [ScheduleBlock("u", [(0, 1.0)]), ScheduleBlock("disturbance", [(0, -0.5)]),
              PlantBlock(fopdt, params, ["u", "disturbance"], ["y"])]
    trace = run(blocks, 0.1, 2.0)
    assert trace["y"][-1, 0] == pytest.approx(2 * (1 - np.exp(-1)), abs=1e-12)


def test_bad_params_are_located_errors(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("plant:\n  model: fopdt\n  params: {time_constant: 0}\n")
    with pytest.raises(FuzzycError) as info:
        scenario.load(path).plant_params()
    assert "bad.yaml:3" in info.value.diagnostics[0].format()
    assert "time_constant must be > 0" in str(info.value)


def test_shipped_scenario_fuzzy_pi_and_baseline_settle_and_the_pi_overshoots():
    # the note of fopdt_step.yaml: both settle, the PI (kick on the set-point step) first; y
    # and r start at 0 and r steps to 1 at 1 s: the overshoot is measured past the step (the
    # fuzzy PI never crosses 1, the PI peaks at 1.058 at 5.7 s)
    sc = scenario.load("fopdt_step")
    fuzzy_trace, pi_trace = simulate(sc), simulate(sc, baseline=True)
    fuzzy, pi = summarize(sc, fuzzy_trace), summarize(sc, pi_trace)
    settle = "settling time (5 %)"
    assert 15 < fuzzy[settle]["mean"] < 21 and 4 < pi[settle]["mean"] < 8
    assert fuzzy["overshoot"]["mean"] == 0 and fuzzy_trace["y"].max() < 1
    peak = pi_trace["y"][:, 0].max()
    assert pi["overshoot"]["mean"] == pytest.approx(peak - 1) and round(peak, 3) == 1.058
    assert pi_trace.time[pi_trace["y"][:, 0].argmax()] == pytest.approx(5.7)
    note = " ".join(" ".join(sc.notes).split())
    assert "the PI overshoots by 0.058 (y peaks at 1.058 at 5.7 s)" in note
    assert fuzzy["error after 30 s"]["mean"] < 0.01 and pi["error after 30 s"]["mean"] < 0.01
