"""Engine cost against the number of inputs: full-grid rule bases with 2 to 10 inputs.

Each input has three uniform triangle terms on [-1, 1] (a partition), every combination of
terms is one AND rule (3**I rules), the consequent is the singleton term nearest the mean of
the premise's term indices, and the output is the center of area (eq. 2).  Microseconds per
evaluation at batch 1 and batch 1,000, median of repeats; the engine path that ran (grid with
per-cell tables, grid with tables per term tuple, sparse or dense); the CPU time of the batch
alongside its wall time; and the dense reference `activations` on the same batch for comparison
(only where it stays under a few seconds); the generated float C header's CPU time per call
on the same batch and the way it finds the rules (its cell table of term tuples, direct or by
binary search among the occupied cells' codes, or every rule); and the q15 and q31 headers'
rule base (`NAME_q15_rulebase` on integer inputs, the same cell table) per call on the same
batch put on their integer grid.  Writes benchmarks/results/wide.md.

    python3 benchmarks/bench_wide.py [--quick]
"""
from __future__ import annotations

import ctypes
import itertools
import os
import pathlib
import platform
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one

from common import markdown_table, median_seconds, write_result  # noqa: E402
from fuzzyc.backends.c.header import HeaderWriter  # noqa: E402
from fuzzyc.backends.c.expressions import REAL_TYPES  # noqa: E402
from fuzzyc.backends.c_fixed.header import FORMATS, generate_fixed_header  # noqa: E402
from fuzzyc.backends.c.load import CController, compile_shared  # noqa: E402
from fuzzyc.language.builder import RuleSpec, assemble_rulebase  # noqa: E402
from fuzzyc.engine.inference import activations, compiled, evaluate  # noqa: E402
from fuzzyc.semantics.model import (Connective, Defuzzifier, Inference, Model, SourceLoc,  # noqa: E402
                          TermKind, Variable)

TERMS = ["N", "Z", "P"]
OUT = ["NB", "NS", "ZO", "PS", "PB"]


def uniform(name: str, names: list[str]) -> Variable:
    peaks = np.linspace(-1, 1, len(names))
    h = peaks[1] - peaks[0]
    params = np.stack([peaks - h, peaks, peaks, peaks + h], axis=1)
    return Variable(name, -1.0, 1.0, list(names), np.full(len(names), int(TermKind.TRAPEZOID)),
                    params)


def full_grid(n_inputs: int):
    inputs = [uniform(f"x{i}", TERMS) for i in range(n_inputs)]
    out = Variable("y", -1.0, 1.0, OUT, np.full(5, int(TermKind.SINGLETON)),
                   np.array([[p, 0, 0, 0] for p in np.linspace(-1, 1, 5)]))
    loc = SourceLoc("bench", 0, 0)
    rules = [RuleSpec({f"x{i}": (t, False, 0) for i, t in enumerate(combo)}, Connective.AND,
                      {"y": int(round(np.mean(combo) * 2))}, 1.0, loc, "")
             for combo in itertools.product(range(3), repeat=n_inputs)]
    return assemble_rulebase(inputs, [out], rules,
                             Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))


def path_of(rb) -> str:
    engine = compiled(rb)
    if engine.grid is not None:
        return "grid" if engine.grid.columns is not None else "grid, tables per term tuple"
    return "sparse" if engine.sparse else "dense"


def c_header_cost(rb, x: np.ndarray) -> str:
    """CPU us per call of the float header over the batch x, and how it finds the rules."""
    model = Model.of_rulebase(rb, f"wide{len(rb.inputs)}")
    writer = HeaderWriter(model, REAL_TYPES["float"])
    controller = CController(model)
    us = median_seconds(lambda: controller.evaluate(x), 5, time.process_time) * 1e6 / len(x)
    how = "every rule" if not writer.sparse else \
        "cell table" if writer.cells.codes is None else "cell codes, binary search"
    return f"{us:.2f} ({how})"


FIXED_SHIM = """\
#include "fixed.h"
void run(int n, const long long *x, long long *y) {{
    int b, k;
    {io} xq[{n_in}], yq[1];
    for (b = 0; b < n; ++b) {{
        for (k = 0; k < {n_in}; ++k) xq[k] = ({io})x[b * {n_in} + k];
        {name}_{numeric}_rulebase(xq, yq);
        y[b] = yq[0];
    }}
}}
"""


def fixed_header_cost(rb, numeric: str, x: np.ndarray) -> str:
    """CPU us per call of the q15/q31 header's rule base over the batch x on its grid."""
    model = Model.of_rulebase(rb, f"wide{len(rb.inputs)}")
    io, full, _ = FORMATS[numeric]
    shim = FIXED_SHIM.format(io=io, n_in=len(rb.inputs), name=model.name, numeric=numeric)
    lib = ctypes.CDLL(str(compile_shared({"fixed.h": generate_fixed_header(model, numeric),
                                          "shim.c": shim}, "shim.c")))
    xq = np.ascontiguousarray(np.round((x + 1) / 2 * full), dtype=np.int64)
    y = np.empty(len(xq), dtype=np.int64)
    ptr = ctypes.POINTER(ctypes.c_longlong)
    lib.run.argtypes = [ctypes.c_int, ptr, ptr]
    us = median_seconds(lambda: lib.run(len(xq), xq.ctypes.data_as(ptr), y.ctypes.data_as(ptr)),
                        5, time.process_time) * 1e6 / len(xq)
    return f"{us:.2f}"


def main(quick: bool = False) -> str:
    rng = np.random.default_rng(0)
    rows = []
    load_before = os.getloadavg()[0]
    for n_in in range(2, 9 if quick else 11):
        rb = full_grid(n_in)
        x1 = rng.uniform(-1, 1, (1, n_in))
        xk = rng.uniform(-1, 1, (1000, n_in))
        one = median_seconds(lambda: evaluate(rb, x1), 30) * 1e6
        batch = median_seconds(lambda: evaluate(rb, xk), 5) * 1e6 / len(xk)
        batch_cpu = median_seconds(lambda: evaluate(rb, xk), 5, time.process_time) * 1e6 / len(xk)
        dense = ""
        if rb.n_rules <= 3 ** 8:
            dense = f"{median_seconds(lambda: activations(rb, xk), 3) * 1e6 / len(xk):.2f}"
        c_cost = c_header_cost(rb, xk)
        fixed = [fixed_header_cost(rb, numeric, xk) for numeric in ("q15", "q31")]
        row = [n_in, f"{rb.n_rules:,}", path_of(rb), f"{one:.1f}", f"{batch:.2f}",
               f"{batch_cpu:.2f}", dense, c_cost, *fixed]
        rows.append(row)
        print(" | ".join(map(str, row)), flush=True)
    load_after = os.getloadavg()[0]
    header = ["inputs", "rules", "engine path", "batch 1: us/eval", "batch 1000: us/eval",
              "batch 1000: CPU us/eval", "dense activations only, batch 1000: us/eval",
              "C float header, batch 1000: CPU us/call", "C q15 header: CPU us/call",
              "C q31 header: CPU us/call"]
    text = ("# Engine cost against the number of inputs\n\n"
            "Full-grid rule bases: three uniform triangles per input, one AND rule per term "
            "combination (3^I rules), center of area over five singletons. Median of repeats; "
            "the last column is the dense reference computing every rule's activation (no "
            "defuzzification), for scale. The CPU column counts this process's CPU time only: "
            "on a loaded machine a call longer than a scheduler time slice also waits for the "
            "other processes in wall time. "
            f"numpy {np.__version__}, CPython {platform.python_version()}; load average (1 min) "
            f"{load_before:.1f} at the start, {load_after:.1f} at the end "
            f"({os.cpu_count()} CPUs).\n\n" + markdown_table(header, rows))
    write_result(ROOT / "benchmarks" / "results" / "wide.md", text)
    return text


if __name__ == "__main__":
    print(main(quick="--quick" in sys.argv))
