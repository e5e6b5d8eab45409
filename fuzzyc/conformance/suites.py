"""Where each suite's example files are, found at run time (nothing is copied into the repo).

- fuzzylite 6: the Debian package `fuzzylite` ships its examples (`dpkg -L fuzzylite`), every
  engine as .fll, .fcl and .fis beside the .fld reference data fuzzylite wrote from the .fll;
  `original/` holds the 5.x versions of some and is left out.
- pyfuzzylite 8: the examples inside its wheel (`.fll` + `.fld`), installed in the venv
  `.venv-pyfuzzylite` (`make .venv-pyfuzzylite`: it pins numpy < 2, so it has a venv of its own).
- Octave: the .fis files of the Debian package `octave-fuzzy-logic-toolkit`.
"""
from __future__ import annotations

import glob
import os
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

FUZZYLITE_EXAMPLES = "/usr/share/doc/fuzzylite/examples"
OCTAVE_TOOLKIT_GLOB = "/usr/share/octave/packages/fuzzy-logic-toolkit-*"
PYFUZZYLITE_VENV = os.environ.get("FUZZYC_PYFUZZYLITE_VENV", ".venv-pyfuzzylite")


@dataclass
class Suite:
    name: str
    oracle: str            # "fuzzylite" (the CLI), "pyfuzzylite" (shipped .fld), "octave"
    semantics: str         # the tool's arithmetic, see fuzzyc.formats.tool_semantics
    files: list[Path] = field(default_factory=list)
    missing: str = ""      # why the suite has no files here


def _dpkg_files(package: str) -> list[str]:
    try:
        done = subprocess.run(["dpkg", "-L", package], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return []
    return done.stdout.splitlines() if done.returncode == 0 else []


def fuzzylite_examples() -> Path | None:
    listed = [p for p in _dpkg_files("fuzzylite") if p.endswith("/examples")]
    for candidate in [*listed, FUZZYLITE_EXAMPLES]:
        if Path(candidate).is_dir():
            return Path(candidate)
    return None


def octave_toolkit() -> Path | None:
    listed = [str(Path(p).parent) for p in _dpkg_files("octave-fuzzy-logic-toolkit")
              if p.endswith("/readfis.m")]
    for candidate in [*listed, *sorted(glob.glob(OCTAVE_TOOLKIT_GLOB))]:
        if Path(candidate).is_dir():
            return Path(candidate)
    return None


def pyfuzzylite_examples(venv: str | Path = PYFUZZYLITE_VENV) -> Path | None:
    found = sorted(glob.glob(f"{venv}/lib/python*/site-packages/fuzzylite/examples"))
    return Path(found[-1]) if found else None


def suites() -> list[Suite]:
    out = []
    examples = fuzzylite_examples()
    for ext in ("fll", "fcl", "fis"):
        suite = Suite(f"fuzzylite 6 examples, .{ext}", "fuzzylite", "fuzzylite")
        if examples is None:
            suite.missing = "Debian package `fuzzylite` not installed"
        else:
            suite.files = sorted(p for p in examples.rglob(f"*.{ext}")
                                 if "original" not in p.relative_to(examples).parts)
        out.append(suite)
    suite = Suite("pyfuzzylite 8.0.6 examples, .fll", "pyfuzzylite", "pyfuzzylite")
    py_examples = pyfuzzylite_examples()
    if py_examples is None:
        suite.missing = f"no pyfuzzylite in {PYFUZZYLITE_VENV} (`make .venv-pyfuzzylite`)"
    else:
        suite.files = sorted(p for p in py_examples.rglob("*.fll")
                             if p.with_suffix(".fld").exists())
    out.append(suite)
    suite = Suite("Octave fuzzy-logic-toolkit examples, .fis", "octave", "octave")
    toolkit = octave_toolkit()
    if toolkit is None:
        suite.missing = "Debian package `octave-fuzzy-logic-toolkit` not installed"
    else:
        suite.files = sorted(toolkit.glob("*.fis"))
    out.append(suite)
    return out
