"""Every error message the suite makes fuzzyc give, collected into one list (issue 30).

tests/conftest.py registers this plugin.  While the tests run it records, without changing
what fuzzyc does:

* raise - each Diagnostic of each FuzzycError that fuzzyc's own code constructs (the class's
  __init__ is wrapped; a FuzzycError a test builds itself is not fuzzyc's message);
* cli   - each `error:` line the command prints on stderr: `fuzzyc.cli.main.main` called in
  the test process (stderr teed while it runs) and `python -m fuzzyc` run with
  subprocess.run and its stderr captured (the CompletedProcess's stderr read afterwards);
  argparse's `fuzzyc CMD: error: ...` included;
* api   - an exception of another type that a test expects with pytest.raises and that was
  raised by fuzzyc's code (the innermost frame of its traceback in the fuzzyc package): the
  refusals of the Python API (ValueError, TypeError, ...).

Each xdist worker (or the single process) writes what it saw to one JSON file in a folder
the controller made under pytest's basetemp; at the end of the session the controller merges
them, normalises each message into its kind (the test's concrete names, numbers, paths and
quoted texts replaced, so one kind of message counts once), and writes the list of kinds with
how many tests produced each and one example test id to error_messages.txt (and the raw
merged record to error_messages.json) beside it, or to the file named by
FUZZYC_ERROR_MESSAGES.  The terminal summary shows the count and the path.

Then each kind is held to tests/error_messages_reviewed.txt (see `check`): a kind not in the
reviewed list, or a kind that breaks the rules the list marks for it, fails the session (exit
status 1, listed in the terminal summary).  The check runs at the end of the session, in the
controller, over the union of all workers' records: no test has to run last, and how xdist
splits the files does not matter - a kind is collected or not whichever worker runs its test.
A run of some of the tests checks the kinds it saw (a subset); the reviewed kinds a run did
not produce are only counted.  FUZZYC_ERROR_MESSAGES_CHECK=warn lists instead of failing (the
default under FUZZYC_EXPLORE: fresh random examples may say new things; the Makefile sets it
for the oracle targets outside `make test`), =off skips the check.
"""
from __future__ import annotations

import functools
import importlib
import json
import os
import re
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import pytest

import fuzzyc
from fuzzyc.errors import FuzzycError

def _package_folders() -> tuple[str, ...]:
    """Where fuzzyc's code lies: the package, and fuzzyc.plants and fuzzyc.runtime, which a
    development install maps to the tree's plants/ and runtime/ (the wheel puts them under
    fuzzyc/; setup.py's ROOTS)."""
    folders = [Path(fuzzyc.__file__).resolve().parent]
    for name in ("fuzzyc.plants", "fuzzyc.runtime"):
        try:
            folders.append(Path(importlib.import_module(name).__file__).resolve().parent)
        except (ImportError, TypeError):
            pass
    return tuple(str(f) + os.sep for f in folders)


PACKAGES = _package_folders()
REVIEWED = Path(__file__).with_name("error_messages_reviewed.txt")
OUT_ENV, CHECK_ENV = "FUZZYC_ERROR_MESSAGES", "FUZZYC_ERROR_MESSAGES_CHECK"
WORKER_KEY = "fuzzyc_error_messages_dir"

# (source, exception type, message, location) -> the ids of the tests that produced it
_seen: dict[tuple, set[str]] = defaultdict(set)
_current = ["<collection>"]
# the tests whose inputs are drawn at random (hypothesis, or marked `drawn_inputs`): their
# messages' texts follow the draws (and a new hypothesis release draws others), so a kind
# only they produce is listed, not gated
_drawn: set[str] = set()


@functools.lru_cache(maxsize=None)
def _in_package(filename: str) -> bool:
    try:
        return str(Path(filename).resolve()).startswith(PACKAGES)
    except (OSError, ValueError):
        return False


def _record(source: str, kind: str, message: str, loc: tuple | None) -> None:
    key = (source, kind, message, loc)
    tests = _seen[key]
    if len(tests) < 50:      # enough to count "how many tests"; bounded for hypothesis loops
        tests.add(_current[0])


# --- raise: FuzzycError constructed by fuzzyc -------------------------------------------------

_original_init = FuzzycError.__init__


def _init(self, diagnostics, *args, **kwargs):
    _original_init(self, diagnostics, *args, **kwargs)
    try:
        if _in_package(sys._getframe(1).f_code.co_filename):
            for d in self.diagnostics:
                loc = None
                if d.loc is not None:
                    col = getattr(d.loc, "col", None)
                    shown = d.source_line
                    caret_in_line = (shown is None or col is None
                                     or 1 <= col <= len(shown.rstrip("\r\n")) + 1)
                    loc = (bool(getattr(d.loc, "file", None)), getattr(d.loc, "line", None),
                           col, caret_in_line)
                _record("raise", "FuzzycError", d.message, loc)
    except Exception:   # noqa: BLE001 - the log must never change a test's outcome
        pass


# --- cli: error lines on stderr -----------------------------------------------------------------

ERROR_LINE = re.compile(r"^(?:(?P<where>.+?): )?error: (?P<message>.*)$")
LOCATED = re.compile(r"^(?P<file>.+?):(?P<line>\d+)(?::(?P<col>\d+))?$")


def _record_stderr(text) -> None:
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    if not text:
        return
    for line in text.split("\n"):     # not splitlines: a quoted \x1c or \x85 is in a line
        found = ERROR_LINE.match(line.rstrip("\r"))
        if not found:
            continue
        where = found.group("where")
        loc = None
        if where:
            placed = LOCATED.match(where)
            if placed:
                col = placed.group("col")
                loc = (True, int(placed.group("line")), int(col) if col else None, True)
            elif where.startswith("fuzzyc"):     # argparse: `fuzzyc check: error: ...`
                loc = None
            else:                                  # `file: error: ...` (no line)
                loc = (True, None, None, True)
        _record("cli", "stderr", found.group("message"), loc)


class _Tee:
    def __init__(self, stream):
        self._stream, self._parts = stream, []

    def write(self, text):
        self._parts.append(text)
        return self._stream.write(text)

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _wrap_main(main):
    def wrapped(*args, **kwargs):
        tee = _Tee(sys.stderr)
        sys.stderr = tee
        try:
            return main(*args, **kwargs)
        finally:
            if sys.stderr is tee:
                sys.stderr = tee._stream
            try:
                _record_stderr("".join(p if isinstance(p, str) else "" for p in tee._parts))
            except Exception:   # noqa: BLE001
                pass
    wrapped.__wrapped__ = main
    wrapped.__doc__ = main.__doc__
    return wrapped


_original_run = subprocess.run


def _run(*args, **kwargs):
    result = _original_run(*args, **kwargs)
    try:
        command = args[0] if args else kwargs.get("args")
        words = command.split() if isinstance(command, str) else [str(w) for w in command]
        # `python -m fuzzyc ...` or the console script (not gcc given a path under fuzzyc/)
        if ("-m" in words and "fuzzyc" in words) or (words and Path(words[0]).name == "fuzzyc"):
            _record_stderr(result.stderr)
    except Exception:   # noqa: BLE001
        pass
    return result


# --- api: other exceptions raised by fuzzyc that a test expects ------------------------------

_original_raises = pytest.raises


def _record_api(exc) -> None:
    if exc is None or isinstance(exc, FuzzycError):
        return
    tb = exc.__traceback__
    if tb is None:
        return
    while tb.tb_next is not None:
        tb = tb.tb_next
    if _in_package(tb.tb_frame.f_code.co_filename):
        _record("api", type(exc).__name__, str(exc).split("\n")[0], None)


class _Watch:
    """pytest.raises' context manager, which also records the exception it caught."""

    def __init__(self, manager):
        self._manager = manager

    def __enter__(self):
        __tracebackhide__ = True     # a failing test's traceback shows its own `with` line
        return self._manager.__enter__()

    def __exit__(self, kind, value, tb):
        __tracebackhide__ = True
        swallowed = self._manager.__exit__(kind, value, tb)
        if swallowed:
            try:
                _record_api(value)
            except Exception:   # noqa: BLE001
                pass
        return swallowed

    def __getattr__(self, name):
        return getattr(self._manager, name)


def _raises(*args, **kwargs):
    __tracebackhide__ = True
    result = _original_raises(*args, **kwargs)
    if isinstance(result, pytest.ExceptionInfo):
        _record_api(result.value)
        return result
    return _Watch(result)


def install() -> None:
    """Wrap the points where messages are made; called once when conftest is imported."""
    cli = importlib.import_module("fuzzyc.cli")
    cli_main = importlib.import_module("fuzzyc.cli.main")   # the module (cli.main: the function)
    FuzzycError.__init__ = _init
    if not hasattr(cli_main.main, "__wrapped__"):
        cli_main.main = cli.main = _wrap_main(cli_main.main)
    subprocess.run = _run
    pytest.raises = _raises


# --- the plugin: per-worker files, merged at the end ---------------------------------------------

def _dump(path: Path) -> None:
    records = [{"source": s, "type": t, "message": m, "loc": list(loc) if loc else None,
                "tests": sorted(tests), "drawn": sorted(tests & _drawn)}
               for (s, t, m, loc), tests in _seen.items()]
    path.write_text(json.dumps(records))


class Plugin:
    def __init__(self, config):
        self.config = config
        self.worker = hasattr(config, "workerinput")
        self.folder: Path | None = None
        self.summary: list[str] = []
        self.failed = False

    def _folder(self) -> Path:
        if self.folder is None:
            if self.worker:
                self.folder = Path(self.config.workerinput[WORKER_KEY])
            else:
                factory = getattr(self.config, "_tmp_path_factory", None)
                base = (factory.getbasetemp() if factory is not None
                        else Path(__import__("tempfile").mkdtemp()))
                self.folder = base / "error-messages"
                self.folder.mkdir(parents=True, exist_ok=True)
        return self.folder

    @pytest.hookimpl(optionalhook=True)
    def pytest_configure_node(self, node):
        node.workerinput[WORKER_KEY] = str(self._folder())

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(self, item):
        _current[0] = item.nodeid
        if item.get_closest_marker("drawn_inputs") is not None or getattr(
                getattr(item, "obj", None), "is_hypothesis_test", False):
            _drawn.add(item.nodeid)
        try:
            yield
        finally:
            _current[0] = "<between tests>"

    @pytest.hookimpl(trylast=True)
    def pytest_sessionfinish(self, session):
        try:
            if self.worker:
                _dump(self._folder() / f"{self.config.workerinput['workerid']}.json")
                return
            folder = self._folder()
            _dump(folder / "controller.json")
            records = []
            for part in sorted(folder.glob("*.json")):
                records.extend(json.loads(part.read_text()))
            out = Path(os.environ[OUT_ENV]) if os.environ.get(OUT_ENV) else (
                folder.parent / "error_messages.txt")
            self.summary, failed = report(records, out)
            if failed and _mode() == "fail":
                self.failed = True
                if session.exitstatus == 0:
                    session.exitstatus = 1
        except Exception as exc:   # noqa: BLE001 - the log must never break the run by accident
            self.summary = [f"error messages: not collected ({type(exc).__name__}: {exc})"]

    def pytest_terminal_summary(self, terminalreporter):
        if self.summary:
            terminalreporter.section("error messages", red=self.failed, bold=self.failed)
            for line in self.summary:
                terminalreporter.write_line(line)


def _kinds(count: int) -> str:
    return f"{count} kind{'s' if count != 1 else ''}"


def _mode() -> str:
    """fail (the gate), warn (list only: make explore's fresh random examples, the oracle
    targets' tests outside the gate) or off."""
    return os.environ.get(CHECK_ENV) or ("warn" if os.environ.get("FUZZYC_EXPLORE") else "fail")


def report(records: list[dict], out: Path) -> tuple[list[str], bool]:
    """Merge the records into kinds, write them to `out` (+ .json), check them against the
    reviewed list: (summary lines, whether the check failed)."""
    from tests.message_review import merge, check, render
    kinds = merge(records)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps(records))
    out.write_text(render(kinds))
    if _mode() == "off":
        return [f"{_kinds(len(kinds))} of error message: {out}"], False
    problems, unused, drawn = check(kinds, REVIEWED)
    lines = [f"{_kinds(len(kinds))} of error message ({len(problems)} problems; {len(unused)} "
             f"reviewed kinds not produced by this run; {len(drawn)} not reviewed from drawn "
             f"inputs, listed): {out}"]
    lines += problems + drawn
    return lines, bool(problems)
