"""The reference tools, run live: the fuzzylite 6 CLI and Octave's fuzzy-logic-toolkit; and the
.fld reference data (`NAME NAME ...` header, one row of inputs then outputs per line, `nan`)."""
from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

TIMEOUT = 120


class OracleError(RuntimeError):
    """The tool refused the file or failed: its own message."""


def read_fld(path: str | Path) -> tuple[list[str], np.ndarray]:
    lines = [line.split() for line in Path(path).read_text().splitlines() if line.strip()]
    if not lines:
        raise OracleError(f"{Path(path).name} is empty")
    header, rows = lines[0], lines[1:]
    return header, np.array([[float(v) for v in row] for row in rows], dtype=float).reshape(
        len(rows), len(header))


def have_fuzzylite() -> bool:
    return shutil.which("fuzzylite") is not None


def have_octave() -> bool:
    if shutil.which("octave") is None:
        return False
    done = _octave("pkg load fuzzy-logic-toolkit; disp(42)")
    return done.returncode == 0 and "42" in done.stdout


def fuzzylite_outputs(path: Path, x: np.ndarray) -> tuple[list[str], np.ndarray]:
    """(names, values (N, I + O)): the fuzzylite CLI importing `path` (in its own format)
    evaluated at the rows of x, in sequence (one engine: lock-previous carries over rows)."""
    with tempfile.TemporaryDirectory() as tmp:
        given, got = Path(tmp) / "in.fld", Path(tmp) / "out.fld"
        given.write_text("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in x))
        done = subprocess.run(
            ["fuzzylite", "-i", str(path), "-if", path.suffix[1:].lower(), "-o", str(got),
             "-of", "fld", "-d", str(given), "-dheader", "true", "-dinputs", "true",
             "-decimals", "12"], capture_output=True, text=True, timeout=TIMEOUT)
        if done.returncode != 0 or not got.exists():
            lines = (done.stderr or done.stdout).strip().splitlines()
            raise OracleError(lines[-1] if lines else "fuzzylite failed")
        return read_fld(got)


PYFUZZYLITE_RUN = """
import sys
import numpy as np
import fuzzylite as fl
engine = fl.FllImporter().from_file(sys.argv[1])
x = np.loadtxt(sys.argv[2], ndmin=2)
for i, name in enumerate(sys.argv[4].split(",")):
    engine.input_variable(name).value = x[:, i]
engine.process()
y = [np.broadcast_to(engine.output_variable(name).value, x.shape[:1])
     for name in sys.argv[5].split(",")]
np.savetxt(sys.argv[3], np.column_stack(y), fmt="%.17g")
"""


def pyfuzzylite_python() -> Path | None:
    """The python of the venv holding pyfuzzylite 8 (it pins numpy < 2: a venv of its own)."""
    from .suites import PYFUZZYLITE_VENV
    python = Path(PYFUZZYLITE_VENV) / "bin" / "python"
    return python if python.exists() else None


def pyfuzzylite_outputs(path: Path, x: np.ndarray, inputs: list[str],
                        outputs: list[str]) -> np.ndarray:
    """(N, O): pyfuzzylite 8 importing the FLL file and processing the rows of x at once."""
    python = pyfuzzylite_python()
    if python is None:
        raise OracleError("no pyfuzzylite venv")
    with tempfile.TemporaryDirectory() as tmp:
        given, got = Path(tmp) / "x.txt", Path(tmp) / "y.txt"
        np.savetxt(given, x, fmt="%.17g")
        done = subprocess.run([str(python), "-c", PYFUZZYLITE_RUN, str(path), str(given),
                               str(got), ",".join(inputs), ",".join(outputs)],
                              capture_output=True, text=True, timeout=TIMEOUT)
        if done.returncode != 0 or not got.exists():
            lines = done.stderr.strip().splitlines()
            raise OracleError(lines[-1] if lines else "pyfuzzylite failed")
        return np.loadtxt(got, ndmin=2).reshape(x.shape[0], len(outputs))


def _octave(code: str, cwd: str | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval", code],
                          capture_output=True, text=True, timeout=TIMEOUT, cwd=cwd)


def octave_outputs(path: Path, x: np.ndarray) -> np.ndarray:
    """(N, O): Octave's `evalfis(x, readfis(path))` (101 points, its default)."""
    with tempfile.TemporaryDirectory() as tmp:
        np.savetxt(Path(tmp) / "x.txt", x, fmt="%.17g")
        fis = str(path).replace("'", "''")
        done = _octave("pkg load fuzzy-logic-toolkit; warning('off', 'all');"
                       f"fis = readfis('{fis}'); x = load('x.txt');"
                       "y = evalfis(x, fis); save('-ascii', '-double', 'y.txt', 'y');", cwd=tmp)
        out = Path(tmp) / "y.txt"
        if done.returncode != 0 or not out.exists():
            lines = [line for line in (done.stderr + done.stdout).splitlines() if "error" in line]
            raise OracleError(lines[0] if lines else "octave failed")
        return np.loadtxt(out, ndmin=2).reshape(x.shape[0], -1)
