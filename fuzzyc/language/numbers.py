"""The one spelling of a number that fuzzyc reads from user text: CSV cells, NAME=VALUE,
command-line numbers and the numeric fields of rule files (docs/limits.md).

It is what C's strtod accepts for a decimal number, in ASCII, so that a value `fuzzyc eval`
reads is the value the C example (examples/c/main.c) reads: digits with an optional point
(`1`, `1.`, `.5`), an optional exponent (`1e-3`, `2E+05`), an optional sign, and strtod's words
`inf`, `infinity` and `nan` in any case.  Python's float() also takes `1_000`, full-width and
other Unicode digits (`５`) and surrounding Unicode spaces, which strtod does not: those are
refused here, never read as a different number.  Hexadecimal floats (`0x1p3`) and
`nan(...)`, which strtod also takes, are refused too.
"""
from __future__ import annotations

import numbers
import re

import numpy as np

NUMBER = re.compile(r"[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
                    r"|(?i:inf|infinity|nan))", re.ASCII)
INTEGER = re.compile(r"[+-]?[0-9]+", re.ASCII)

SPACES = " \t"     # around a number, as strtod (before) and the C example (after) skip them

SYNTAX = "digits with an optional point and exponent (1, -0.5, .5, 2e-3), inf or nan"


def parse_number(text: str) -> float | None:
    """The number `text` spells (spaces or tabs around it allowed), else None."""
    text = text.strip(SPACES)
    if NUMBER.fullmatch(text) is None:
        return None
    return float(text)


def parse_integer(text: str) -> int | None:
    """The whole number `text` spells in ASCII digits, else None (int() takes `1_000`, `５`)."""
    text = text.strip(SPACES)
    if INTEGER.fullmatch(text) is None or len(text) > 100:    # int() refuses > 4300 digits
        return None
    return int(text)


def not_a_number(text: str) -> str:
    """Why `text` is refused, shortened to a readable length."""
    shown = text if len(text) <= 40 else text[:40] + "..."
    return f"`{shown}` is not a number: write {SYNTAX}"


def real_array(name: str, value) -> np.ndarray:
    """`value` (a real number or an array of them) as a float array; ValueError naming the
    input otherwise.  np.asarray(value, dtype=float) alone takes None (as NaN), a string
    ("1.5"), a bool, a datetime64 (as its count of units) and a masked array (dropping the
    mask), and raises OverflowError for 10**400: none of them is a reading of a sensor."""
    if isinstance(value, np.ma.MaskedArray):
        return _refuse(name, "a masked array: fill it first (`.filled(np.nan)` gives NaN, "
                             "which the engine reads as no value)")
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fiu":
            return value.astype(float, copy=False)
        if value.dtype.kind == "O":
            for item in value.flat:      # the first element that is no real number says why
                _scalar(name, item)
            return np.array([float(item) for item in value.flat]).reshape(value.shape)
        return _refuse(name, f"an array of dtype {value.dtype}, not of real numbers")
    if isinstance(value, (list, tuple)):
        return real_array(name, np.array(value, dtype=object) if _ragged_or_mixed(value)
                          else np.asarray(value))
    return np.asarray(_scalar(name, value))


def _scalar(name: str, value) -> float:
    if value is None:
        _refuse(name, "None, not a number")
    if isinstance(value, (bool, np.bool_)):
        _refuse(name, f"the boolean {value}, not a number")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return float(real_array(name, value))
    # timedelta64 is a numpy integer type: said apart, with datetime64
    if isinstance(value, (np.datetime64, np.timedelta64)) or not isinstance(
            value, (numbers.Real, np.integer, np.floating)):
        shown = repr(value) if len(repr(value)) <= 40 else repr(value)[:40] + "..."
        _refuse(name, f"{shown} of type {type(value).__name__}: give a real number (int, "
                      "float, a numpy integer or float) or an array of them")
    try:
        return float(value)
    except OverflowError:
        _refuse(name, f"an integer of {len(str(abs(value)))} digits, too large for a float "
                      "(at most about 1.8e308)")


def _ragged_or_mixed(items) -> bool:
    """True when np.asarray would not make a numeric array of `items` (or guess a type that
    hides what is in it: [1, None] is an object array, [1, "2"] a string array)."""
    return not all(isinstance(item, (numbers.Real, np.integer, np.floating))
                   and not isinstance(item, (bool, np.bool_, np.timedelta64)) for item in items)


def _refuse(name: str, why: str):
    raise ValueError(f"input `{name}`: {why}")
