"""`cd tests && python -m differential [--per-tool N] [--seed S] [--tools a,b] [--keep]`.

Generates N random rule bases per tool and format, judges each (fuzzyc under the tool's
semantics against the live tool), prints per tool: generated, imported, refused, crashed,
agree, agree but on rows a known bug of the tool explains (toolbugs), disagree, tool errors,
and the `.fz` round trip of the imported files (same numbers under every semantics /
imported; differential.roundtrip), then each tool's shares of the imported files; then the
refusals and crashes grouped by message, the round trips that fail or that the .fz writer
refuses grouped by message, and the disagreements shrunk and grouped by cause.  --keep writes
each cause's smallest case to differential/cases/ (replayed by
tests/test_differential_cases.py).  Exits 1 on a crash."""
from __future__ import annotations

import argparse
import collections
import re
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from fuzzyc.formats import load_any

from . import cases, toolbugs, tools
from .compare import TOOLS
from .judge import Verdict, judge
from .render import SUFFIX
from .roundtrip import RoundTrip, fz_round_trip
from .shrink import diagnose_all, shrink_all
from .spec import Generator, evaluation_points

COLUMNS = ("tool, format", "generated", "imported", "refused", "crashed", "agree",
           "agree but the tool's bug rows", "disagree", "tool error", ".fz round trip")
IMPORTED = ("agree", "tool-bug", "disagree", "tool-error")


def campaign(tool_key: str, count: int, seed: int) -> tuple[list, list[Verdict], list]:
    fmt = TOOLS[tool_key][2]
    generator = Generator(fmt, seed * 7919 + sum(map(ord, tool_key)))
    systems = [generator.system(f"r{seed}_{k}") for k in range(count)]
    xs = [np.array(evaluation_points(s, seed * 100003 + k)) for k, s in enumerate(systems)]
    verdicts = judge(tool_key, systems, xs)
    return list(zip(systems, xs)), verdicts, round_trips(systems, xs, verdicts)


def round_trips(systems: list, xs: list, verdicts: list[Verdict]) -> list:
    """Per imported file its .fz round trip (differential.roundtrip), None for the others."""
    done = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, (system, x, verdict) in enumerate(zip(systems, xs, verdicts)):
            if verdict.status not in IMPORTED:
                done.append(None)
                continue
            path = Path(tmp) / f"{system.name}_{k}{SUFFIX[system.fmt]}"
            path.write_text(verdict.text)
            try:
                done.append(fz_round_trip(load_any(path), x, str(path.with_suffix(".fz"))))
            except Exception as exc:    # noqa: BLE001 -- a crash is a finding
                done.append(RoundTrip("crashed", f"{type(exc).__name__}: {exc}"))
    return done


def row(tool_key: str, verdicts: list[Verdict], trips: list) -> list:
    counts = collections.Counter(v.status for v in verdicts)
    imported = sum(counts[s] for s in IMPORTED)
    trip = collections.Counter(t.status for t in trips if t is not None)
    failed = imported - trip["same"] - trip["refused"]
    return [tool_key, len(verdicts), imported, counts["refused"], counts["crashed"],
            counts["agree"], counts["tool-bug"], counts["disagree"], counts["tool-error"],
            f"{trip['same']}/{imported} same, {trip['refused']} refused, {failed} failed"]


def shares(tool_key: str, verdicts: list[Verdict]) -> str:
    """Agreement among the imported files, with and without the rows of the tool's known bugs,
    and the share refused."""
    counts = collections.Counter(v.status for v in verdicts)
    imported = sum(counts[s] for s in IMPORTED)
    if not imported:
        return f"{tool_key}: nothing imported"
    pct = lambda n, of: f"{100 * n / of:.1f} %"     # noqa: E731
    both = counts["agree"] + counts["tool-bug"]
    return (f"{tool_key}: {counts['agree']} of {imported} imported agree on every row "
            f"({pct(counts['agree'], imported)}), {both} ({pct(both, imported)}) with the rows "
            f"of the tool's known bugs aside; refused {pct(counts['refused'], len(verdicts))}")


def table(rows: list[list]) -> str:
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def _unplaced(message: str) -> str:
    """A message without its file and place, so that one kind of refusal counts once."""
    return re.sub(r"^\S+:\d+:\d+: error: ", "", message)


def _unnamed(message: str) -> str:
    """A round trip's message without the file's own names and numbers (one line per kind)."""
    message = re.sub(r"`[^`]*`", "`X`", _unplaced(message))
    return re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", "N", message)


def report(key: str, made: list, verdicts: list[Verdict], trips: list, args) -> list[str]:
    """The tool's refusals, crashes and tool errors grouped by message, the .fz round trips
    that are refused or fail; its disagreements and crashes shrunk, grouped by cause (and
    kept with --keep)."""
    lines = [f"\n## {key}"]
    for status in ("refused", "crashed", "tool-error", "tool-bug"):
        grouped = collections.Counter(_unplaced(v.message).split(toolbugs.EVIDENCE)[0]
                                      for v in verdicts if v.status == status)
        lines += [f"  {status} x{n}: {message}" for message, n in grouped.most_common()]
    grouped = collections.Counter(f"{t.status}: {_unnamed(t.message)}" for t in trips
                                  if t is not None and t.status != "same")
    lines += [f"  .fz round trip {what} x{n}" for what, n in grouped.most_common()]
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
    print(table([row(k, verdicts, trips) for k, (_, verdicts, trips) in done.items()]))
    print("\n".join(shares(k, verdicts) for k, (_, verdicts, _) in done.items()))
    with ThreadPoolExecutor(max_workers=2) as pool:
        reports = list(pool.map(lambda k: report(k, *done[k], args), done))
    for lines in reports:
        print("\n".join(lines))
    failed = gate(done)
    print("\n".join(["", *failed] if failed else ["", "gate: passed (" + GATE + ")"]))
    print(f"\n{time.monotonic() - start:.0f} s")
    return 1 if failed else 0


GATE = ("no crash; per tool at least 95 % of the imported files agree, the rows of the tool's "
        "known bugs aside; at most 5 % refused; every .fz round trip the same or refused")


def gate(done: dict) -> list[str]:
    """What fails issue 28's bar, a line each (empty when it holds)."""
    failed = []
    for key, (_, verdicts, trips) in done.items():
        counts = collections.Counter(v.status for v in verdicts)
        imported = sum(counts[s] for s in IMPORTED)
        agree = counts["agree"] + counts["tool-bug"]
        trip = collections.Counter(t.status for t in trips if t is not None)
        if counts["crashed"]:
            failed.append(f"gate: {key}: {counts['crashed']} crashed")
        if imported and agree < 0.95 * imported:
            failed.append(f"gate: {key}: {agree} of {imported} imported agree, under 95 %")
        if counts["refused"] > 0.05 * len(verdicts):
            failed.append(f"gate: {key}: {counts['refused']} of {len(verdicts)} refused, "
                          "over 5 %")
        if imported - trip["same"] - trip["refused"]:
            failed.append(f"gate: {key}: {imported - trip['same'] - trip['refused']} .fz "
                          "round trips failed")
    return failed


if __name__ == "__main__":
    sys.exit(main())
