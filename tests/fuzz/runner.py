"""Run mutated inputs through `fuzzyc.cli.main` in-process and classify what happens.

Outcomes: `ok` (exit 0), `rejected` (exit 2, every message with file:line:col), `usage`
(argparse refused the command line), `refused` (`convert` or `compile` of a valid file into a
format or back end that cannot say it: the message names what, the input is not at fault),
`exit N` (another status a command documents, e.g. a
verify that finds a counterexample), and the failures: `traceback` (any exception out of
main), `unlocated` (an exit-2 message about an input file without file:line:col),
`over-bound` (an input that runs past the CPU or wall-clock limit, or a MemoryError past the
worker's address-space limit) and `subprocess` (the console script disagrees with the
in-process run).
"""
from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import seed as hypothesis_seed
from hypothesis import strategies as st

from typing import TYPE_CHECKING

from .known import known_owner

if TYPE_CHECKING:           # targets imports the API runner, which imports this module
    from .targets import Target

FAILURES = ("traceback", "unlocated", "nonfinite", "over-bound", "subprocess")
# CPU seconds bound the work; wall-clock seconds (this many times the CPU bound) catch an input
# that waits instead (on stdin, a pipe, a lock, a sleep), which a CPU timer never sees
WALL_FACTOR = 4
TRACEBACK = "Traceback (most recent call last)"
SAVED_PER_CLASS = 3


class InputTimeout(BaseException):
    """Raised by the alarm: a BaseException so no `except Exception` in the code swallows it."""


@dataclass
class Run:
    argv: list[str]
    code: int | None
    stderr: str
    stdout: str = ""
    error: str | None = None     # the traceback text, when main raised
    usage: bool = False          # argparse exited
    warnings: int = 0
    located: bool | None = None  # an API rejection: whether it names the input


@contextlib.contextmanager
def bounded(seconds: float):
    """Raise InputTimeout after `seconds` of CPU time or WALL_FACTOR times that of wall time
    (a generous wall bound: on a shared machine the CPU bound is the one that measures work)."""
    def cpu(*_):
        raise InputTimeout(f"more than {seconds:g} CPU s")

    def wall(*_):
        raise InputTimeout(f"more than {seconds * WALL_FACTOR:g} s of wall time")

    previous = signal.signal(signal.SIGPROF, cpu), signal.signal(signal.SIGALRM, wall)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, seconds * WALL_FACTOR)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGPROF, previous[0])
        signal.signal(signal.SIGALRM, previous[1])


def run_in_process(argv: list[str], seconds: float) -> Run:
    from fuzzyc.cli import main
    out, err = io.StringIO(), io.StringIO()
    run = Run(argv, None, "")
    try:
        with bounded(seconds), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
                warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                run.code = main(argv)
            except SystemExit as exc:          # only argparse exits
                run.code, run.usage = (exc.code if isinstance(exc.code, int) else 2), True
            finally:
                run.warnings = len(caught)
    except BaseException as exc:               # noqa: B036 - classifying is the point
        if isinstance(exc, KeyboardInterrupt):
            raise
        run.error = traceback.format_exc()
    finally:
        with contextlib.suppress(Exception):
            import matplotlib.pyplot as plt
            plt.close("all")
    run.stderr, run.stdout = err.getvalue(), out.getvalue()
    return run


def run_console_script(argv: list[str], seconds: float,
                       cwd: Path | None = None) -> tuple[int | None, str]:
    script = Path(sys.executable).with_name("fuzzyc")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "fuzzyc"]
    try:
        done = subprocess.run(command + argv, capture_output=True, text=True, errors="replace",
                              timeout=seconds * 10, cwd=cwd)
    except subprocess.TimeoutExpired:
        return None, "timeout"
    return done.returncode, done.stderr


# Diagnostic.format(): `FILE:LINE:COL: error: ...`, or `error: ...` when it has no place; a
# message may also carry the place in its text (`error: data.csv:3:2: ...`).
UNLOCATED = re.compile(r"(?m)^error: (?!.*:\d+:\d+)(.*)$")
# Commands that translate a file `check` accepted (the rule targets run them only then): a
# message without a place says what the other format or back end cannot do, not what is wrong
# with the input.
TRANSLATORS = ("convert", "compile")


def _deepest_project_frame(text: str) -> str:
    frames = re.findall(r'File "([^"]+)", line \d+, in (\S+)', text)
    mine = [(f, fn) for f, fn in frames
            if re.search(r"/(fuzzyc|plants|runtime|rulebases)/", f) and "/site-packages/" not in f]
    if not mine:
        return "?"
    file, function = mine[-1]
    short = re.sub(r".*/(fuzzyc|plants|runtime)/", r"\1/", file)
    return f"{short}:{function}"


def _normalized(message: str, tmp: Path) -> str:
    text = message.replace(str(tmp), "TMP")
    text = re.sub(r"`[^`]*`", "`…`", text)
    text = re.sub(r"0x[0-9a-f]+|\d+", "0", text)
    return text[:70]


def classify(run: Run, target: Target, tmp: Path) -> tuple[str, str]:
    """(outcome, class signature: what makes two failures the same bug)."""
    command = run.argv[0] if run.argv else "-"
    # main() catches what nothing else did and prints it as an internal error (exit 70)
    error = run.error or (run.stderr if TRACEBACK in run.stderr else None)
    if error is not None:
        last = error.strip().splitlines()[-1]
        exc_type = last.split(":")[0].rpartition(".")[2]
        # past a bound: the CPU or wall timer, or the worker's address space (numpy's
        # _ArrayMemoryError is a MemoryError)
        kind = "over-bound" if "InputTimeout" in last or "MemoryError" in exc_type \
            else "traceback"
        return kind, f"{command}: {exc_type} at {_deepest_project_frame(error)}"
    if run.usage:
        return "usage", ""
    if run.located is not None:           # an API call (tests/fuzz/api.py)
        if run.code == 0:
            return ("nonfinite", f"{command}: {run.stdout[:70]}") if run.stdout else ("ok", "")
        return ("rejected", "") if run.located else \
            ("unlocated", f"{command}: {_normalized(run.stderr.strip(), tmp)}")
    if run.code == 0:
        nonfinite = nonfinite_output(run) if command == "eval" else None
        return ("nonfinite", f"eval: {_normalized(nonfinite, tmp)}") if nonfinite else ("ok", "")
    if run.code == 2 and command in TRANSLATORS and UNLOCATED.search(run.stderr):
        return "refused", ""
    if run.code == 2:
        unlocated = UNLOCATED.search(run.stderr)
        if unlocated and target.located:
            return "unlocated", f"{command}: {_normalized(unlocated.group(1), tmp)}"
        return "rejected", ""
    return f"exit {run.code}", ""


def _refuse_constant(name: str):
    raise ValueError(name)


def nonfinite_output(run: Run) -> str | None:
    """What is wrong when a successful `eval` printed an output that is NaN or infinite (the
    engine promises a number for every input, docs/limits.md) or --json that is not JSON."""
    if "--csv" in run.argv:
        return _nonfinite_csv(run)
    if "--json" in run.argv:
        try:
            outputs = json.loads(run.stdout, parse_constant=_refuse_constant)["outputs"]
        except ValueError as exc:
            return f"--json is not strict JSON ({exc})"
        bad = [k for k, v in outputs.items() if v is None or not math.isfinite(v)]
        return f"--json output {bad[0]} is not a number" if bad else None
    line = next((ln for ln in run.stdout.splitlines() if ln.startswith("outputs: ")), "")
    return "an output is nan or inf" if re.search(r"= -?(nan|inf)\b", line) else None


def _nonfinite_csv(run: Run) -> str | None:
    """Output columns (those the input CSV has not) with a value that is not finite."""
    table = Path(run.argv[run.argv.index("--csv") + 1])
    # the header as eval reads it: without a byte-order mark
    first = table.read_text(encoding="utf-8-sig", errors="replace").partition("\n")[0]
    inputs = {name.strip() for name in first.split(",")}
    try:       # newline="": a quoted \r inside a field is the field's, as csv wants it
        rows = list(csv.reader(io.StringIO(run.stdout, newline="")))
        columns = [i for i, name in enumerate(rows[0]) if name not in inputs] if rows else []
        for row in rows[1:]:
            for i in columns:
                if not math.isfinite(float(row[i])):
                    return f"--csv output {rows[0][i]} = {row[i]}"
    except (csv.Error, ValueError, IndexError) as exc:   # a finding, never the harness's crash
        return f"--csv output is not a table of numbers ({type(exc).__name__}: {exc})"
    return None


@dataclass
class Tally:
    """What one target's inputs did."""
    target: str
    inputs: int = 0
    outcomes: Counter = field(default_factory=Counter)
    commands: Counter = field(default_factory=Counter)
    exit_codes: Counter = field(default_factory=Counter)     # "exception": main raised
    failures: Counter = field(default_factory=Counter)       # (kind, signature) -> count
    examples: dict = field(default_factory=dict)              # (kind, signature) -> [folders]
    warnings: int = 0
    subprocess_runs: int = 0
    cpu: float = 0.0          # CPU seconds of this process (the machine may be shared)
    reproduce: str = "fuzzyc"  # the command a saved input's argv is given to

    def merge(self, other: "Tally") -> None:
        self.inputs += other.inputs
        self.outcomes.update(other.outcomes)
        self.commands.update(other.commands)
        self.exit_codes.update(other.exit_codes)
        self.failures.update(other.failures)
        for key, folders in other.examples.items():
            self.examples.setdefault(key, []).extend(folders)
        self.warnings += other.warnings
        self.subprocess_runs += other.subprocess_runs
        self.cpu += other.cpu

    def failure_count(self, include_known: bool = True) -> int:
        return sum(n for (kind, sig), n in self.failures.items()
                   if include_known or known_owner(sig) is None)


def _save(tally: Tally, key: tuple[str, str], run: Run, tmp: Path, out: Path) -> None:
    folders = tally.examples.setdefault(key, [])
    if len(folders) >= SAVED_PER_CLASS:
        return
    slug = re.sub(r"[^A-Za-z0-9]+", "_", f"{key[0]} {key[1]}")[:80].strip("_")
    folder = out / tally.target / f"{slug}-{len(folders) + 1}-{tmp.name}"
    shutil.copytree(tmp, folder, dirs_exist_ok=True)
    argv = [a.replace(str(tmp), str(folder)) for a in run.argv]
    detail = run.error or run.stderr + run.stdout
    (folder / "REPRODUCE.txt").write_text(
        f"{key[0]}: {key[1]}\nreproduce: {tally.reproduce} {shlex.join(argv)}\n\n{detail}",
        encoding="utf-8", errors="replace")
    folders.append(str(folder))


def fuzz_target(target: Target, inputs: int, seed: int, out: Path, seconds: float = 15.0,
                subprocess_every: int = 0, unmutated: list[int] | None = None) -> Tally:
    """`inputs` mutated inputs of one target (hypothesis-driven, reproducible from `seed`);
    `unmutated`: the seed files of these indices as they are, instead."""
    tally = Tally(target.name, reproduce=target.reproduce)
    started = time.process_time()
    strategy = (st.sampled_from([(i, target.seeds[i][0].encode("utf-8")) for i in unmutated])
                if unmutated else target.input_strategy())

    @hypothesis_seed(seed)
    @settings(max_examples=inputs, database=None, deadline=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck), print_blob=False)
    @given(strategy, st.data())
    def one(chosen, data):
        index, blob = chosen
        with tempfile.TemporaryDirectory(prefix=f"fuzz-{target.name}-") as name, \
                _working_directory(name):         # a default output (compile -o .) lands here
            tmp = Path(name)
            path = tmp / f"input{target.suffix}"
            path.write_bytes(blob)
            counted = False
            pending = list(target.commands(data.draw, path, tmp, target.seeds[index][1]))
            while pending:
                argv = pending.pop(0)
                if callable(argv):            # follow-up commands, built once the others passed
                    pending = list(argv()) + pending
                    continue
                if not counted:           # hypothesis may abandon an input while drawing
                    tally.inputs, counted = tally.inputs + 1, True
                # the console script runs the command on a copy of the folder as it is now:
                # after the in-process run, a command that refuses to overwrite would differ
                due = subprocess_every and tally.inputs % subprocess_every == 1 \
                    and target.run is None
                before = _copy_of(tmp) if due else None
                run = (target.run or run_in_process)(argv, seconds)
                kind, signature = classify(run, target, tmp)
                tally.commands[argv[0] if argv else "-"] += 1
                tally.outcomes[kind] += 1
                tally.exit_codes["exception" if run.code is None else str(run.code)] += 1
                tally.warnings += run.warnings
                if kind in FAILURES:
                    tally.failures[(kind, signature)] += 1
                    _save(tally, (kind, signature), run, tmp, out)
                    break
                if before is not None:
                    _compare_with_console_script(tally, run, kind, tmp, before, out, seconds)
                if kind != "ok":
                    break

    one()
    tally.cpu = time.process_time() - started
    return tally


@contextlib.contextmanager
def _working_directory(path: str):
    previous = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(previous)


def _copy_of(tmp: Path) -> Path:
    copy = Path(tempfile.mkdtemp(prefix=f"{tmp.name}-script-"))
    shutil.copytree(tmp, copy, dirs_exist_ok=True)
    return copy


def _compare_with_console_script(tally: Tally, run: Run, kind: str, tmp: Path, before: Path,
                                 out: Path, seconds: float) -> None:
    """The installed `fuzzyc`, run on `before` (a copy of the folder as it was before the
    in-process run), gives the in-process exit status and prints no traceback."""
    if any("\0" in a for a in run.argv):     # no process can be given a NUL in its arguments
        shutil.rmtree(before, ignore_errors=True)
        return
    tally.subprocess_runs += 1
    try:
        code, stderr = run_console_script([a.replace(str(tmp), str(before)) for a in run.argv],
                                          seconds, cwd=before)
    finally:
        shutil.rmtree(before, ignore_errors=True)
    if code == run.code and TRACEBACK not in stderr:
        return
    key = ("subprocess", f"{run.argv[0]}: in-process {kind} exit {run.code}, script exit {code}")
    tally.failures[key] += 1
    _save(tally, key, Run(run.argv, code, stderr), tmp, out)
