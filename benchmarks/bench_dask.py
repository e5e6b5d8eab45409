"""Monte Carlo campaign speed: 10^6 randomized WEDM test-1 loops in chunks, in this process and
on a local Dask cluster of 1 and 2 workers.

Each variant runs the command's campaign (`fuzzyc simulate --scenario wedm_finish --set
duration=S --batch N --randomize --chunk C [--workers W]`, printed) through the same function
the command calls, `repeats` times, the variants interleaved so that load from other work falls
on all of them alike; the median wall time (cluster start-up included: it is what a user
waits for) and loops per second are reported, with the load average before and after. Every
run's summary must equal the first one's (the split does not change the numbers).
Markdown to benchmarks/results/dask.md (atomic).
Run: python3 benchmarks/bench_dask.py [--loops 1000000] [--seconds 1] [--chunk 10000]
     [--repeats 3]
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))


VARIANTS = {"in this process": None, "1 Dask worker": 1, "2 Dask workers": 2}


def command(loops: int, seconds: float, chunk: int, workers: int | None) -> str:
    return (f"fuzzyc simulate --scenario wedm_finish --set duration={seconds:g} --batch {loops} "
            f"--randomize --chunk {chunk}" + ("" if workers is None else f" --workers {workers}"))


def run_once(scenario, loops: int, chunk: int, workers: int | None) -> tuple[float, str]:
    """(wall seconds, the summary as JSON) of one campaign."""
    from fuzzyc.runtime.campaign import Cluster, simulate_campaign
    start = time.perf_counter()
    campaign = simulate_campaign(scenario, loops, Cluster(workers=workers, chunk=chunk,
                                                          progress=False), randomize=True)
    return time.perf_counter() - start, json.dumps(campaign.summary)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loops", type=int, default=1_000_000)
    ap.add_argument("--seconds", type=float, default=1.0, help="simulated seconds per loop")
    ap.add_argument("--chunk", type=int, default=10_000, help="loops per task")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    from fuzzyc.plants.scenario import load
    from common import markdown_table, write_result
    scenario = load("wedm_finish", {"duration": str(args.seconds)})
    periods = int(round(args.seconds / scenario.period))
    load_before = os.getloadavg()[0]
    times: dict[str, list[float]] = {name: [] for name in VARIANTS}
    summaries = set()
    for repeat in range(args.repeats):
        for name, workers in VARIANTS.items():
            print(f"[{repeat + 1}/{args.repeats}] {command(args.loops, args.seconds, args.chunk, workers)}",
                  flush=True)
            seconds, summary = run_once(scenario, args.loops, args.chunk, workers)
            times[name].append(seconds)
            summaries.add(summary)
            print(f"    {seconds:.1f} s", flush=True)
    load_after = os.getloadavg()[0]
    if len(summaries) != 1:
        print("the summaries differ between runs: the split changed the numbers")
        return 1
    base = statistics.median(times["in this process"])
    rows = []
    for name, workers in VARIANTS.items():
        median = statistics.median(times[name])
        rows.append([name, f"`{command(args.loops, args.seconds, args.chunk, workers)}`",
                     f"{median:.1f}", f"{min(times[name]):.1f}", f"{max(times[name]):.1f}",
                     f"{args.loops / median:,.0f}", f"{base / median:.2f}x"])
    text = (f"# Monte Carlo campaign on Dask: {args.loops:,} WEDM test-1 loops\n\n"
            f"{args.loops:,} randomized loops of {args.seconds:g} simulated s ({periods} periods "
            f"of 40 ms: {args.loops * periods:,} controller+plant steps), {args.chunk:,} loops "
            f"per task; wall time, cluster start-up included, median of {args.repeats} runs "
            f"per variant, the variants interleaved. {platform.python_version()}, "
            f"{platform.machine()}, {os.cpu_count()} cores shared with other work: load average "
            f"(1 min) {load_before:.1f} before, {load_after:.1f} after. Every run gave the same "
            "summary, bit for bit.\n\n"
            + markdown_table(["where", "command", "median s", "fastest s", "slowest s",
                              "loops/s", "vs in-process"], rows))
    print(text)
    write_result(ROOT / "benchmarks" / "results" / "dask.md", text)
    print(f"wrote {ROOT / 'benchmarks' / 'results' / 'dask.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
