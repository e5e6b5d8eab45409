"""Timing helpers shared by the benchmarks: median of repeats, peak memory, markdown output."""
from __future__ import annotations

import copy
import resource
import statistics
import time
import tracemalloc
from pathlib import Path
from typing import Callable

from fuzzyc.atomic import write_text


def median_seconds(fn: Callable[[], object], repeats: int = 5,
                   clock: Callable[[], float] = time.perf_counter) -> float:
    """The median time of `repeats` calls (one untimed warm-up call first): wall time, or the
    process's CPU time with clock=time.process_time."""
    fn()
    times = []
    for _ in range(repeats):
        start = clock()
        fn()
        times.append(clock() - start)
    return statistics.median(times)


def peak_bytes(fn: Callable[[], object]) -> int:
    """Peak memory numpy and Python allocate during one call (tracemalloc traces numpy too)."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def markdown_table(header: list[str], rows: list[list[object]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def write_result(path: str | Path, text: str) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    write_text(path, text)


def triangle_outputs(rb):
    """The rule base with uniform triangle output terms (peaks kept) and exact centroid."""
    import numpy as np
    from fuzzyc.semantics.model import Defuzzifier, TermKind
    rb = copy.deepcopy(rb)
    for v in rb.outputs:
        peaks = v.peaks()
        h = np.diff(peaks).min()
        v.kinds = np.full(len(peaks), TermKind.TRAPEZOID)
        v.params = np.stack([peaks - h, peaks, peaks, peaks + h], axis=1)
    rb.inference.defuzzifier = Defuzzifier.CENTROID
    return rb


def faults_per_call(fn: Callable[[], object], calls: int = 3) -> float:
    """Minor page faults per call after a warm-up call (fresh pages the call touched)."""
    fn()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(calls):
        fn()
    return (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / calls
