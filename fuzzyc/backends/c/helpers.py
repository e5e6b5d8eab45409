"""The float/double helpers that do not depend on the rule base (NaN-aware min/max, clamp,
the trapezoid, the walks over M's points for centroid, bisector and mean of maximum) are C, in
real_helpers.c, pasted by c_template with the header's prefix and its real typedef."""
from __future__ import annotations

from ..c_template import pasted

TEMPLATE = "backends/c/real_helpers.c"


def helper_lines(names: list[str], p: str, P: str) -> list[str]:
    """The named sections of real_helpers.c, with prefix p (functions, and the type
    fuzzyc_real -> p + "real", the header's typedef) and P (the constants' macros)."""
    return pasted(TEMPLATE, names, "fuzzyc", p, P)
