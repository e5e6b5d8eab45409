"""Exports read back by the tools themselves: a model written as FLL, FCL or FIS by fuzzyc, read
by the fuzzylite 6 CLI (all three) or Octave's readfis/evalfis (FIS), must give fuzzyc's numbers
under that tool's semantics."""
from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import FuzzycError
from ..formats import READERS, WRITERS
from ..formats.tool_semantics import Chain
from ..semantics.model import Model
from . import oracles
from .check import TOLERANCE, random_inputs

EXPORTS = {"fuzzylite": ("fll", "fcl", "fis"), "octave": ("fis",)}


@dataclass
class RoundTrip:
    name: str
    fmt: str
    tool: str
    written: bool
    message: str = ""
    worst: float = np.nan          # max |tool - fuzzyc under the tool's semantics| / range

    @property
    def agrees(self) -> bool:
        return self.written and self.worst <= TOLERANCE


def round_trip(model: Model, name: str, fmt: str, tool: str) -> RoundTrip:
    """Write `model` as `fmt`, let `tool` evaluate the file on random inputs, compare."""
    try:
        text = WRITERS[f".{fmt}"](model, [])
    except FuzzycError as exc:
        return RoundTrip(name, fmt, tool, False, str(exc).splitlines()[0])
    rb = Chain(model)      # every rule block, in order: the file's inputs and outputs
    x = random_inputs(Path(name), rb)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{model.name}.{fmt}"
        path.write_text(text)
        try:
            if tool == "octave":
                theirs = oracles.octave_outputs(path, x)
            else:
                header, values = oracles.fuzzylite_outputs(path, x)
                theirs = values[:, len(rb.inputs):]
        except (oracles.OracleError, OSError, ValueError) as exc:
            return RoundTrip(name, fmt, tool, True, f"tool: {exc}", np.inf)
    if theirs.shape != (x.shape[0], len(rb.outputs)):
        return RoundTrip(name, fmt, tool, True, f"tool gave {theirs.shape[1]} outputs", np.inf)
    # fuzzyc's numbers for the file as written (a FIS file, say, fixes MATLAB's defaults)
    ours = Chain(READERS[f".{fmt}"](text, name)).evaluate(x, tool)
    span = np.array([v.hi - v.lo or 1.0 for v in rb.outputs])
    same_nan = np.isnan(ours) == np.isnan(theirs)
    diff = np.where(np.isnan(theirs), 0.0, np.abs(ours - theirs)) / span
    worst = float(np.nanmax(diff, initial=0.0)) if np.all(same_nan) else np.inf
    return RoundTrip(name, fmt, tool, True, "", worst)
