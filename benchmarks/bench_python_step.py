"""One evaluation from Python: microseconds of CPU time per call on the WEDM rule base
(rulebases/wedm_three_region.fz, 75 rules, 3 inputs, 2 outputs), for each way of asking:

- engine evaluate, batch 1: fuzzyc.engine.inference.evaluate(rb, x) with x of shape (1, 3)
  (checks the rule-base cache, then the scalar path);
- evaluate_one(rb, dict): the same with inputs by name;
- fuzzyc.evaluate(model, dict): the public API (names checked, arrays broadcast);
- scalar_evaluator(rb): the scalar path bound to the compiled tables (no per-call checks);
- Controller.step, batch 1: the signal chain around the rule base (scaling, delta, integrate).

Each figure is the best of 5 passes over 2,000 distinct random points (every pass CPU time
via time.process_time, so other processes on a shared machine count less), interleaved pass by
pass; the load average is printed beside them.  The rule base's outputs are checked equal (bit
for bit) between the engine and the scalar path on the same points first.

    python3 benchmarks/bench_python_step.py
"""
from __future__ import annotations

import os
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one

import fuzzyc  # noqa: E402
from fuzzyc.engine.chain import Controller  # noqa: E402
from fuzzyc.engine.inference import evaluate, evaluate_one, scalar_evaluator  # noqa: E402

POINTS = 2000
PASSES = 5


def cases(model) -> dict:
    rb = model.rulebase
    names = [v.name for v in rb.inputs]
    x = np.random.default_rng(0).uniform(-1.2, 1.2, (POINTS, len(names)))
    rows = [x[k:k + 1] for k in range(POINTS)]
    points = x.tolist()
    named = [dict(zip(names, p)) for p in points]
    scalar = scalar_evaluator(rb)
    batch = evaluate(rb, x)
    if not np.array_equal(np.array([scalar(p) for p in points]), batch):
        raise SystemExit("the scalar path and the batch engine disagree")
    controller = Controller(model, batch=1)
    signals = [s.name for s in model.signals]
    lo = np.array([s.lo for s in model.signals], dtype=float)
    hi = np.array([s.hi for s in model.signals], dtype=float)
    steps = [{n: np.array([v]) for n, v in zip(signals, row)}
             for row in np.random.default_rng(1).uniform(lo, hi, (POINTS, len(signals)))]
    return {
        "engine evaluate, batch 1": (lambda r: evaluate(rb, r), rows),
        "evaluate_one(rb, dict)": (lambda d: evaluate_one(rb, d), named),
        "fuzzyc.evaluate(model, dict)": (lambda d: fuzzyc.evaluate(model, d), named),
        "scalar_evaluator(rb)": (scalar, points),
        "Controller.step, batch 1": (controller.step, steps),
    }


def measure(fns: dict) -> dict[str, float]:
    """Best CPU microseconds per call of each case, passes interleaved."""
    best = {name: float("inf") for name in fns}
    for fn, items in fns.values():      # warm-up
        for item in items[:100]:
            fn(item)
    for _ in range(PASSES):
        for name, (fn, items) in fns.items():
            start = time.process_time()
            for item in items:
                fn(item)
            best[name] = min(best[name], (time.process_time() - start) / len(items) * 1e6)
    return best


def main() -> str:
    model = fuzzyc.load(ROOT / "rulebases" / "wedm_three_region.fz")
    load_before = os.getloadavg()[0]
    best = measure(cases(model))
    load_after = os.getloadavg()[0]
    lines = [f"one evaluation from Python, WEDM (CPU us per call, best of {PASSES} passes over "
             f"{POINTS} points; load average {load_before:.1f} -> {load_after:.1f}, "
             f"{os.cpu_count()} CPUs)"]
    lines += [f"  {name:<32} {us:8.2f} us" for name, us in best.items()]
    return "\n".join(lines)


if __name__ == "__main__":
    print(main())
