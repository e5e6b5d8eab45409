"""One example file: imported by fuzzyc, evaluated by fuzzyc (exact, and under the tool's
semantics) and by the tool, compared output by output relative to the output's range."""
from __future__ import annotations

import re
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import FuzzycError
from ..formats import load_any
from ..formats.tool_semantics import Chain
from . import oracles
from .suites import Suite

TOLERANCE = 1e-6          # of the output's range
RANDOM_ROWS = 200
MAX_REFERENCE_ROWS = 1024
RESOLUTION = re.compile(r"^OutputVariable:\s*(\S+)|defuzzifier:\s*(?:Centroid|Bisector|"
                        r"MeanOfMaximum|SmallestOfMaximum|LargestOfMaximum)\s+(\d+)", re.M)


@dataclass
class FileResult:
    path: Path
    imported: bool
    message: str = ""          # why it was refused, or why it could not be compared
    compared: bool = False
    rows: int = 0
    worst_tool: float = np.nan     # max |ours under the tool's semantics - tool| / range
    worst_exact: float = np.nan    # max |ours exact - tool| / range

    @property
    def agrees(self) -> bool:
        return self.compared and self.worst_tool <= TOLERANCE


def check(path: Path, suite: Suite, live: bool = True) -> FileResult:
    try:
        model = load_any(path)
    except FuzzycError as exc:
        first = str(exc).splitlines()[0]
        return FileResult(path, False, first)
    rb = Chain(model)
    result = FileResult(path, True)
    try:
        x, reference = _reference(path, suite, rb, live)
    except (oracles.OracleError, OSError, ValueError) as exc:
        result.message = f"tool: {exc}"
        return result
    ours_tool = rb.evaluate(x, suite.semantics, _resolution(path))
    ours_exact = rb.evaluate(x)
    # relative to the output's range; absolute for an empty range (a Sugeno output's [0, 0])
    span = np.array([v.hi - v.lo or 1.0 for v in rb.outputs])
    tool_nan = np.isnan(reference)
    # Where the tool says NaN (nothing fired, fuzzylite's default nan), ours must say so too.
    nan_mismatch = np.any(tool_nan != np.isnan(ours_tool))
    result.compared, result.rows = True, x.shape[0]
    result.worst_tool = np.inf if nan_mismatch else _worst(ours_tool, reference, span)
    result.worst_exact = _worst(ours_exact, reference, span)
    return result


def _worst(ours: np.ndarray, reference: np.ndarray, span: np.ndarray) -> float:
    """max |ours - reference| / span over the rows where the tool gives a number; equal values
    (the same infinity, pyfuzzylite's Tsukamoto) are 0 apart, a NaN of ours is infinitely far."""
    with np.errstate(invalid="ignore"):
        diff = np.where(np.isnan(reference) | (ours == reference), 0.0,
                        np.abs(ours - reference)) / span
    return float(np.max(np.where(np.isnan(diff), np.inf, diff), initial=0.0))


def _resolution(path: Path) -> dict[str, int]:
    """Each output's own sampling resolution (FLL `Centroid 200`); the tool's default for the
    others."""
    text = path.read_text(errors="replace") if path.suffix == ".fll" else ""
    found, output = {}, ""
    for name, points in RESOLUTION.findall(text):
        output = name or output
        if points:
            found[output] = int(points)
    return found


def random_inputs(path: Path, rb) -> np.ndarray:
    rng = np.random.default_rng(zlib.crc32(path.name.encode()))
    lo = np.array([v.lo for v in rb.inputs])
    hi = np.array([v.hi for v in rb.inputs])
    return lo + (hi - lo) * rng.random((RANDOM_ROWS, len(rb.inputs)))


def _reference(path: Path, suite: Suite, rb, live: bool) -> tuple[np.ndarray, np.ndarray]:
    """(x (N, I) in fuzzyc's input order, the tool's y (N, O) in fuzzyc's output order)."""
    inputs = [v.name for v in rb.inputs]
    outputs = [v.name for v in rb.outputs]
    fld = path.with_suffix(".fld")
    if suite.oracle == "octave":
        if not (live and oracles.have_octave()):
            raise oracles.OracleError("octave with fuzzy-logic-toolkit not installed")
        x = random_inputs(path, rb)
        return x, oracles.octave_outputs(path, x)
    shipped = oracles.read_fld(fld) if fld.exists() else None
    tool = {"fuzzylite": oracles.have_fuzzylite,
            "pyfuzzylite": lambda: oracles.pyfuzzylite_python() is not None}[suite.oracle]
    if live and tool():
        x = random_inputs(path, rb)
        if shipped is not None:
            x = np.vstack([_columns(*shipped, inputs, fld)[:MAX_REFERENCE_ROWS], x])
        if suite.oracle == "pyfuzzylite":
            return x, oracles.pyfuzzylite_outputs(path, x, inputs, outputs)
        return x, _columns(*oracles.fuzzylite_outputs(path, x), outputs, path)
    if shipped is None:
        raise oracles.OracleError("no live tool and no .fld reference data")
    return _columns(*shipped, inputs, fld), _columns(*shipped, outputs, fld)


def _columns(header: list[str], values: np.ndarray, names: list[str], where: Path) -> np.ndarray:
    missing = [n for n in names if n not in header]
    if missing:
        raise ValueError(f"{where.name} has no column {', '.join(missing)}")
    return values[:, [header.index(n) for n in names]]
