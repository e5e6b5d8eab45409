"""What the command modules share."""
from __future__ import annotations

import argparse
import math
import os
import tempfile
from pathlib import Path

from ..atomic import cannot_write
from ..language.limits import MAX_BATCH, MAX_WORKERS
from ..language.numbers import not_a_number, parse_integer, parse_number

# What every command that reads through formats.load_any says of its rule-file argument.
RULE_FILE_HELP = ("a .fz, .fll, .fcl or .fis rule file; FILE.fcl::NAME reads the FUNCTION_BLOCK "
                  "NAME of an FCL file that has several")


SEMANTICS_HELP = ("the arithmetic of a source tool where it differs from fuzzyc's exact one: "
                  "fuzzylite (6), pyfuzzylite (8), matlab, octave, optionally :RESOLUTION "
                  "(fuzzylite:200); default exact (docs/formats.md)")


def add_semantics(parser) -> None:
    parser.add_argument("--semantics", default="exact", metavar="TOOL[:N]", help=SEMANTICS_HELP)


def at_least(low: int | None, high: int | None = None):
    """An argparse type: an integer of at least `low` (and at most `high`); argparse refuses
    anything else (exit 2, naming the option) instead of a traceback deep in the run (`--batch
    0`, a negative `--seed`, `--batch 99999999999`)."""
    def integer(text: str) -> int:
        value = parse_integer(text)
        if value is None:
            raise argparse.ArgumentTypeError(f"`{text}` is not a whole number: write "
                                             "digits, with an optional sign")
        if low is not None and value < low:
            raise argparse.ArgumentTypeError(f"must be at least {low}, got {value}")
        if high is not None and value > high:
            raise argparse.ArgumentTypeError(f"must be at most {high:,}, got {value:,}")
        return value
    return integer


# a whole number in ASCII digits (int() also takes `1_0` and `５`); the command checks its range
whole_number = at_least(None)
# --batch: checked here, before the loops' arrays are allocated (fuzzyc.language.limits.MAX_BATCH)
batch_size = at_least(1, MAX_BATCH)


def finite(text: str) -> float:
    """An argparse type: a finite number (`--eta nan` trained a whole run, then failed)."""
    value = parse_number(text)
    if value is None:
        raise argparse.ArgumentTypeError(not_a_number(text))
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value


def non_negative(text: str) -> float:
    """An argparse type: a finite number >= 0 (`--noise-sigmas nan` would reach a proof)."""
    value = finite(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be at least 0, got {text}")
    return value


def check_output(path: str | Path, folder: bool = False) -> None:
    """Before any work: FuzzycError `cannot write to PATH: reason` unless PATH can be written,
    a folder (folder=True) or a file, made with its missing parent folders. Tried for real,
    by creating and removing a temporary file (or folder) where the first one would go: a
    read-only folder, /proc or a name under a file (/dev/full/x) all fail here, in a moment,
    not after a long simulation or training."""
    path = Path(path)
    try:
        reason = _unwritable(path, folder)
    except OSError as exc:   # e.g. a parent folder that may not be searched
        reason = exc.strerror or str(exc)
    if reason:
        raise cannot_write(path, reason)


def _unwritable(path: Path, folder: bool) -> str | None:
    if "\0" in str(path):          # the system refuses the name (pathlib: a ValueError)
        return "a file name cannot hold a NUL character"
    if path.exists() or path.is_symlink():
        if folder and not path.is_dir():
            return "it is a file, not a folder"
        if not folder and not path.is_file():
            # the file is replaced atomically: a folder, a device or a pipe cannot be
            return "it is a folder" if path.is_dir() else "it is not a regular file"
    target = path if folder else path.parent
    existing = target
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        return f"{existing} is not a folder"
    try:
        if existing == target:
            fd, probe = tempfile.mkstemp(prefix=".fuzzyc-probe-", dir=existing)
            os.close(fd)
            os.unlink(probe)
        else:
            os.rmdir(tempfile.mkdtemp(prefix=".fuzzyc-probe-", dir=existing))
    except OSError as exc:
        return f"cannot create anything in {existing} ({exc.strerror or exc})"
    return None


def add_progress(parser) -> None:
    """--progress / --no-progress: args.progress True (a bar on stderr even when it is not a
    terminal), False (never) or None (the default: a bar only when stderr is a terminal, so a
    log file or a pipe never gets one)."""
    shown = parser.add_mutually_exclusive_group()
    shown.add_argument("--progress", action="store_true", default=None,
                       help="show the progress line on stderr even when it is not a terminal "
                            "(default: only on a terminal)")
    shown.add_argument("--no-progress", "--quiet", action="store_false", dest="progress",
                       help="never show a progress line")


def add_campaign_arguments(parser) -> None:
    """--workers / --scheduler / --chunk: run the loops in chunks, on Dask (runtime.campaign)."""
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=at_least(1, MAX_WORKERS), metavar="N",
                       help="run the loops in chunks on a local Dask cluster of N processes "
                            "(pip install 'fuzzyc[dask]'); the numbers do not change")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run the chunks on a running Dask cluster (tcp://host:8786)")
    parser.add_argument("--chunk", type=whole_number, metavar="LOOPS",
                        help="loops per task (default 10000; alone: chunks in this process)")


def cluster_from(args):
    """The runtime.campaign.Cluster the arguments ask for; None for one batch in-process."""
    if args.workers is None and args.scheduler is None and args.chunk is None:
        return None
    from fuzzyc.runtime.campaign import DEFAULT_CHUNK, Cluster
    from ..errors import Diagnostic, FuzzycError
    try:
        chunk = DEFAULT_CHUNK if args.chunk is None else args.chunk
        return Cluster(args.workers, args.scheduler, chunk,
                       progress=getattr(args, "progress", None))
    except ValueError as exc:
        raise FuzzycError([Diagnostic(None, str(exc))]) from None
