"""`cd tests && python -m differential [--per-tool N] [--seed S] [--tools a,b] [--keep]`.

Generates N random rule bases per tool and format, judges each (fuzzyc under the tool's
semantics against the live tool), prints per tool: generated, imported, refused, crashed,
agree, disagree, tool errors; then the refusals and crashes grouped by message, and the
disagreements shrunk and grouped by cause.  --keep writes each cause's smallest case to
differential/cases/ (replayed by tests/test_differential_cases.py).  Exits 1 on a crash."""
from __future__ import annotations

import argparse
import collections
import re
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import cases, toolbugs, tools
from .compare import TOOLS
from .judge import Verdict, judge
from .shrink import diagnose_all, shrink_all
from .spec import Generator, evaluation_points

COLUMNS = ("tool, format", "generated", "imported", "refused", "crashed", "agree", "disagree",
           "tool error")


def campaign(tool_key: str, count: int, seed: int) -> tuple[list, list[Verdict]]:
    fmt = TOOLS[tool_key][2]
    generator = Generator(fmt, seed * 7919 + sum(map(ord, tool_key)))
    systems = [generator.system(f"r{seed}_{k}") for k in range(count)]
    xs = [np.array(evaluation_points(s, seed * 100003 + k)) for k, s in enumerate(systems)]
    return list(zip(systems, xs)), judge(tool_key, systems, xs)


def row(tool_key: str, verdicts: list[Verdict]) -> list:
    counts = collections.Counter(v.status for v in verdicts)
    imported = counts["agree"] + counts["disagree"] + counts["tool-error"]
    return [tool_key, len(verdicts), imported, counts["refused"], counts["crashed"],
            counts["agree"], counts["disagree"], counts["tool-error"]]


def table(rows: list[list]) -> str:
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def _unplaced(message: str) -> str:
    """A message without its file and place, so that one kind of refusal counts once."""
    return re.sub(r"^\S+:\d+:\d+: error: ", "", message)


def report(key: str, made: list, verdicts: list[Verdict], args) -> list[str]:
    """The tool's refusals, crashes and tool errors grouped by message; its disagreements
    and crashes shrunk, grouped by cause (and kept with --keep)."""
    lines = [f"\n## {key}"]
    for status in ("refused", "crashed", "tool-error"):
        grouped = collections.Counter(_unplaced(v.message).split(toolbugs.EVIDENCE)[0]
                                      for v in verdicts if v.status == status)
        lines += [f"  {status} x{n}: {message}" for message, n in grouped.most_common()]
    found = [(s, x, v) for (s, x), v in zip(made, verdicts)
             if v.status in ("disagree", "crashed")][:args.shrink]
    causes = collections.Counter()
    shrunk = shrink_all(key, found, args.shrink_seconds)
    for (small, small_x, last), cause in zip(shrunk, diagnose_all(key, shrunk)):
        causes[cause] += 1
        if args.keep:
            cases.keep(key, cause, small, small_x, last)
    return lines + [f"  cause x{n}: {cause}" for cause, n in causes.most_common()]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m differential")
    parser.add_argument("--per-tool", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--tools", default=",".join(TOOLS))
    parser.add_argument("--shrink", type=int, default=40,
                        help="at most this many disagreements and crashes shrunk per tool")
    parser.add_argument("--shrink-seconds", type=float, default=90.0,
                        help="time to shrink each tool's cases")
    parser.add_argument("--keep", action="store_true", help="write the shrunk cases")
    parser.add_argument("--refresh", action="store_true",
                        help="only re-evaluate the kept cases (after a fix) and say which are open")
    args = parser.parse_args(argv)
    if args.refresh:
        for path, still in cases.refresh():
            print(f"{path.parent.name}/{path.name}: {still or 'matches'}")
        return 0
    start = time.monotonic()
    keys = [k for k in args.tools.split(",") if k]
    missing = {k: tools.available(TOOLS[k][0]) for k in keys}
    for key, why in missing.items():
        if why:
            print(f"{key}: skipped, {why}")
    keys = [k for k in keys if not missing[k]]
    with ThreadPoolExecutor(max_workers=2) as pool:
        done = dict(zip(keys, pool.map(lambda k: campaign(k, args.per_tool, args.seed), keys)))
    print(table([row(k, verdicts) for k, (_, verdicts) in done.items()]))
    with ThreadPoolExecutor(max_workers=2) as pool:
        reports = list(pool.map(lambda k: report(k, *done[k], args), done))
    for lines in reports:
        print("\n".join(lines))
    crashed = any(v.status == "crashed" for _, verdicts in done.values() for v in verdicts)
    print(f"\n{time.monotonic() - start:.0f} s")
    return 1 if crashed else 0


if __name__ == "__main__":
    sys.exit(main())
