"""Work buffers the engine reuses from call to call instead of allocating temporaries per chunk.

Fresh arrays per chunk cost page faults: a temporary above glibc's mmap threshold is mapped and
unmapped every time (and with a low MALLOC_TRIM_THRESHOLD_, as Dask sets, smaller ones too), so
a call paid about 12,000 minor faults at batch 1e5.  A `Workspace` holds one flat buffer per name
sized for `capacity` samples; a request for n <= capacity samples gets the first elements of it
reshaped, which is contiguous, so every kernel sees the same layout as with a fresh array and
the results are the same bits.

A `WorkspacePool` hands workspaces out per call (one caller at a time holds a workspace, so
concurrent calls never share buffers) and takes them back afterwards; it keeps a few capacities
(the most recent), so alternating batch sizes reuse what each size built.  `builds` counts the
workspaces created (the tests read it).
"""
from __future__ import annotations

import math
import threading
from collections import OrderedDict
from contextlib import contextmanager
from typing import Iterator

import numpy as np

KEPT_CAPACITIES = 4      # batch sizes whose workspaces stay (alternating sizes reuse theirs)
KEPT_PER_CAPACITY = 4    # free workspaces kept per size (one per concurrent caller)
MAX_VIEWS = 256          # views memoised per workspace (a few dozen per batch size)


class Workspace:
    """Named buffers for batches of up to `capacity` samples."""

    def __init__(self, capacity: int):
        self.capacity = capacity
        self._flat: dict[str, np.ndarray] = {}
        self._views: dict[tuple, np.ndarray] = {}     # (name, shape, dtype) -> its view
        # what a buffer filled with per-size values (clip bounds, ...) was filled for
        self.tables: dict[str, int] = {}

    def array(self, name: str, shape: tuple[int, ...], dtype=float) -> np.ndarray:
        """A C-contiguous (shape) array of dtype, the same memory on every call (contents
        undefined); grows once if a larger shape is asked for under the same name."""
        view = self._views.get((name, shape, dtype))
        if view is not None:
            return view
        size = math.prod(shape)
        flat = self._flat.get(name)
        if flat is None or flat.dtype != dtype or flat.size < size:
            flat = self._flat[name] = np.empty(size, dtype=dtype)
            self.tables.clear()         # whatever was filled may be in the old memory
            self._views = {k: v for k, v in self._views.items() if k[0] != name}
        if len(self._views) >= MAX_VIEWS:    # many batch sizes: start the memo afresh
            self._views.clear()
        view = self._views[name, shape, dtype] = flat[:size].reshape(shape)
        return view


class WorkspacePool:
    """Workspaces by capacity, checked out by one call at a time."""

    def __init__(self):
        self._free: OrderedDict[int, list[Workspace]] = OrderedDict()
        self._lock = threading.Lock()
        self.builds = 0

    @contextmanager
    def checkout(self, capacity: int) -> Iterator[Workspace]:
        with self._lock:
            free = self._free.get(capacity)
            work = free.pop() if free else None
            if work is None:
                self.builds += 1
        if work is None:
            work = Workspace(capacity)
        try:
            yield work
        finally:
            self._give_back(work)

    def _give_back(self, work: Workspace) -> None:
        with self._lock:
            free = self._free.setdefault(work.capacity, [])
            if len(free) < KEPT_PER_CAPACITY:
                free.append(work)
            self._free.move_to_end(work.capacity)
            while len(self._free) > KEPT_CAPACITIES:
                self._free.popitem(last=False)
