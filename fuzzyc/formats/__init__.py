"""Other tools' rule-base formats: import fuzzylite FLL, IEC 61131-7 FCL and MATLAB FIS into the
model; export the model's rule base to .fz, FLL, FCL and MATLAB FIS.

Importers give the Model the .fz front end would give for the same rule base: one raw input per
rule-base input (same name), one DIRECT output `NAME_out` per rule-base output, saturated to its
range (`NAME_out2`, ... when the file has a `NAME_out` of its own: model.chain_output_names).  Whatever a file says that the model cannot carry is an error with its place; nothing is
dropped silently (defaults and settings the model replaces are recorded in `Model.notes`).
Exports write the bare rule base and return warnings naming what was left out.
"""
from __future__ import annotations

import re
from pathlib import Path

from ..atomic import write_text
from ..errors import Diagnostic, FuzzycError
from ..language.limits import check_model, read_rule_file
from ..semantics.model import Model
from .fcl import read_fcl, write_fcl
from .fis import read_fis, write_fis
from .fll import read_fll, write_fll
from .fz import write_fz

READERS = {".fll": read_fll, ".fcl": read_fcl, ".fis": read_fis}
BLOCK_SEPARATOR = "::"   # FILE.fcl::NAME chooses one FUNCTION_BLOCK
WRITERS = {".fz": write_fz, ".fll": write_fll, ".fcl": write_fcl, ".fis": write_fis}

__all__ = ["load_any", "split_block", "absolute_ref", "save", "read_fll", "write_fll",
           "read_fcl", "write_fcl", "read_fis", "write_fis", "write_fz", "READERS", "WRITERS"]


def load_any(path: str | Path) -> Model:
    """A model from .fz, .fll, .fcl or .fis (by extension); FuzzycError on any problem.
    `FILE.fcl::NAME` reads the FUNCTION_BLOCK named NAME of a file that has several."""
    path, block = split_block(path)
    suffix = path.suffix.lower()
    if block is not None and suffix != ".fcl":
        raise FuzzycError([Diagnostic(None, f"`{path}::{block}`: only an .fcl file has named "
                                            "blocks to choose with `::NAME`")])
    if suffix == ".fz":
        from ..language.parser import load
        return load(path)
    if suffix not in READERS:
        raise FuzzycError([Diagnostic(None, f"cannot read `{path}`: unknown extension "
                                            f"`{suffix}` (known: .fz .fll .fcl .fis)")])
    text = read_rule_file(path)
    model = (read_fcl(text, str(path), block) if block is not None
             else READERS[suffix](text, str(path)))
    check_model(model)
    return model


def split_block(ref: str | Path) -> tuple[Path, str | None]:
    """`FILE.fcl::NAME` -> (FILE.fcl, NAME); anything else -> (the path, None).

    `::` as in pytest's node ids: it cannot occur in an FCL name, is rare in file names, and
    unlike a single `:` does not meet a Windows drive letter.  A `::` followed by what is not a
    name (`a::b/c.fcl`) is left in the path."""
    text = str(ref)
    head, sep, name = text.rpartition(BLOCK_SEPARATOR)
    if not sep:
        return Path(text), None
    if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        return Path(head), name
    if head.lower().endswith(".fcl"):
        raise FuzzycError([Diagnostic(None, f"`{text}`: after `::` comes a FUNCTION_BLOCK "
                                            f"name (letters, digits, _), not `{name}`")])
    return Path(text), None   # `::` inside a folder name: a plain (missing) path


def absolute_ref(ref: str | Path) -> str:
    """FILE made absolute (a scenario resolves a relative one in its rulebases folder), keeping
    a `::NAME` block choice."""
    path, block = split_block(ref)
    try:
        return str(path.resolve()) + ("" if block is None else f"::{block}")
    except ValueError as exc:       # a NUL in the name
        raise FuzzycError([Diagnostic(None, f"cannot read {path}: {exc}")]) from None


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
