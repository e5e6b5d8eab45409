"""Closed-loop speed: WEDM test-1 loops (three-region rule base + gap plant) per second.

Reports simulated controller+plant steps per second (loop periods x batch / wall time) at
batch 1 and 1,000 (randomized plant parameters), the median of repeated runs, and the ratio
to batch 1 measured in the same run; and the shares of the loop's time taken by the engine
(rule-base evaluation) and by the plant's step, measured in one more run whose engine and
plant calls are timed.  The load average before and after goes with the numbers. Markdown to
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



def _scenario(seconds: float, batch: int):
    from fuzzyc.plants.scenario import load
    from fuzzyc.runtime.simulate import load_controller
    scenario = load("wedm_finish", {"duration": str(seconds)})
    return scenario, load_controller(scenario, batch)


def _run_loop(scenario, controller, batch: int, seed: int, wrap_plant=None):
    """One timed run (s): the blocks are built and the rule base compiled before the clock.
    wrap_plant(module) -> a stand-in for the plant module (to time its steps)."""
    from fuzzyc.runtime.blocks import PlantBlock
    from fuzzyc.runtime.loop import run
    from fuzzyc.runtime.simulate import build
    blocks = build(scenario, controller, batch, seed, randomize=batch > 1)
    if wrap_plant is not None:
        for block in blocks:
            if isinstance(block, PlantBlock):
                block.plant = wrap_plant(block.plant)
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


class _Timed:
    """A stand-in that times the calls of some of its target's methods (the rest pass)."""

    def __init__(self, target, methods: tuple[str, ...]):
        self.target, self.seconds = target, 0.0
        for name in methods:
            setattr(self, name, self._timed(getattr(target, name)))

    def _timed(self, method):
        def call(*args):
            start = time.perf_counter()
            out = method(*args)
            self.seconds += time.perf_counter() - start
            return out
        return call

    def __getattr__(self, name):
        return getattr(self.target, name)


def shares(batch: int, seconds: float) -> tuple[float, float]:
    """(rule-base evaluation, plant step) shares of one run's wall time, their calls timed.

    The engine is the controller's rule base (`fuzzyc.engine.chain.compiled`); the plant is the
    plant module's `step` (plants/wedm_gap.py, with its noise draws)."""
    import fuzzyc.engine.chain as C
    scenario, controller = _scenario(seconds, batch)
    engines: list[_Timed] = []
    plants: list[_Timed] = []
    plain = C.compiled
    C.compiled = lambda rb: engines.append(
        _Timed(plain(rb), ("evaluate_chunk", "evaluate_rows"))) or engines[-1]
    try:
        elapsed, _ = _run_loop(scenario, controller, batch, 0,
                               lambda m: plants.append(_Timed(m, ("step",))) or plants[-1])
    finally:
        C.compiled = plain
    return (sum(t.seconds for t in engines) / elapsed, sum(t.seconds for t in plants) / elapsed)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=20.0, help="simulated seconds per run")
    args = ap.parse_args(argv)
    from fuzzyc.atomic import write_text
    load_before = os.getloadavg()[0]
    rows = []
    for batch in (1, 1000):
        median, worst = steps_per_second(batch, args.seconds, args.repeats)
        engine, plant = shares(batch, args.seconds)
        rows.append((batch, median, worst, engine, plant))
        print(f"batch {batch:5d}: {median:12,.0f} steps/s (median of {args.repeats}; "
              f"slowest {worst:,.0f}); engine {100 * engine:.0f} %, plant {100 * plant:.0f} % "
              "of the time")
    load_after = os.getloadavg()[0]
    print(f"load average (1 min) {load_before:.1f} before, {load_after:.1f} after, "
          f"on {os.cpu_count()} cores")
    base = rows[0][1]
    lines = ["# Closed-loop speed: WEDM test 1 (three-region rule base + gap plant)", "",
             f"{args.seconds:g} simulated s at 40 ms per run, median of {args.repeats} runs; "
             f"{platform.python_version()}, {platform.machine()}. Target at batch 1,000: "
             f">= 2,000,000 steps/s. Wall time: the machine's load average was "
             f"{load_before:.1f} when the run started and {load_after:.1f} when it ended, on "
             f"{os.cpu_count()} cores (other work slows every number here alike). Engine: the "
             "rule-base evaluation; plant: the plant model's step (its noise included); the "
             "rest is the controller's signal chain and the loop.", "",
             "| batch | steps/s (median) | slowest run | vs batch 1 | engine share | "
             "plant share |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {b} | {m:,.0f} | {w:,.0f} | {m / base:.0f}x | {100 * e:.0f} % | "
              f"{100 * p:.0f} % |" for b, m, w, e, p in rows]
    write_text(ROOT / "benchmarks" / "results" / "loop.md", "\n".join(lines) + "\n")
    print(f"wrote {ROOT / 'benchmarks' / 'results' / 'loop.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
