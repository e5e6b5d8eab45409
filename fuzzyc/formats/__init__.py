"""Other tools' rule-base formats: import fuzzylite FLL, IEC 61131-7 FCL and MATLAB FIS into the
model; export the model's rule base to .fz, FLL, FCL and MATLAB FIS.

Importers give the Model the .fz front end would give for the same rule base: one raw input per
rule-base input (same name), one DIRECT output `NAME_out` per rule-base output, saturated to its
range.  Whatever a file says that the model cannot carry is an error with its place; nothing is
dropped silently (defaults and settings the model replaces are recorded in `Model.notes`).
Exports write the bare rule base and return warnings naming what was left out.
"""
from __future__ import annotations

from pathlib import Path

from ..atomic import write_text
from ..errors import Diagnostic, FuzzycError
from ..model import Model
from .fcl import read_fcl, write_fcl
from .fis import read_fis, write_fis
from .fll import read_fll, write_fll
from .fz import write_fz

READERS = {".fll": read_fll, ".fcl": read_fcl, ".fis": read_fis}
WRITERS = {".fz": write_fz, ".fll": write_fll, ".fcl": write_fcl, ".fis": write_fis}

__all__ = ["load_any", "save", "read_fll", "write_fll", "read_fcl", "write_fcl", "read_fis",
           "write_fis", "write_fz", "READERS", "WRITERS"]


def load_any(path: str | Path) -> Model:
    """A model from .fz, .fll, .fcl or .fis (by extension); FuzzycError on any problem."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".fz":
        from ..parser import load
        return load(path)
    if suffix not in READERS:
        raise FuzzycError([Diagnostic(None, f"cannot read `{path}`: unknown extension "
                                            f"`{suffix}` (known: .fz .fll .fcl .fis)")])
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise FuzzycError([Diagnostic(None, f"cannot read {path}: {exc}")]) from None
    return READERS[suffix](text, str(path))


def save(model: Model, path: str | Path) -> list[str]:
    """Write the model to .fz, .fll, .fcl or .fis (by extension), atomically; returns the warnings
    (what the file does not carry).  FuzzycError when the format cannot say the rule base."""
    suffix = Path(path).suffix.lower()
    if suffix not in WRITERS:
        raise FuzzycError([Diagnostic(None, f"cannot write `{path}`: unknown extension "
                                            f"`{suffix}` (known: .fz .fll .fcl .fis)")])
    warnings: list[str] = []
    text = WRITERS[suffix](model, warnings)
    write_text(path, text)
    return warnings
