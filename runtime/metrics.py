"""Closed-loop figures of merit, each over a (T, N) signal: one value per loop, shape (N,).

Definitions (stated once, used by the summaries, the demo table and the tests):
- settling_time: the first time after which |y - target| stays within `band` to the end
  (NaN if it never settles).
- overshoot: how far y goes past the target on the far side of a set-point step, in y's units
  (0 if it never crosses). A step is a run of samples where the target changes (a jump, or
  the ramp a smoothed jump becomes; changes under STEP_TOL relative are rounding); it lasts
  until the next step. Its direction is sign(target at the end of the change - y just before
  it); the first stretch, from t = 0, takes sign(target[0] - y[0]). So a loop that starts at
  its set point (y[0] = target[0]: sign 0) has nothing to overshoot until the set point steps,
  and then the step counts. The excess is direction * (y - target) at every sample
  (overshoot_excess); overshoot = max(0, its max over the run): the worst of the steps.
  The verifier's `overshoot S below X` is the same excess with S's final value (mean of the
  last 10 % of the run) as the target: one step, direction sign(final - S[0]).
- steady_state_error: mean |y - target| over the last `tail` fraction of the run.
- chattering: the mean absolute change per sample over the last `tail` fraction of the run
  (the feed-chattering figure: sum |u(k) - u(k-1)| / samples).
- steady_change: max - min of u over the last `tail` fraction (the paper's |delta f| on feed).
- event_count: rising edges of a 0/1 event signal.
- moving_average: the trailing mean over k samples (the first k-1 average what exists).
"""
from __future__ import annotations

import numpy as np


STEP_TOL = 1e-9     # relative: a target change smaller than this is rounding, not a step


def _tail(x: np.ndarray, tail: float) -> np.ndarray:
    start = min(int(len(x) * (1.0 - tail)), len(x) - 1)
    return x[start:]


def _target(target, y: np.ndarray) -> np.ndarray:
    return np.broadcast_to(np.asarray(target, dtype=float), y.shape)


def settling_time(time: np.ndarray, y: np.ndarray, target, band: float) -> np.ndarray:
    outside = np.abs(y - _target(target, y)) > band                 # (T, N)
    ever = outside.any(axis=0)
    last = len(time) - 1 - np.argmax(outside[::-1], axis=0)         # last sample outside
    settled = np.where(last + 1 < len(time), time[np.minimum(last + 1, len(time) - 1)], np.nan)
    return np.where(ever, settled, time[0])


def overshoot_excess(y: np.ndarray, target) -> np.ndarray:
    """(T, ...) how far y is past the target of the step in force, toward the far side (> 0:
    overshooting; 0 throughout a stretch where y starts on its target)."""
    y = np.asarray(y, dtype=float)
    tgt = _target(target, y)
    # a step: a run of samples where the target changes (a jump, or the ramp a smoothed jump
    # becomes); changes within rounding (a moving average of a constant) are none
    changing = np.zeros(y.shape, dtype=bool)
    changing[1:] = np.abs(np.diff(tgt, axis=0)) > STEP_TOL * np.maximum(
        1.0, np.maximum(np.abs(tgt[1:]), np.abs(tgt[:-1])))
    starts = changing.copy()
    starts[1:] &= ~changing[:-1]
    starts[0] = True
    rows = np.arange(len(y)).reshape((-1,) + (1,) * (y.ndim - 1))
    # where each run of changes ends: the target the step goes to
    stable = np.where(changing, len(y), rows)
    end = np.minimum.accumulate(stable[::-1], axis=0)[::-1]
    goal = np.take_along_axis(tgt, np.maximum(np.minimum(end, len(y)) - 1, rows), axis=0)
    goal = np.where(changing, goal, tgt)
    before = np.concatenate([y[:1], y[:-1]])            # y just before each sample
    sign_at = np.where(starts, np.sign(goal - before), 0.0)
    # carry each step's direction over its stretch (index of the latest step, per loop)
    latest = np.maximum.accumulate(np.where(starts, rows, 0), axis=0)
    return np.take_along_axis(sign_at, latest, axis=0) * (y - tgt)


def overshoot(y: np.ndarray, target) -> np.ndarray:
    return np.maximum(0.0, np.max(overshoot_excess(y, target), axis=0))


def steady_state_error(y: np.ndarray, target, tail: float = 0.2) -> np.ndarray:
    return np.mean(np.abs(_tail(y - _target(target, y), tail)), axis=0)


def chattering(u: np.ndarray, tail: float = 0.5) -> np.ndarray:
    return np.mean(np.abs(np.diff(_tail(u, tail), axis=0)), axis=0)


def steady_change(u: np.ndarray, tail: float = 0.2) -> np.ndarray:
    last = _tail(u, tail)
    return np.max(last, axis=0) - np.min(last, axis=0)


def event_count(flag: np.ndarray) -> np.ndarray:
    on = np.asarray(flag) > 0.5
    rising = on[1:] & ~on[:-1]
    return rising.sum(axis=0) + on[0]


def moving_average(y: np.ndarray, k: int) -> np.ndarray:
    if k <= 1:
        return y
    c = np.cumsum(np.asarray(y, dtype=float), axis=0)
    out = c.copy()
    out[k:] = c[k:] - c[:-k]
    counts = np.minimum(np.arange(1, len(y) + 1), k).reshape((-1,) + (1,) * (y.ndim - 1))
    return out / counts
