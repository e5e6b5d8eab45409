"""C kept as C: the C back ends' helpers that do not depend on the rule base are static .c
templates (backends/c/real_helpers.c, backends/c_fixed/fixed_helpers.c), in the manner of
nanopb's generator: Python writes the tables and the rule base's code, and pastes the helpers.

A template is a preamble that lets it compile alone, then sections, each opened by a line
`/* -- section: NAME -- */`.  A header pastes the sections it needs with the template's
stand-in prefixes replaced by its own (`fuzzyc_min` -> `NAME_min`, `FUZZYC_ONE` -> `NAME_ONE`),
so it stays one self-contained file and two headers can share a translation unit."""
from __future__ import annotations

import re
from functools import cache
from importlib import resources

_SECTION = re.compile(r"^/\* -- section: (\w+) -- \*/\n", re.M)


@cache
def sections(template: str) -> dict[str, str]:
    """The template's sections by name (template: its path inside the fuzzyc package)."""
    text = resources.files("fuzzyc").joinpath(template).read_text()
    parts = _SECTION.split(text)          # preamble, name, body, name, body, ...
    return dict(zip(parts[1::2], parts[2::2]))


def pasted(template: str, names: list[str], stand_in: str, p: str, P: str) -> list[str]:
    """The lines of the named sections, functions and types renamed from `stand_in`_ to p and
    macros from `STAND_IN`_ to P; one pass, so a prefix that itself looks like a stand-in is
    not replaced again."""
    prefix = re.compile(rf"\b({re.escape(stand_in)}_|{re.escape(stand_in.upper())}_)")
    text = "".join(sections(template)[name] for name in names)
    text = prefix.sub(lambda m: p if m.group(1).islower() else P, text)
    return text.rstrip("\n").split("\n")
