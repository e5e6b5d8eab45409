"""The fixed-period loop: blocks in order, every period, over a batch of independent loops.

pace="sim" runs simulated time as fast as the blocks allow; pace="wall" sleeps to the wall
clock and counts the periods that finished after their deadline (a real machine interface
would be driven the same way).
"""
from __future__ import annotations

import time as _time
from typing import Any, Iterable

import numpy as np

from .blocks import column
from .progress import Progress
from .trace import Trace


def _initial_bus(blocks: list, batch: int, initial: dict[str, Any] | None) -> dict:
    bus: dict[str, Any] = {}
    for block in blocks:
        block.reset(batch)
        seed = getattr(block, "initial_outputs", None)
        if seed is not None:
            bus.update({k: column(v, batch) for k, v in seed().items()})
    bus.update({k: column(v, batch) for k, v in (initial or {}).items()})
    return bus


def run(blocks: Iterable, period: float, duration: float, batch: int = 1, pace: str = "sim",
        progress: bool | None = False, initial: dict[str, Any] | None = None,
        record: list[str] | None = None, decimate: int = 1) -> Trace:
    """Run `duration` seconds of the loop; returns the recorded trace.

    initial: signal values on the bus before the first period (scalars or (N,)); a block with
    `initial_outputs()` (a controller with a model) seeds its outputs' u(-1) itself.
    record: the signals to keep (default: every array signal on the bus); decimate: keep every
    k-th period. progress: None = only on a tty, True/False = always/never.
    """
    if pace not in ("sim", "wall"):
        raise ValueError(f"pace must be 'sim' or 'wall', got {pace!r}")
    if period <= 0 or duration < 0 or batch < 1 or decimate < 1:
        raise ValueError("need period > 0, duration >= 0, batch >= 1, decimate >= 1")
    blocks = list(blocks)
    steps = int(round(duration / period))
    bus = _initial_bus(blocks, batch, initial)
    recorder = _Recorder(steps // decimate, record)
    bar = Progress(steps, progress)
    misses = 0
    wall_start = _time.perf_counter()
    for k in range(steps):
        bus["t"], bus["dt"] = k * period, period
        for block in blocks:
            bus.update(block.step(bus))
        if pace == "wall":
            misses += _wait_for_deadline(wall_start + (k + 1) * period)
        if (k + 1) % decimate == 0:
            recorder.add((k + 1) * period, bus)
        if k % 64 == 0:
            bar.update(k)
    bar.close()
    return Trace(recorder.times, recorder.signals, period, misses, steps)


class _Recorder:
    """The recorded signals, written row by row into arrays allocated once."""

    def __init__(self, rows: int, names: list[str] | None):
        self.names = names          # None: every array signal on the bus after the first period
        self.times = np.empty(rows)
        self.signals: dict[str, np.ndarray] = {}
        self.rows, self.row = rows, 0

    def add(self, time: float, bus: dict) -> None:
        if self.row == 0:
            self._allocate(bus)
        self.times[self.row] = time
        for name, rows in self.signals.items():
            rows[self.row] = bus[name]
        self.row += 1

    def _allocate(self, bus: dict) -> None:
        if self.names is None:
            self.names = [n for n, v in bus.items() if isinstance(v, np.ndarray)]
        unknown = [n for n in self.names if n not in bus]
        if unknown:
            raise KeyError(f"cannot record {', '.join(unknown)}: no block writes it")
        # each signal's shape as it stands now: (N,) arrays, or a float (recorded as (T,))
        self.signals = {n: np.empty((self.rows,) + np.shape(bus[n])) for n in self.names}


def _wait_for_deadline(deadline: float) -> int:
    """Sleep until the deadline; 1 when the work already overran it."""
    now = _time.perf_counter()
    if now > deadline:
        return 1
    _time.sleep(deadline - now)
    return 0
