"""The q15/q31 helpers that do not depend on the rule base (saturation, the rounding shift,
an input's two memberships, the t-norms) are C, in fixed_helpers.c: each header pastes them
with the template's stand-in prefixes replaced by its own, so the header stays one
self-contained file and two headers can share a translation unit.  Python writes the tables."""
from __future__ import annotations

import re
from functools import cache
from importlib import resources

# the template's stand-ins: functions (fuzzyc_fx_sat) and the macros a header defines (ONE, MF)
_STAND_IN = re.compile(r"\b(fuzzyc_fx_|FUZZYC_FX_)")
# above this line, what lets the file compile alone; below it, what a header takes
_PASTED_FROM = "/* -- pasted into each header from here -- */\n"


@cache
def _template() -> str:
    path = resources.files("fuzzyc").joinpath("backends/c_fixed/fixed_helpers.c")
    return path.read_text().split(_PASTED_FROM, 1)[1]


def helper_lines(p: str, P: str) -> list[str]:
    """The template's helpers named with prefix p (functions) and P (macros: P ONE, P MF).
    One pass, so a prefix that itself looks like a stand-in is not replaced again."""
    text = _STAND_IN.sub(lambda m: p if m.group(1).islower() else P, _template())
    return text.rstrip("\n").split("\n")


def defines(helper: str) -> bool:
    """Whether the template defines fuzzyc_fx_<helper> (the operator registry names them)."""
    return f" fuzzyc_fx_{helper}(" in _template()
