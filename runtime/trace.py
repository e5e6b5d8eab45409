"""A recorded run: time (T,) and each signal as a (T, N) array (T samples, N loops)."""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fuzzyc.atomic import atomic_path
from fuzzyc.csvtext import csv_line

# The loops of a batch a picture draws and trace.csv keeps by default: a Monte Carlo batch of
# thousands would make an unreadable plot and a CSV of gigabytes.
SHOWN_LOOPS = 20


@dataclass
class Trace:
    """Signals as they stand at the end of each recorded period; `time[k]` is that instant.

    deadline_misses counts the periods that ended after their wall-clock deadline (pace="wall").
    """
    time: np.ndarray
    signals: dict[str, np.ndarray]
    period: float
    deadline_misses: int = 0
    steps: int = 0
    meta: dict = field(default_factory=dict)

    @property
    def batch(self) -> int:
        first = next(iter(self.signals.values()), None)
        return 0 if first is None else first.shape[1]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.signals[name]

    def __contains__(self, name: str) -> bool:
        return name in self.signals

    def select(self, loop: int) -> "Trace":
        """One loop of the batch, as a trace of batch 1."""
        return Trace(self.time, {k: v[:, loop:loop + 1] for k, v in self.signals.items()},
                     self.period, self.deadline_misses, self.steps, dict(self.meta))

    def to_csv(self, path: str | Path, loops: int | None = None) -> Path:
        """One row per sample; columns `t` then `name` (batch 1) or `name[i]` per loop.

        loops: write only the first `loops` loops of the batch (a big batch makes a huge file).
        Written atomically.
        """
        n = self.batch if loops is None else min(loops, self.batch)
        names, columns = ["t"], [self.time]
        for key, values in self.signals.items():
            for i in range(n):
                names.append(key if self.batch == 1 else f"{key}[{i}]")
                columns.append(values[:, i])
        table = np.column_stack(columns)
        with atomic_path(path) as tmp:
            np.savetxt(tmp, table, delimiter=",", header=csv_line(names)[:-1], comments="",
                       fmt="%.9g")
        return Path(path)

    @staticmethod
    def from_csv(path: str | Path) -> "Trace":
        """Read back a batch-1 CSV written by `to_csv` (for tools and tests)."""
        with open(path, encoding="utf-8", newline="") as handle:
            # one reader for header and rows: a name may hold a quoted line break
            names, *rows = csv.reader(handle)
        table = np.array(rows, dtype=float).reshape(len(rows), len(names))
        time = table[:, 0]
        period = float(time[1] - time[0]) if len(time) > 1 else 0.0
        return Trace(time, {n: table[:, i:i + 1] for i, n in enumerate(names) if i > 0}, period)
