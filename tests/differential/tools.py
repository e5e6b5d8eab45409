"""The tools, live, on many files at once: `run(tool, jobs)` with jobs = [(path, x, inputs,
outputs)] -> per job the tool's y (N, O) in the given output order, or an OracleError.

pyfuzzylite and Octave start slowly (a second or more), so each takes every job in one process
(pyfuzzylite: the loop of fuzzyc.conformance.oracles' PYFUZZYLITE_RUN; Octave: `evalfis` per file
inside try/catch).  The fuzzylite CLI starts fast and runs per file through
fuzzyc.conformance.oracles.fuzzylite_outputs."""
from __future__ import annotations

import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from fuzzyc.conformance import oracles
from fuzzyc.conformance.oracles import OracleError

TIMEOUT_PER_JOB = 20
ROOT = Path(__file__).resolve().parents[2]


def pyfuzzylite_python() -> Path | None:
    """The venv's python as the conformance suite finds it, or the checkout's venv (this
    harness runs from tests/, where the relative default does not point)."""
    python = ROOT / ".venv-pyfuzzylite" / "bin" / "python"
    return oracles.pyfuzzylite_python() or (python if python.exists() else None)

PYFUZZYLITE_BATCH = """
import json, sys, traceback
import numpy as np
import fuzzylite as fl
for job in json.load(open(sys.argv[1])):
    try:
        engine = fl.FllImporter().from_file(job["path"])
        x = np.loadtxt(job["x"], ndmin=2)
        for i, name in enumerate(job["inputs"]):
            engine.input_variable(name).value = x[:, i]
        engine.process()
        y = [np.broadcast_to(engine.output_variable(n).value, x.shape[:1]).astype(float)
             for n in job["outputs"]]
        np.savetxt(job["y"], np.column_stack(y), fmt="%.17g")
    except Exception as exc:
        open(job["y"] + ".err", "w").write(f"{type(exc).__name__}: {exc}")
"""

OCTAVE_BATCH = """
pkg load fuzzy-logic-toolkit; warning('off', 'all');
jobs = strsplit(fileread('jobs.txt'), "\\n");
for k = 1:numel(jobs)
  if isempty(jobs{k}) continue; end
  parts = strsplit(jobs{k}, "\\t");
  try
    fis = readfis(parts{1}); x = load(parts{2});
    try
      y = evalfis(x, fis);
    catch err
      % evalfis fails the whole matrix for one row it cannot do (an empty Sugeno aggregate):
      % each row alone, NaN and the row's number in .rows where that row fails too
      y = NaN(rows(x), numel(fis.output)); failed = fopen([parts{3} '.rows'], 'w');
      for r = 1:rows(x)
        try
          y(r, :) = evalfis(x(r, :), fis);
        catch e2
          fprintf(failed, '%d\\t%s\\n', r, e2.message);
        end
      end
      fclose(failed);
    end
    save('-ascii', '-double', parts{3}, 'y');
  catch err
    f = fopen([parts{3} '.err'], 'w'); fprintf(f, '%s', err.message); fclose(f);
  end
end
"""


class RowsFailed(OracleError):
    """The tool failed on the whole input matrix and on these rows alone; `y` holds the other
    rows' outputs (NaN on the failed rows)."""

    def __init__(self, message: str, y: np.ndarray, rows: np.ndarray):
        super().__init__(message)
        self.y, self.rows = y, rows


def available(tool: str) -> str | None:
    """None when the tool runs here, else why not."""
    if tool == "pyfuzzylite":
        return None if pyfuzzylite_python() else "no pyfuzzylite venv " \
            "(make .venv-pyfuzzylite)"
    if tool == "fuzzylite":
        return None if oracles.have_fuzzylite() else "no fuzzylite CLI"
    return None if oracles.have_octave() else "no octave with the fuzzy-logic-toolkit"


def run(tool: str, jobs: list[tuple[Path, np.ndarray, list[str], list[str]]]) \
        -> list[np.ndarray | OracleError]:
    if not jobs:
        return []
    if tool == "fuzzylite":
        return [_fuzzylite(*job) for job in jobs]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for k, (_, x, _, _) in enumerate(jobs):
            np.savetxt(folder / f"x{k}.txt", np.atleast_2d(x), fmt="%.17g")
        timeout = 60 + TIMEOUT_PER_JOB * len(jobs)
        try:
            if tool == "pyfuzzylite":
                _pyfuzzylite(jobs, folder, timeout)
            else:
                _octave(jobs, folder, timeout)
        except subprocess.TimeoutExpired:
            pass   # the files it did finish stay; the rest are errors below
        return [_result(folder / f"y{k}.txt", x.shape[0], len(outs))
                for k, (_, x, _, outs) in enumerate(jobs)]


def _fuzzylite(path: Path, x: np.ndarray, inputs: list[str], outputs: list[str]):
    try:
        header, values = oracles.fuzzylite_outputs(path, x)
    except (OracleError, subprocess.TimeoutExpired) as exc:
        return OracleError(str(exc))
    missing = [n for n in outputs if n not in header]
    if missing:
        return OracleError(f"no column {missing}")
    return values[:, [header.index(n) for n in outputs]]


def _pyfuzzylite(jobs, folder: Path, timeout: float) -> None:
    manifest = [{"path": str(p), "x": str(folder / f"x{k}.txt"), "inputs": ins,
                 "outputs": outs, "y": str(folder / f"y{k}.txt")}
                for k, (p, _, ins, outs) in enumerate(jobs)]
    (folder / "jobs.json").write_text(json.dumps(manifest))
    subprocess.run([str(pyfuzzylite_python()), "-c", PYFUZZYLITE_BATCH,
                    str(folder / "jobs.json")], capture_output=True, text=True,
                   timeout=timeout)


def _octave(jobs, folder: Path, timeout: float) -> None:
    (folder / "jobs.txt").write_text("".join(
        f"{Path(p).resolve()}\tx{k}.txt\ty{k}.txt\n" for k, (p, _, _, _) in enumerate(jobs)))
    subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval",
                    OCTAVE_BATCH], capture_output=True, text=True, timeout=timeout, cwd=folder)


def _result(path: Path, rows: int, columns: int) -> np.ndarray | OracleError:
    error = path.with_name(path.name + ".err")
    if error.exists():
        return OracleError(error.read_text().strip().splitlines()[0] if error.read_text()
                           .strip() else "failed")
    if not path.exists():
        return OracleError("the tool gave no output (crashed or timed out)")
    try:
        y = np.loadtxt(path, ndmin=2).reshape(rows, columns)
    except ValueError as exc:
        return OracleError(f"unreadable output: {exc}")
    failed = path.with_name(path.name + ".rows")
    if not failed.exists():
        return y
    lines = [line.split("\t", 1) for line in failed.read_text().splitlines() if line]
    rows_failed = [int(r) - 1 for r, _ in lines]
    if not lines:
        return y
    if len(rows_failed) == rows:
        return OracleError(lines[0][1])
    return RowsFailed(lines[0][1], y, np.array(rows_failed, dtype=int))
