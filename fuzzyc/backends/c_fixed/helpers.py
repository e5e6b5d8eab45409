"""The q15/q31 helpers that do not depend on the rule base (saturation, the rounding shift,
an input's two memberships, the t-norms) are C, in fixed_helpers.c, pasted by c_template."""
from __future__ import annotations

from ..c_template import pasted, sections

TEMPLATE = "backends/c_fixed/fixed_helpers.c"


def helper_lines(p: str, P: str) -> list[str]:
    """The template's helpers named with prefix p (functions) and P (macros: P ONE, P MF)."""
    return pasted(TEMPLATE, ["helpers"], "fuzzyc_fx", p, P)


def defines(helper: str) -> bool:
    """Whether the template defines fuzzyc_fx_<helper> (the operator registry names them)."""
    return f" fuzzyc_fx_{helper}(" in sections(TEMPLATE)["helpers"]
