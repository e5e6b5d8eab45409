"""Engine speed on the 75-rule WEDM rule base (rulebases/wedm_three_region.fz).

Evaluations per second at several batch sizes, for center of area (the paper's eq. 2) and for
the exact centroid (outputs switched to uniform triangles with the same peaks), against the
plain dense numpy baseline (benchmarks/dense_numpy_wedm.py) and, if installed, pyfuzzylite 8
(benchmarks/fuzzylite_wedm.py says exactly what is compared).
Median of repeated runs in CPU time (time.process_time: other processes on a shared machine
count less than in wall time); minor page faults per call (resource.getrusage) and peak memory
by tracemalloc.  Writes benchmarks/results/engine.md.

    python3 benchmarks/bench_engine.py [--quick]
"""
from __future__ import annotations

import copy
import os
import pathlib
import platform
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one

from common import (faults_per_call, markdown_table, median_seconds, peak_bytes,  # noqa: E402
                    triangle_outputs, write_result)
import dense_numpy_wedm  # noqa: E402
from fuzzyc.engine.inference import evaluate  # noqa: E402
from fuzzyc.semantics.model import Defuzzifier  # noqa: E402
from fuzzyc.language.parser import load  # noqa: E402


def rate(fn, n, repeats):
    return n / median_seconds(fn, repeats)


def interleaved_seconds(fns, repeats):
    """Per repeat, one timed call of every fn in turn (after one warm-up call each), so a
    change in the machine's load hits the baseline and the engine alike; CPU seconds.
    (repeats, len(fns))"""
    for fn in fns:
        fn()
    times = np.empty((repeats, len(fns)))
    for r in range(repeats):
        for k, fn in enumerate(fns):
            start = time.process_time()
            fn()
            times[r, k] = time.process_time() - start
    return times


def main(quick: bool = False) -> str:
    rb = load(ROOT / "rulebases" / "wedm_three_region.fz").rulebase
    cases = [rb, triangle_outputs(rb)]
    sizes = [1, 1000, 100_000] if quick else [1, 1000, 100_000, 1_000_000]
    rng = np.random.default_rng(0)
    rows = []
    load_before = os.getloadavg()[0]
    for n in sizes:
        x = rng.uniform(-1, 1, (n, 3))
        repeats = 7 if n >= 100_000 else 30
        fns = [lambda: dense_numpy_wedm.evaluate(x), lambda: dense_numpy_wedm.evaluate_matrix(x)] \
            + [lambda rbx=rbx: evaluate(rbx, x) for rbx in cases]
        t = interleaved_seconds(fns, repeats)
        rates = n / np.median(t, axis=0)
        # per-repeat speed-ups of the engine's COA over each baseline, then the median
        loop_ratio, matrix_ratio = np.median(t[:, :2] / t[:, 2:3], axis=0)
        centroid_ratio = np.median(t[:, 0] / t[:, 3])
        row = [f"{n:,}", f"{rates[0]:,.0f}", f"{rates[1]:,.0f}", f"{rates[2]:,.0f}",
               f"{loop_ratio:.1f}x", f"{matrix_ratio:.1f}x", f"{rates[3]:,.0f}",
               f"{centroid_ratio:.1f}x"]
        row += [f"{faults_per_call(fn):,.0f}" for fn in fns[2:]]
        row += [f"{peak_bytes(fn) / 2**20:.1f}" for fn in fns]
        rows.append(row)
        print(" | ".join(row), flush=True)
    load_after = os.getloadavg()[0]
    header = ["batch", "dense loop COA /s", "dense matrix COA /s", "engine COA /s",
              "vs loop", "vs matrix", "engine centroid /s", "vs loop", "COA faults/call",
              "centroid faults/call", "loop MiB", "matrix MiB",
              "COA MiB", "centroid MiB"]
    text = ("# Engine benchmark: WEDM three-region rule base (75 rules, 3 inputs, 2 outputs)\n\n"
            "Evaluations per second (CPU time), median of repeats; one evaluation = both outputs; "
            "minor page faults per call after a warm-up call (an output array the allocator maps "
            "fresh costs its pages: 391 at 1e5). Two "
            "plain dense numpy baselines, both evaluating all 75 rules for every sample "
            "(benchmarks/dense_numpy_wedm.py): *loop*, a Python loop over the 75 rules with each "
            "rule vectorized over the batch, and *matrix*, all activations as one (N, 75) matrix "
            "aggregated through a one-hot map (in 64k chunks). The "
            "baselines and the engine are timed in turn within each repeat and \"vs\" is "
            "the median of the per-repeat speed-ups (the machine's load varies: on a shared 2-core "
            "machine single rates moved by up to 2x between runs). Peak memory by "
            "tracemalloc, including the result itself (N x 2 float64 = 15.3 MiB at 1e6). "
            f"numpy {np.__version__}, CPython {platform.python_version()}. Load average (1 min) "
            f"{load_before:.1f} when the run started, {load_after:.1f} when it ended "
            f"({os.cpu_count()} CPUs).\n\n"
            "- COA: the paper's eq. 2 (max-min, center of area over the output terms' peaks).\n"
            "- centroid: the same rule base with uniform triangle output terms (same peaks), "
            "exact centroid of the max-min aggregate.\n\n" + markdown_table(header, rows))
    text += "\n" + fuzzylite_row(rng)
    write_result(ROOT / "benchmarks" / "results" / "engine.md", text)
    return text


def fuzzylite_row(rng) -> str:
    try:
        import fuzzylite_wedm
    except ImportError:
        return "pyfuzzylite is not installed: no comparison.\n"
    rb = load(ROOT / "rulebases" / "wedm_three_region.fz").rulebase
    weighted = copy.deepcopy(rb)
    weighted.inference.defuzzifier = Defuzzifier.WEIGHTED_AVERAGE
    pairs = [(fuzzylite_wedm.build(rb, tsk=True), weighted),
             (fuzzylite_wedm.build(triangle_outputs(rb), tsk=False), triangle_outputs(rb))]
    rows = []
    for n in (1, 1000):
        x = rng.uniform(-1, 1, (n, 3))
        row = [f"{n:,}"]
        for fl_engine, rbx in pairs:
            fl_rate = rate(lambda: fuzzylite_wedm.evaluate(fl_engine, x), n, 3 if n > 1 else 20)
            ours = rate(lambda: evaluate(rbx, x), n, 20)
            gap = np.abs(fuzzylite_wedm.evaluate(fl_engine, x) - evaluate(rbx, x)).max()
            row += [f"{fl_rate:,.0f}", f"{ours:,.0f}", f"{gap:.1e}"]
        rows.append(row)
        print(" | ".join(row), flush=True)
    header = ["batch", "fuzzylite TSK /s", "fuzzyc weighted average /s", "max diff",
              "fuzzylite centroid /s", "fuzzyc exact centroid /s", "max diff"]
    return ("\n## pyfuzzylite 8 on the same rule base\n\n"
            "TSK: Constant output terms at the peaks, WeightedAverage over the rules, against "
            "fuzzyc's weighted average (the same sum over rules; not eq. 2, which takes the max "
            "over rules concluding the same term). Mamdani: Minimum implication, Maximum "
            "aggregation, Centroid sampled at fuzzylite's default 1000 points, against fuzzyc's "
            "exact centroid (max diff = the sampling error). Vectorized `process()`.\n\n"
            + markdown_table(header, rows))


if __name__ == "__main__":
    print(main(quick="--quick" in sys.argv))
