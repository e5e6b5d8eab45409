"""Failure classes found by the harness that other branches are fixing.

Each entry: (regex over the class signature, owner, what it is). The pytest sample skips these
classes and fails on any other; `make fuzz` counts them all and names the owner. Remove an
entry when its fix lands: the sample then guards against the class coming back.
"""
from __future__ import annotations

import re

KNOWN_OPEN: list[tuple[str, str, str]] = [
    (r"codec can't decode", "robust",
     "a rule file that is not UTF-8: `cannot read FILE: 'utf-8' codec can't decode ...` without "
     "line:col (.fz through parser.load, .fll/.fcl/.fis through formats.load_any)"),
    (r"^check: IndexError at fuzzyc/parser\.py:_report", "robust",
     ".fz syntax error on a line split by \\v, \\f or U+2028: lark counts lines on \\n, "
     "str.splitlines() on all of them, so the caret's line is another line"),
    (r"^eval: UnicodeDecodeError at fuzzyc/cli/eval\.py:_run_csv", "robust",
     "eval --csv of a CSV that is not UTF-8"),
    (r"^eval: Error at fuzzyc/cli/eval\.py:_run_csv", "robust",
     "eval --csv of a CSV with a field over the csv module's limit (131072 characters)"),
    (r"^eval: TMP/input\.csv: the file is empty", "robust",
     "eval --csv of an empty CSV: the message has no line:col"),
]


def known_owner(signature: str) -> str | None:
    for pattern, owner, _what in KNOWN_OPEN:
        if re.search(pattern, signature):
            return owner
    return None
