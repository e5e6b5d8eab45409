"""The loop runner, blocks, traces and metrics on systems whose answers are known by hand."""
import types

import numpy as np
import pytest

from fuzzyc.runtime import ControllerBlock, FunctionBlock, PlantBlock, ScheduleBlock, Trace, run
from fuzzyc.runtime import metrics


@pytest.fixture
def first_order():
    """x(k+1) = a x(k) + (1 - a) u(k), a = exp(-dt/tau): an exact discretisation."""
    def initial_state(params, batch, rng):
        return {"x": np.zeros(batch)}

    def step(params, state, inputs, t, dt, rng):
        a = np.exp(-dt / params)
        x = a * state["x"] + (1 - a) * inputs["u"]
        return {"x": x}, {"y": x}

    return types.SimpleNamespace(initial_state=initial_state, step=step)


class Gain:
    """A minimal controller: u = K (r - y)."""
    input_names = ["y"]
    output_names = ["u"]

    def __init__(self, k, ref):
        self.k, self.ref = k, ref
        self.params = {"ref": ref}

    def reset(self, batch):
        self.batch = batch

    def initial_outputs(self):
        return {"u": 0.0}

    def step(self, inputs):
        return {"u": self.k * (self.params["ref"] - inputs["y"])}


def test_open_loop_step_response_is_exact(first_order):
    # u = 1 from t = 0: y(k) = 1 - exp(-k dt / tau); tau = 0.5, dt = 0.1, after 5 steps
    # y = 1 - exp(-1) = 0.632120559
    blocks = [ScheduleBlock("u", [(0, 1.0)]), PlantBlock(first_order, 0.5, ["u"], ["y"])]
    trace = run(blocks, period=0.1, duration=0.5, batch=3)
    assert trace["y"].shape == (5, 3)
    assert trace.time[-1] == pytest.approx(0.5)
    assert trace["y"][-1] == pytest.approx(np.full(3, 1 - np.exp(-1)))


def test_closed_loop_converges_to_the_static_gain(first_order):
    # u = K (1 - y) with plant DC gain 1: y* = K / (1 + K) = 4/5 for K = 4
    ctl = Gain(4.0, 1.0)
    blocks = [PlantBlock(first_order, 0.2, ["u"], ["y"]), ControllerBlock(ctl)]
    trace = run(blocks, period=0.01, duration=5.0, batch=2)
    assert trace["y"][-1] == pytest.approx([0.8, 0.8], abs=1e-6)
    # the plant's first period sees u(-1) = 0, so y stays 0 after it
    assert trace["y"][0] == pytest.approx([0.0, 0.0])


def test_param_inputs_follow_a_schedule(first_order):
    # the set point steps 1 -> 2 at t = 2.5: y* = 0.8 * 2 = 1.6 at the end
    ctl = Gain(4.0, 1.0)
    blocks = [ScheduleBlock("ref", [(0, 1.0), (2.5, 2.0)]),
              PlantBlock(first_order, 0.2, ["u"], ["y"]), ControllerBlock(ctl, ["ref"])]
    trace = run(blocks, period=0.01, duration=5.0)
    k = np.searchsorted(trace.time, 2.5)
    assert trace["y"][k - 1, 0] == pytest.approx(0.8, abs=1e-4)
    assert trace["y"][-1, 0] == pytest.approx(1.6, abs=1e-4)


def test_missing_signal_is_reported_by_name():
    block = FunctionBlock(lambda z: {"w": z}, ["z"], ["w"], name="doubler")
    with pytest.raises(KeyError, match="doubler: no signal named z"):
        run([block], period=0.1, duration=0.2)


def test_wall_pacing_takes_wall_time_and_counts_misses():
    import time
    slow = FunctionBlock(lambda: (time.sleep(0.03), {})[1], [], [])
    start = time.perf_counter()
    trace = run([ScheduleBlock("a", [(0, 1)])], period=0.02, duration=0.1, pace="wall")
    assert time.perf_counter() - start >= 0.09
    assert trace.deadline_misses == 0
    assert run([slow], period=0.01, duration=0.05, pace="wall").deadline_misses == 5


def test_csv_round_trip(tmp_path, first_order):
    blocks = [ScheduleBlock("u", [(0, 1.0)]), PlantBlock(first_order, 0.5, ["u"], ["y"])]
    trace = run(blocks, period=0.1, duration=0.3)
    back = Trace.from_csv(trace.to_csv(tmp_path / "t.csv"))
    assert back.time == pytest.approx(trace.time)
    assert back["y"][:, 0] == pytest.approx(trace["y"][:, 0], rel=1e-8)
    assert not list(tmp_path.glob(".*"))     # no temporary file left behind


def test_csv_round_trip_of_a_name_with_a_line_break(tmp_path):
    # the header quotes "a\nb" over two lines; the rows are read after it, not from line 2
    trace = Trace(np.array([0.0, 0.5]), {"a\nb": np.array([[1.0], [2.0]]),
                                          "c,d": np.array([[3.0], [4.0]])}, 0.5)
    back = Trace.from_csv(trace.to_csv(tmp_path / "t.csv"))
    assert back.time.tolist() == [0.0, 0.5]
    assert back["a\nb"][:, 0].tolist() == [1.0, 2.0] and back["c,d"][:, 0].tolist() == [3.0, 4.0]


def test_metrics_on_a_hand_made_signal():
    t = np.arange(6.0)
    # two loops: one rises 0 -> 1.2 -> 1.0, one stays low
    y = np.array([[0, 0], [0.5, 0.1], [1.2, 0.2], [1.05, 0.2], [1.0, 0.2], [1.0, 0.2]])
    assert metrics.overshoot(y, 1.0) == pytest.approx([0.2, 0.0])
    # within 0.1 of 1.0 from sample 3 (t = 3) on; the second never gets there
    settle = metrics.settling_time(t, y, 1.0, 0.1)
    assert settle[0] == 3.0 and np.isnan(settle[1])
    # last 2 of 6 samples (tail 1/3): |y - 1| = 0, 0 and 0.8, 0.8
    assert metrics.steady_state_error(y, 1.0, tail=1 / 3) == pytest.approx([0.0, 0.8])
    # mean |diff| over the last half (samples 3..5): (0.05 + 0) / 2 and 0
    assert metrics.chattering(y, tail=0.5) == pytest.approx([0.025, 0.0])
    flags = np.array([[0], [1], [1], [0], [1], [0]])
    assert metrics.event_count(flags) == [2]


def test_moving_average_is_trailing_and_starts_with_what_exists():
    y = np.array([[2.0], [4.0], [6.0], [8.0]])
    # k = 2: 2/1, (2+4)/2, (4+6)/2, (6+8)/2
    assert metrics.moving_average(y, 2)[:, 0] == pytest.approx([2.0, 3.0, 5.0, 7.0])


def test_controller_internals_are_exposed_by_name(first_order):
    class WithSignals(Gain):
        def step(self, inputs):
            out = super().step(inputs)
            self.signals = {"error": self.params["ref"] - inputs["y"]}
            return out

    blocks = [PlantBlock(first_order, 0.2, ["u"], ["y"]),
              ControllerBlock(WithSignals(4.0, 1.0), expose=["error"])]
    trace = run(blocks, period=0.01, duration=5.0)
    # at the end y = 0.8, so the error is 1 - 0.8
    assert trace["error"][-1, 0] == pytest.approx(0.2, abs=1e-6)
    with pytest.raises(KeyError, match="no internal signal nosuch"):
        run([PlantBlock(first_order, 0.2, ["u"], ["y"]),
             ControllerBlock(WithSignals(4.0, 1.0), expose=["nosuch"])], 0.01, 0.02)


def test_progress_bar_when_asked_and_silent_off_a_tty():
    import io
    from fuzzyc.runtime.progress import Progress
    shown = io.StringIO()
    bar = Progress(100, enabled=True, stream=shown)
    bar.update(50)
    bar.close()
    assert "50.0%" in shown.getvalue() and "100.0%" in shown.getvalue()
    quiet = io.StringIO()          # a StringIO is not a tty: no bar unless asked
    bar = Progress(100, stream=quiet)
    bar.update(50)
    bar.close()
    assert quiet.getvalue() == ""


def test_metrics_where_rate_std_and_scale_by_hand():
    """Two loops over t = 0, 1, 2, 3 s.
    y = [[0, 0], [310, 0], [290, 0], [320, 0]], cutting flag = [[0, 0], [1, 0], [1, 0], [1, 0]]:
    mean |y - 300| where cutting: loop 0 (10 + 10 + 20) / 3 = 13.333..., loop 1 never cuts: NaN.
    removal r = [[0, 0], [1, 2], [2, 4], [3, 6]] mm: rate (3 - 0) / 3 = 1 and 2 mm/s, x60 -> 60,
    120 mm/min.  std of y: loop 0, mean 920 / 4 = 230, mean(x^2) = (96100 + 84100 + 102400) / 4
    = 70650, sqrt(70650 - 230^2) = sqrt(17750) = 133.23; loop 1: 0."""
    from types import SimpleNamespace

    from fuzzyc.runtime.simulate import summarize
    from fuzzyc.runtime.trace import Trace

    y = np.array([[0, 0], [310, 0], [290, 0], [320, 0]], float)
    flag = np.array([[0, 0], [1, 0], [1, 0], [1, 0]], float)
    removal = np.array([[0, 0], [1, 2], [2, 4], [3, 6]], float)
    trace = Trace(np.arange(4.0), {"y": y, "cutting": flag, "removal": removal}, period=1.0)
    sc = SimpleNamespace(metrics=[
        {"name": "mean_abs_error", "signal": "y", "target": 300.0, "where": "cutting",
         "label": "err"},
        {"name": "rate", "signal": "removal", "scale": 60.0, "label": "rate"},
        {"name": "std", "signal": "y", "label": "std"}], error=None)
    out = summarize(sc, trace)
    assert out["err"]["mean"] == pytest.approx(40 / 3)        # loop 1 (NaN) is left out
    assert out["rate"]["min"] == pytest.approx(60.0) and out["rate"]["max"] == pytest.approx(120.0)
    assert out["std"]["max"] == pytest.approx(17750 ** 0.5) and out["std"]["min"] == 0.0
