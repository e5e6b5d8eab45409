"""The `.fz` round trip of a random rule base (issue 28: every file that imports converts to
`.fz` and reads back with the same numbers under every semantics): the imported model written
by `write_fz`, parsed back, and both evaluated (tool_semantics.Chain) at the generator's points
under each semantics; equal means bit-identical, NaN and NaN, or within 1e-12 of the value's
magnitude (at least 1).  A model the writer refuses is `refused`, with the writer's message
(each such construct is listed in docs/formats.md)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fuzzyc.errors import FuzzycError
from fuzzyc.formats import write_fz
from fuzzyc.formats.tool_semantics import SEMANTICS, Chain
from fuzzyc.language.parser import parse
from fuzzyc.semantics.model import Model

TOLERANCE = 1e-12


@dataclass
class RoundTrip:
    status: str          # same, refused (by the writer), unreadable, differs, crashed
    message: str = ""


def same_numbers(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return (a == b) | (np.isnan(a) & np.isnan(b)) | \
            (np.abs(a - b) <= TOLERANCE * np.maximum(1.0, np.abs(a)))


def fz_round_trip(model: Model, x: np.ndarray, name: str = "roundtrip.fz") -> RoundTrip:
    """`model` (imported) through .fz and back, compared at the rows x under every semantics
    that gives `model` numbers."""
    try:
        text = write_fz(model)
    except FuzzycError as exc:
        return RoundTrip("refused", str(exc).splitlines()[0])
    try:
        back = parse(text, name)
    except FuzzycError as exc:
        return RoundTrip("unreadable", str(exc).splitlines()[0])
    for semantics in SEMANTICS:
        try:
            with np.errstate(all="ignore"):
                want = Chain(model).evaluate(x, semantics)
        except FuzzycError:
            continue          # a semantics that refuses the model (a tool's missing behaviour)
        try:
            with np.errstate(all="ignore"):
                got = Chain(back).evaluate(x, semantics)
        except FuzzycError as exc:
            return RoundTrip("differs", f"{semantics}: the .fz model is refused: "
                                        f"{str(exc).splitlines()[0]}")
        except Exception as exc:    # noqa: BLE001 -- a crash is a finding
            return RoundTrip("crashed", f"{semantics}: {type(exc).__name__}: {exc}")
        if got.shape != want.shape:
            return RoundTrip("differs", f"{semantics}: {got.shape[1]} outputs, not "
                                        f"{want.shape[1]}")
        bad = ~same_numbers(want, got)
        if bad.any():
            r, o = (int(v[0]) for v in np.nonzero(bad))
            return RoundTrip("differs", f"{semantics}: output {o} at row {r}: {want[r, o]!r} "
                                        f"imported, {got[r, o]!r} through .fz")
    return RoundTrip("same")
