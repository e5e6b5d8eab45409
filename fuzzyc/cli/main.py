"""The `fuzzyc` command: one subcommand per module, bad input reported without a traceback."""
from __future__ import annotations

import argparse
import importlib
import sys

from ..errors import FuzzycError

# Each module has add_parser(subparsers) and run(args) -> exit status.
COMMAND_MODULES = ("check", "eval", "plot", "compile", "simulate", "learn", "verify", "convert")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="fuzzyc",
        description="Fuzzy controllers for machine-tool processes: check, evaluate, plot, "
                    "compile to C, simulate against plant models, learn, verify, convert.")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMAND_MODULES:
        importlib.import_module(f"fuzzyc.cli.{name}").add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except FuzzycError as exc:
        for diagnostic in exc.diagnostics:
            print(diagnostic.format(), file=sys.stderr)
        count = len(exc.diagnostics)
        print(f"{count} error{'s' if count != 1 else ''}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
