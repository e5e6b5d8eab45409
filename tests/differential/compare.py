"""fuzzyc's numbers for one file under its tool's semantics, against the tool's, and the file's
class: refused (a FuzzycError), crashed (any other exception: a bug), agree or disagree.

fuzzyc evaluates as `fuzzyc eval FILE --semantics TOOL` does for a whole model: the rule blocks
in order (tool_semantics.Chain), compared with the tool per output relative to the output's
range: 1e-3 for Mamdani outputs (sampled integrals), 1e-6 for Takagi-Sugeno ones.  Where the tool
says NaN, fuzzyc must say NaN too, and the other way round."""
from __future__ import annotations

import traceback
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any
from fuzzyc.formats.tool_semantics import Chain

MAMDANI_TOLERANCE = 1e-3
SUGENO_TOLERANCE = 1e-6
# the tool, the semantics fuzzyc evaluates its files with, and the generator's format
TOOLS = {"pyfuzzylite-fll": ("pyfuzzylite", "pyfuzzylite", "fll"),
         "fuzzylite-fll": ("fuzzylite", "fuzzylite", "fll6"),
         "fuzzylite-fcl": ("fuzzylite", "fuzzylite", "fcl"),
         "octave-fis": ("octave", "octave", "fis")}


@dataclass
class Ours:
    """fuzzyc's reading of a file: y (N, O) or why there is none."""
    status: str                  # "imported", "refused", "crashed"
    message: str = ""
    y: np.ndarray | None = None
    inputs: list[str] = field(default_factory=list)
    outputs: list[str] = field(default_factory=list)


def ours(path: Path, x: np.ndarray, semantics: str) -> Ours:
    try:
        chain = Chain(load_any(path))
    except FuzzycError as exc:
        return Ours("refused", str(exc).splitlines()[0])
    except Exception:       # noqa: BLE001 -- any other exception is the bug being hunted
        return Ours("crashed", _last_frame())
    got = Ours("imported", inputs=[v.name for v in chain.inputs],
               outputs=[v.name for v in chain.outputs])
    try:
        with np.errstate(all="ignore"):
            got.y = chain.evaluate(x, semantics)
    except FuzzycError as exc:
        got.status, got.message = "refused", str(exc).splitlines()[0]
    except Exception:       # noqa: BLE001
        got.status, got.message = "crashed", _last_frame()
    return got


def _last_frame() -> str:
    """`Type: message (file:line)` of the innermost frame in fuzzyc: one line per crash kind."""
    lines = traceback.format_exc().strip().splitlines()
    frames = [line.strip() for line in lines if line.strip().startswith('File "')
              and "/fuzzyc/" in line]
    where = frames[-1].split("/fuzzyc/")[-1].replace('", line ', ":").split(",")[0] \
        if frames else "?"
    return f"{lines[-1][:200]} ({where})"


def tolerances(spans: np.ndarray, sugeno: list[bool]) -> np.ndarray:
    return np.where(sugeno, SUGENO_TOLERANCE, MAMDANI_TOLERANCE) * np.where(spans > 0, spans, 1)


def worst(ours_y: np.ndarray, tool_y: np.ndarray, tolerance: np.ndarray) -> float:
    """The largest |ours - tool| / tolerance over the rows (> 1: disagree); a NaN on one side
    only is infinitely far, equal values (the same infinity, NaN and NaN) 0 apart."""
    with np.errstate(invalid="ignore"):
        same = (ours_y == tool_y) | (np.isnan(ours_y) & np.isnan(tool_y))
        diff = np.where(same, 0.0, np.abs(ours_y - tool_y) / tolerance)
    return float(np.max(np.where(np.isnan(diff), np.inf, diff), initial=0.0))


def disagreeing_rows(ours_y: np.ndarray, tool_y: np.ndarray, tolerance: np.ndarray) -> np.ndarray:
    return np.flatnonzero([worst(a[None], b[None], tolerance) > 1
                           for a, b in zip(ours_y, tool_y)])
