"""`python -m fuzzyc.conformance [--details] [--no-live]`: the conformance table in Markdown."""
from __future__ import annotations

import argparse
import sys
from importlib import resources

from pathlib import Path

from ..formats import load_any
from . import oracles
from .check import TOLERANCE, FileResult, check
from .roundtrip import EXPORTS, round_trip
from .suites import suites

RULEBASES = Path(str(resources.files("fuzzyc.rulebases")))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzzyc.conformance",
                                     description=__doc__)
    parser.add_argument("--details", action="store_true", help="one line per file as well")
    parser.add_argument("--no-live", action="store_true",
                        help="compare with the shipped .fld data only (no fuzzylite/octave runs)")
    args = parser.parse_args(argv)
    rows, details, agreeing = [], [], []
    for suite in suites():
        results = [check(p, suite, live=not args.no_live) for p in suite.files]
        rows.append(summary(suite.name, results, suite.missing))
        details += [detail(suite.name, r) for r in results]
        agreeing += [r.path for r in results if r.agrees and suite.oracle == "fuzzylite"
                     and r.path.suffix == ".fll"]
    print("| suite | files | import | refused | agree (tool semantics, "
          f"{TOLERANCE:g} of range) | worst difference, exact semantics |")
    print("|---|---|---|---|---|---|")
    print("\n".join(rows))
    if not args.no_live:
        print()
        print(round_trip_table(agreeing))
    if args.details:
        print("\n| suite | file | result |\n|---|---|---|")
        print("\n".join(details))
    return 0


def round_trip_table(corpus: list[Path]) -> str:
    """Exports of the shipped rule bases and of the agreeing fuzzylite examples, read back by
    the tools (skipped where a tool is missing)."""
    models = [(p, load_any(p)) for p in [*sorted(RULEBASES.glob("*.fz")), *corpus]]
    live = {"fuzzylite": oracles.have_fuzzylite(), "octave": oracles.have_octave()}
    lines = ["| export | read by | models | written | agree (tool semantics) | not agreeing |",
             "|---|---|---|---|---|---|"]
    for tool, formats in EXPORTS.items():
        for fmt in formats:
            if not live[tool]:
                lines.append(f"| .{fmt} | {tool} | skipped: not installed | | | |")
                continue
            done = [round_trip(m, str(p), fmt, tool) for p, m in models]
            written = [r for r in done if r.written]
            bad = ", ".join(f"{Path(r.name).name} ({r.message or f'{r.worst:.2g}'})"
                            for r in written if not r.agrees)
            lines.append(f"| .{fmt} | {tool} | {len(done)} | {len(written)} | "
                         f"{sum(r.agrees for r in written)}/{len(written)} | "
                         f"{bad.replace('|', '/')} |")
    return "\n".join(lines)


def summary(name: str, results: list[FileResult], missing: str) -> str:
    if missing:
        return f"| {name} | skipped: {missing} | | | | |"
    n = len(results)
    imported = sum(r.imported for r in results)
    agree = sum(r.agrees for r in results)
    compared = [r for r in results if r.compared]
    worst = max(compared, key=lambda r: r.worst_exact, default=None)
    shown = f"{worst.worst_exact:.3g} ({worst.path.name})" if worst else ""
    return f"| {name} | {n} | {imported}/{n} | {n - imported} | {agree}/{n} | {shown} |"


def detail(suite: str, r: FileResult) -> str:
    if not r.imported:
        what = "refused: " + r.message
    elif not r.compared:
        what = "imported, not compared: " + r.message
    else:
        what = (f"{'agrees' if r.agrees else 'DIFFERS'}: tool {r.worst_tool:.3g}, "
                f"exact {r.worst_exact:.3g} ({r.rows} rows)")
    return f"| {suite} | {r.path.name} | {what.replace('|', '/')} |"


if __name__ == "__main__":
    sys.exit(main())
