"""`python -m tests.fuzz [--inputs N] [--jobs J] [--seed S] [--targets fz,csv,...]`.

Prints inputs tried, outcomes and failures per target, and every failure class with the folder
of its saved input; exits 1 when any traceback, unlocated rejection, over-bound input (CPU, wall
clock or memory) or subprocess mismatch occurred.
"""
from __future__ import annotations

import argparse
import multiprocessing
import resource
import shutil
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from .known import known_owner
from .runner import FAILURES, Tally, fuzz_target
from .targets import ROOT, SHARES, TARGETS, snapshot

MEMORY_LIMIT = 4 << 30   # a hostile input that allocates more is a MemoryError, not a dead machine


def plan(inputs: int, jobs: int, seed: int, names: list[str]) -> list[tuple[str, int, int]]:
    """(target, inputs, hypothesis seed) chunks: each target's share split over the jobs."""
    total = sum(SHARES[n] for n in names)
    chunks = []
    for name in names:
        count = max(1, round(inputs * SHARES[name] / total))
        for k in range(jobs):
            share = count // jobs + (1 if k < count % jobs else 0)
            if share:
                chunks.append((name, share, seed * 1000 + k))
    return chunks


def _work(chunk: tuple[str, int, int], out: str, seconds: float, subprocess_every: int) -> Tally:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    name, count, seed = chunk
    return fuzz_target(TARGETS[name], count, seed, Path(out), seconds, subprocess_every)


def run_all(inputs: int, jobs: int, seed: int, names: list[str], out: Path, seconds: float,
            subprocess_every: int) -> dict[str, Tally]:
    tallies = {name: Tally(name) for name in names}
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
        chunks = plan(inputs, jobs, seed, names)
        results = pool.map(_work, chunks, *zip(*[(str(out), seconds, subprocess_every)]
                                                * len(chunks)))
        for (name, _, _), tally in zip(chunks, results):
            tallies[name].merge(tally)
    return tallies


# the failure kinds as headers: "tracebacks" for traceback
COLUMNS = ("target", "inputs", "runs", "accepted", "rejected-located", "usage", "refused",
           "other exit", *(k + "s" if k == "traceback" else k for k in FAILURES), "warnings",
           "cpu s")


def table(tallies: dict[str, Tally]) -> str:
    """One row per target (mutation targets, then generators) and a total: inputs, command
    runs by outcome, CPU seconds."""
    rows = []
    total = Tally("total")
    for tally in tallies.values():
        total.merge(tally)
    for tally in [*tallies.values(), total]:
        o = tally.outcomes
        other = sum(n for k, n in o.items() if k.startswith("exit "))
        fails = failures_by_kind(tally)
        rows.append((tally.target, tally.inputs, sum(tally.commands.values()), o["ok"],
                     o["rejected"], o["usage"], o["refused"], other,
                     *(fails[k] for k in FAILURES), tally.warnings, f"{tally.cpu:.0f}"))
    width = [max(len(str(r[i])) for r in [COLUMNS, *rows]) for i in range(len(COLUMNS))]
    lines = ["  ".join(str(v).rjust(w) for v, w in zip(r, width))
             for r in [COLUMNS, *rows]]
    # the generators (gen-*) after the mutation targets, apart
    first = next((i for i, r in enumerate(rows, 1) if r[0].startswith("gen-")), None)
    if first and first > 1:
        lines.insert(first, "")
    return "\n".join(lines)


def failures_by_kind(tally: Tally) -> dict[str, int]:
    counts = dict.fromkeys(FAILURES, 0)
    for (kind, _), n in tally.failures.items():
        counts[kind] += n
    return counts


def failure_list(tallies: dict[str, Tally]) -> str:
    lines = []
    for tally in tallies.values():
        for (kind, signature), n in tally.failures.most_common():
            owner = known_owner(signature)
            note = f"  [known, {owner}]" if owner else ""
            lines.append(f"{tally.target:8s} {n:5d}  {kind}: {signature}{note}")
            lines += [f"{'':16s}{folder}" for folder in tally.examples[(kind, signature)][:1]]
    return "\n".join(lines)


def summary(tallies: dict[str, Tally], wall: float) -> str:
    """The figures `make fuzz` promises: inputs tried, exit codes, tracebacks, rejections
    without file:line:col."""
    total = Tally("total")
    for tally in tallies.values():
        total.merge(tally)
    fails = failures_by_kind(total)
    codes = ", ".join(f"{code}: {n}" for code, n in sorted(
        total.exit_codes.items(), key=lambda item: (not item[0].isdigit(), item[0].zfill(3))))
    return "\n".join([
        f"inputs tried: {total.inputs} ({sum(total.commands.values())} commands, "
        f"{total.subprocess_runs} also through the console script; {wall:.0f} s wall, "
        f"{total.cpu:.0f} CPU s)",
        f"exit codes: {codes}",
        f"tracebacks: {fails['traceback']}",
        f"rejections without file:line:col: {fails['unlocated']}",
        f"other failures: nonfinite {fails['nonfinite']}, over-bound {fails['over-bound']}, "
        f"subprocess {fails['subprocess']}"])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests.fuzz", description=__doc__)
    parser.add_argument("--inputs", type=int, default=10000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--targets", default=",".join(TARGETS),
                        help="comma-separated: " + ",".join(TARGETS))
    parser.add_argument("--out", default=str(ROOT / "out" / "fuzz"),
                        help="failing inputs are saved here (emptied first)")
    parser.add_argument("--timeout", type=float, default=15.0, help="CPU seconds per command")
    parser.add_argument("--subprocess-every", type=int, default=200,
                        help="run every Nth input of a chunk through the console script too")
    args = parser.parse_args(argv)
    names = [n for n in args.targets.split(",") if n]
    unknown = [n for n in names if n not in TARGETS]
    if unknown:
        parser.error(f"unknown target {', '.join(unknown)}")
    out = Path(args.out)
    shutil.rmtree(out, ignore_errors=True)
    started, before = time.monotonic(), snapshot()
    tallies = run_all(args.inputs, args.jobs, args.seed, names, out, args.timeout,
                      args.subprocess_every)
    changed = [str(p) for p, data in before.items() if p.read_bytes() != data]
    print(table(tallies))
    failures = failure_list(tallies)
    print(f"\nfailure classes (first saved input under {out}):\n{failures}" if failures
          else "\nno failures")
    print("\n" + summary(tallies, time.monotonic() - started))
    if changed:
        print("the run changed shipped files (restore them with git checkout): "
              + " ".join(changed))
    return 1 if changed or any(t.failures for t in tallies.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
