"""Every figure of merit of runtime.metrics (and the simulate summary's METRICS table) on short
arrays, with the arithmetic in the comments. Shapes are (T, N): one column per loop."""
import numpy as np
import pytest

from fuzzyc.runtime import metrics as M
from fuzzyc.runtime.simulate import METRICS


def col(*values):
    return np.array(values, dtype=float)[:, None]


# ---- overshoot ------------------------------------------------------------------------------

def test_overshoot_upward_step_from_below():
    # y 0 -> 1.3 -> 1.0, target 1 throughout: direction sign(1 - 0) = +1, max(y - 1) = 0.3
    assert M.overshoot(col(0, 0.6, 1.3, 1.1, 1.0), 1.0) == pytest.approx([0.3])


def test_overshoot_when_the_loop_starts_at_its_set_point():
    # y and r both 0 until the step 0 -> 1 at sample 2 (the fopdt_step case). Stretch 1: sign(0
    # - 0) = 0, nothing to overshoot. Stretch 2 (r = 1): sign(1 - y[1] = 1 - 0) = +1, excess
    # y - 1 = -1, -0.5, 0.058, 0, -0.01: overshoot 0.058 (the old sign(r[0] - y[0]) gave 0)
    y = col(0, 0, 0, 0.5, 1.058, 1.0, 0.99)
    r = col(0, 0, 1, 1, 1, 1, 1)
    assert M.overshoot(y, r) == pytest.approx([0.058])
    assert M.overshoot_excess(y, r)[:2, 0] == pytest.approx([0, 0])


def test_overshoot_downward_step():
    # y starts at 5, target steps 5 -> 2 at sample 1: direction sign(2 - 5) = -1; y goes to
    # 1.6, 2.1, 2: excess -(y - 2) = -3, -1, 0.4, -0.1, 0 -> overshoot 0.4 (below the target)
    y = col(5, 3, 1.6, 2.1, 2.0)
    r = col(5, 2, 2, 2, 2)
    assert M.overshoot(y, r) == pytest.approx([0.4])


def test_overshoot_never_crossing_is_zero():
    # rises 0 -> 0.9 toward 1, never past it: every excess y - 1 < 0 -> 0
    assert M.overshoot(col(0, 0.5, 0.8, 0.9), 1.0) == pytest.approx([0.0])


def test_overshoot_per_step_takes_the_worst_step():
    # r: 0 (start, y at it), 1 from sample 1, 0 from sample 4.
    # step up: sign(1 - y[0] = 1) = +1, y - 1 over samples 1-3: -0.5, 0.2, 0 -> 0.2
    # step down: sign(0 - y[3] = -1) = -1, -(y - 0) over samples 4-6: -0.4, 0.1, 0 -> 0.1
    y = col(0, 0.5, 1.2, 1.0, 0.4, -0.1, 0.0)
    r = col(0, 1, 1, 1, 0, 0, 0)
    assert M.overshoot_excess(y, r)[:, 0] == pytest.approx([0, -0.5, 0.2, 0, -0.4, 0.1, 0])
    assert M.overshoot(y, r) == pytest.approx([0.2])


def test_overshoot_a_ramped_step_is_one_step():
    # r ramps 0 -> 0.5 -> 1 over samples 2-3 (a smoothed jump): one step, its direction
    # sign(r at the end of the ramp, 1, - y before it, y[1] = 0) = +1 over samples 2-5:
    # y - r = -0.3, -0.2, 0.1, 0 -> 0.1. (Per sample, sign(r[3] - y[2]) would also be +1 here,
    # but a y ahead of the ramp would flip it.)
    y = col(0, 0, 0.2, 0.8, 1.1, 1.0)
    r = col(0, 0, 0.5, 1, 1, 1)
    assert M.overshoot(y, r) == pytest.approx([0.1])
    # y ahead of the ramp (0.6 > 0.5 at sample 2): still upward, 0.6 - 0.5 = 0.1 counts
    assert M.overshoot(col(0, 0, 0.6, 0.9, 1.0, 1.0), r) == pytest.approx([0.1])


def test_overshoot_rounding_in_the_target_is_no_step():
    # a moving average of a constant 0.4 wobbles by ~1e-16: no step, the direction stays
    # sign(0.4 - 0.25) = +1 and the overshoot is 0.41 - 0.4 = 0.01 (not the 0.4 - 0.37 = 0.03
    # that a step at the wobble of sample 3, y[2] = 0.41 above it, would measure downward)
    r = col(0.4, 0.4 + 3e-16, 0.4 - 3e-16, 0.4 + 3e-16, 0.4 - 3e-16, 0.4)
    assert (np.diff(r[:, 0]) != 0).all()
    y = col(0.25, 0.38, 0.41, 0.37, 0.40, 0.40)
    assert M.overshoot(y, r) == pytest.approx([0.01])


def test_overshoot_one_value_per_loop():
    # loop 1: 0 -> 1.5 past 1: 0.5; loop 2: starts at 2 above 1, falls to 0.7: 1 - 0.7 = 0.3
    y = np.array([[0, 2], [1.5, 0.7], [1, 1]], dtype=float)
    assert M.overshoot(y, 1.0) == pytest.approx([0.5, 0.3])


def test_verifier_overshoot_uses_the_same_excess_past_the_final_value():
    """`overshoot y below X` (temporal.py): the final value (mean of the last 10 %: here the
    last sample of 10, 1.0) stands in for the target. Rising 0 -> 1.4 -> 1: 0.4; falling
    3 -> 0.8 -> 1: 0.2 below the final value (the start above it is not an overshoot)."""
    from fuzzyc.semantics.model import Property
    from fuzzyc.verifier.temporal import evaluate
    t = np.arange(10.0)
    up = [0, 0.5, 1.4, 1.2, 1, 1, 1, 1, 1, 1]
    down = [3, 2, 0.8, 0.9, 1, 1, 1, 1, 1, 1]
    y = np.array([up, down], dtype=float).T
    for limit, violated in ((0.3, [True, False]), (0.5, [False, False]), (0.1, [True, True])):
        check = Property("overshoot", {"signal": "y", "limit": limit}, None, "")
        bad, when = evaluate(check, t, {"y": y}, {})
        assert bad.tolist() == violated
    # at limit 0.1: the rise passes at t = 2 (0.4), the fall at t = 2 (1 - 0.8 = 0.2)
    assert when.tolist() == [2.0, 2.0]


# ---- the other metrics ----------------------------------------------------------------------

def test_settling_time():
    # band 0.1 around 1: |y - 1| = 1, 0.5, 0.2, 0.05, 0.08, 0: last sample outside is t = 2,
    # settled from the next sample, t = 3. Loop 2 leaves the band at the end: NaN.
    # Loop 3 is inside from the start: time[0] = 0.
    t = np.arange(6.0)
    y = np.array([[0, 1, 1], [0.5, 1, 1], [0.8, 1, 1], [1.05, 1, 1], [0.92, 1, 1],
                  [1.0, 1.5, 1]])
    got = M.settling_time(t, y, 1.0, 0.1)
    assert got[0] == 3.0 and np.isnan(got[1]) and got[2] == 0.0


def test_steady_state_error():
    # 10 samples, tail 0.2: the last 2; |y - 1| = 0.1 and 0.3 -> mean 0.2
    y = col(0, 0, 0, 0, 0, 0, 0, 0, 1.1, 0.7)
    assert M.steady_state_error(y, 1.0, tail=0.2) == pytest.approx([0.2])


def test_chattering():
    # 8 samples, tail 0.5: the last 4 (2, 4, 3, 3): |diff| = 2, 1, 0 -> mean 1
    u = col(9, -9, 9, -9, 2, 4, 3, 3)
    assert M.chattering(u, tail=0.5) == pytest.approx([1.0])


def test_steady_change():
    # 10 samples, tail 0.2: the last 2 (5, 3.5): max - min = 1.5 (the 100 before is ignored)
    u = col(100, 0, 0, 0, 0, 0, 0, 0, 5, 3.5)
    assert M.steady_change(u, tail=0.2) == pytest.approx([1.5])


def test_event_count():
    # rising edges of > 0.5: loop 1 0,1,1,0,1,0 -> edges at 1 and 4: 2; loop 2 starts on
    # (counts 1), off, on again: 2; loop 3 never on: 0
    flag = np.array([[0, 1, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [1, 0, 0], [0, 0, 0.4]])
    assert M.event_count(flag).tolist() == [2, 2, 0]


def test_moving_average():
    # k = 3: 1, (1+2)/2, (1+2+3)/3, (2+3+7)/3, (3+7+5)/3 = 1, 1.5, 2, 4, 5
    y = col(1, 2, 3, 7, 5)
    assert M.moving_average(y, 3)[:, 0] == pytest.approx([1, 1.5, 2, 4, 5])
    assert M.moving_average(y, 1) is y          # k <= 1: the signal itself


def test_summary_metrics_table():
    # the lambdas of the simulate summary not in metrics.py, on t = 0..4, y = 2, 4, 4, 6, 9
    t = np.arange(5.0)
    y = col(2, 4, 4, 6, 9)
    spec = {}
    # |y - 5| = 3, 1, 1, 1, 4 -> 10 / 5
    assert METRICS["mean_abs_error"](t, y, 5.0, spec) == pytest.approx([2.0])
    # (9 - 2) / (4 - 0)
    assert METRICS["rate"](t, y, None, spec) == pytest.approx([1.75])
    # the mean of the last max(1, 5 // 20) = 1 sample
    assert METRICS["final"](t, y, None, spec) == pytest.approx([9.0])
    # tail 0.4: from sample int(5 * 0.6) = 3: (6 + 9) / 2
    assert METRICS["mean"](t, y, None, {"tail": 0.4}) == pytest.approx([7.5])
    assert METRICS["max"](t, y, None, spec) == pytest.approx([9.0])
    assert METRICS["min"](t, y, None, spec) == pytest.approx([2.0])
    # mean 5, squares of deviations 9 + 1 + 1 + 1 + 16 = 28, / 5 = 5.6
    assert METRICS["std"](t, y, None, spec) == pytest.approx([np.sqrt(5.6)])
    done = np.array([[0, 0], [0, 0], [1, 0], [1, 0], [1, 0]], dtype=float)
    got = METRICS["time_until"](t, done, None, spec)
    assert got[0] == 2.0 and np.isnan(got[1])
    # the overshoot row is metrics.overshoot: 9 past a target of 8 reached from below
    assert METRICS["overshoot"](t, y, 8.0, spec) == pytest.approx([1.0])
