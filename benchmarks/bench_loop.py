"""Closed-loop speed: WEDM test-1 loops (three-region rule base + gap plant) per second.

Reports simulated controller+plant steps per second (loop periods x batch / wall time) at
batch 1 and 1,000 (randomized plant parameters), the median of repeated runs, and the ratio
to batch 1 measured in the same run; and the engine's share of the loop's time (rule-base
evaluation, measured in one more run whose engine calls are timed). Markdown to
benchmarks/results/loop.md (atomic).
Run: python3 benchmarks/bench_loop.py [--repeats 5] [--seconds 20]
"""
from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _import_paths() -> None:
    """From a source checkout, alias runtime/ and plants/ as the installed package has them."""
    try:
        import fuzzyc.runtime  # noqa: F401
    except ImportError:
        sys.path.insert(0, str(ROOT))
        sys.path.insert(0, str(ROOT / "tests"))
        import conftest  # noqa: F401  (the aliasing lives there)


def _scenario(seconds: float, batch: int):
    from fuzzyc.plants.scenario import load
    from fuzzyc.runtime.simulate import load_controller
    scenario = load("wedm_finish", {"duration": str(seconds)})
    return scenario, load_controller(scenario, batch)


def _run_loop(scenario, controller, batch: int, seed: int):
    """One timed run (s): the blocks are built and the rule base compiled before the clock."""
    from fuzzyc.runtime.loop import run
    from fuzzyc.runtime.simulate import build
    blocks = build(scenario, controller, batch, seed, randomize=batch > 1)
    start = time.perf_counter()
    trace = run(blocks, scenario.period, scenario.duration, batch,
                initial=scenario.data.get("initial"), record=["abnormal_ratio"])
    return time.perf_counter() - start, trace.steps


def steps_per_second(batch: int, seconds: float, repeats: int) -> tuple[float, float]:
    """(median, slowest) controller+plant steps per second over `repeats` runs."""
    scenario, controller = _scenario(seconds, batch)
    rates = []
    for seed in range(repeats):
        elapsed, steps = _run_loop(scenario, controller, batch, seed)
        rates.append(steps * batch / elapsed)
    return statistics.median(rates), min(rates)


class _TimedEngine:
    """The engine's tables with their evaluation timed."""

    def __init__(self, engine):
        self.engine, self.seconds = engine, 0.0

    def evaluate_rows(self, x):
        start = time.perf_counter()
        y = self.engine.evaluate_rows(x)
        self.seconds += time.perf_counter() - start
        return y

    def evaluate_chunk(self, x):
        start = time.perf_counter()
        y = self.engine.evaluate_chunk(x)
        self.seconds += time.perf_counter() - start
        return y


def engine_share(batch: int, seconds: float) -> float:
    """The rule-base evaluation's share of one run's wall time (its calls timed)."""
    import fuzzyc.controller as C
    scenario, controller = _scenario(seconds, batch)
    timed: list[_TimedEngine] = []
    plain = C.compiled
    C.compiled = lambda rb: timed.append(_TimedEngine(plain(rb))) or timed[-1]
    try:
        elapsed, _ = _run_loop(scenario, controller, batch, 0)
    finally:
        C.compiled = plain
    return sum(t.seconds for t in timed) / elapsed


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=20.0, help="simulated seconds per run")
    args = ap.parse_args(argv)
    _import_paths()
    from fuzzyc.atomic import write_text
    rows = []
    for batch in (1, 1000):
        median, worst = steps_per_second(batch, args.seconds, args.repeats)
        share = engine_share(batch, args.seconds)
        rows.append((batch, median, worst, share))
        print(f"batch {batch:5d}: {median:12,.0f} steps/s (median of {args.repeats}; "
              f"slowest {worst:,.0f}); engine {100 * share:.0f} % of the time")
    base = rows[0][1]
    lines = ["# Closed-loop speed: WEDM test 1 (three-region rule base + gap plant)", "",
             f"{args.seconds:g} simulated s at 40 ms per run, median of {args.repeats} runs; "
             f"{platform.python_version()}, {platform.machine()}. Target at batch 1,000: "
             f">= 2,000,000 steps/s. Wall time: the machine's load average when the run "
             f"started was {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores (other work "
             "slows every number here alike).", "",
             "| batch | steps/s (median) | slowest run | vs batch 1 | engine share |",
             "|---|---|---|---|---|"]
    lines += [f"| {b} | {m:,.0f} | {w:,.0f} | {m / base:.0f}x | {100 * e:.0f} % |"
              for b, m, w, e in rows]
    write_text(ROOT / "benchmarks" / "results" / "loop.md", "\n".join(lines) + "\n")
    print(f"wrote {ROOT / 'benchmarks' / 'results' / 'loop.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
