"""Closed-loop figures of merit, each over a (T, N) signal: one value per loop, shape (N,).

Definitions (stated once, used by the summaries, the demo table and the tests):
- settling_time: the first time after which |y - target| stays within `band` to the end
  (NaN if it never settles).
- overshoot: how far y goes past the target on the far side from where it started, in y's
  units (0 if it never crosses): max(sign * (y - target)), sign = sign(target - y[0]).
- steady_state_error: mean |y - target| over the last `tail` fraction of the run.
- chattering: the mean absolute change per sample over the last `tail` fraction of the run
  (the feed-chattering figure: sum |u(k) - u(k-1)| / samples).
- steady_change: max - min of u over the last `tail` fraction (the paper's |delta f| on feed).
- event_count: rising edges of a 0/1 event signal.
- moving_average: the trailing mean over k samples (the first k-1 average what exists).
"""
from __future__ import annotations

import numpy as np


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


def overshoot(y: np.ndarray, target) -> np.ndarray:
    tgt = _target(target, y)
    sign = np.sign(tgt[0] - y[0])
    return np.maximum(0.0, np.max(sign * (y - tgt), axis=0))


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
