"""Sensor faults as a loop block: a measured signal reads NaN, or sticks at its last healthy
value, over a window of time that each loop of the batch has for itself.

Placed right after the plant, the block replaces the measurement for every block downstream
(observers, controller), as a failing sensor or counter card would. The plant's true value stays
on the bus as `NAME@plant`, so a check or a plot can tell the process from what the sensor said.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class SensorFault:
    """signal: the measured bus signal; start (N,) s (inf: no fault in that loop); length (N,) s;
    stuck (N,) bool: hold the last healthy value (a fault from the first sample holds the first
    reading) instead of reading NaN."""
    signal: str
    start: np.ndarray
    length: np.ndarray
    stuck: np.ndarray
    name: str = "sensor fault"

    def __post_init__(self) -> None:
        self.true_name = f"{self.signal}@plant"
        self.input_names = [self.signal, "t"]
        self.output_names = [self.signal, self.true_name]

    def reset(self, batch: int) -> None:
        shape = (batch,)
        self._start = np.broadcast_to(np.asarray(self.start, float), shape)
        self._end = self._start + np.broadcast_to(np.asarray(self.length, float), shape)
        self._stuck = np.broadcast_to(np.asarray(self.stuck, bool), shape)
        self._last: np.ndarray | None = None      # the last healthy reading per loop

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        t = signals["t"]
        true = np.broadcast_to(np.asarray(signals[self.signal], float), self._start.shape)
        if self._last is None:
            self._last = true.copy()
        active = (t >= self._start) & (t < self._end)
        sensed = np.where(active, np.where(self._stuck, self._last, np.nan), true)
        self._last = np.where(active, self._last, true)
        return {self.signal: sensed, self.true_name: true}
