"""The `fuzzyc` command: one subcommand per module, bad input reported without a traceback.

Exit status: 0 success, 1 a property violated (`verify`), 2 bad input (a located message),
70 an internal error (a bug: the traceback is printed to be reported), 130 interrupted,
141 standard output closed early (`fuzzyc ... | head`).
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys
import traceback

from .. import __version__
from ..errors import FuzzycError

# Each module has add_parser(subparsers) and run(args) -> exit status.
COMMAND_MODULES = ("check", "eval", "plot", "compile", "simulate", "learn", "tune", "verify",
                   "convert", "examples")

BAD_INPUT, INTERNAL_ERROR, INTERRUPTED, BROKEN_PIPE = 2, 70, 130, 141


class _CommandParser(argparse.ArgumentParser):
    """A subcommand's parser: options may stand anywhere among the positionals
    (`fuzzyc eval FILE --json a=1` as well as `fuzzyc eval --json FILE a=1`)."""

    _intermixing = False

    def parse_known_args(self, args=None, namespace=None):
        # parse_known_intermixed_args calls parse_known_args itself: plain parsing there.
        if self._intermixing:
            return super().parse_known_args(args, namespace)
        self._intermixing = True
        try:
            return self.parse_known_intermixed_args(args, namespace)
        finally:
            self._intermixing = False


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="fuzzyc",
        description="Fuzzy controllers for machine-tool processes: check, evaluate, plot, "
                    "compile to C, simulate against plant models, learn, verify, convert.")
    parser.add_argument("--version", action="version", version=f"fuzzyc {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True,
                                       parser_class=_CommandParser)
    for name in COMMAND_MODULES:
        importlib.import_module(f"fuzzyc.cli.{name}").add_parser(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        status = int(args.run(args) or 0)
        sys.stdout.flush()   # a full disk behind `> file` shows here, not at interpreter exit
        return status
    except FuzzycError as exc:
        for diagnostic in exc.diagnostics:
            print(diagnostic.format(), file=sys.stderr)
        count = len(exc.diagnostics)
        print(f"{count} error{'s' if count != 1 else ''}", file=sys.stderr)
        return BAD_INPUT
    except KeyboardInterrupt:
        return INTERRUPTED
    except BrokenPipeError:
        _silence_stdout()
        return BROKEN_PIPE
    except OSError as exc:
        # Reads and writes of named files are checked and reported where they happen, so an
        # OSError without a file name is standard output failing (`> /dev/full`: ENOSPC).
        if exc.filename is not None:
            return _internal_error()
        _silence_stdout()
        print(f"error: cannot write to standard output: {exc.strerror or exc}", file=sys.stderr)
        return BAD_INPUT
    except Exception:   # noqa: BLE001 - the last resort: every bad input has its own message
        return _internal_error()


def _internal_error() -> int:
    print("fuzzyc: internal error, please report it with the command and its input files:",
          file=sys.stderr)
    traceback.print_exc()
    return INTERNAL_ERROR


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail again."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):   # no real file descriptor (a test's captured stdout)
        pass


if __name__ == "__main__":
    sys.exit(main())
