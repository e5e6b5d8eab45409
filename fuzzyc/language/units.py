"""Units as products of named atoms with integer powers ("mm^2/min" = {mm: 2, min: -1}).

The checker is deliberately simple: atoms are compared by name, with no conversion between
kHz and Hz. A quantity with no declared unit (a bare number, an undeclared signal) is
"unknown" and adapts to whatever it meets, so only two *declared* units can clash.
"""
from __future__ import annotations

from typing import Iterable

Unit = tuple[tuple[str, int], ...]  # sorted (atom, power) pairs; () is dimensionless

DIMENSIONLESS: Unit = ()


def make(pairs: Iterable[tuple[str, int]]) -> Unit:
    powers: dict[str, int] = {}
    for atom, power in pairs:
        powers[atom] = powers.get(atom, 0) + power
    return tuple(sorted((a, p) for a, p in powers.items() if p != 0))


def multiply(a: Unit | None, b: Unit | None, sign: int = 1) -> Unit | None:
    """a * b (sign=1) or a / b (sign=-1); unknown when either side is: a gain declared
    without a unit may hold any (0.25 per kHz), so a scaled error `(Yr1 - f) * GE1` is not in
    kHz (the plots labelled `e1 [kHz]` on [-1, 1]). Declare the gain's unit (`kHz^-1`) to have
    the product's checked."""
    if a is None or b is None:
        return None
    return make(list(a or ()) + [(atom, sign * p) for atom, p in (b or ())])


def power(a: Unit | None, exponent: int) -> Unit | None:
    return None if a is None else make((atom, p * exponent) for atom, p in a)


def format_unit(u: Unit | None) -> str:
    if u is None:
        return "no unit"
    if not u:
        return "dimensionless"
    num = [a if p == 1 else f"{a}^{p}" for a, p in u if p > 0]
    if not num:     # `kHz^-1`, not `1/kHz`: the text reads back as a unit (`param G = 2 kHz^-1`)
        return "*".join(f"{a}^{p}" for a, p in u)
    den = [a if p == -1 else f"{a}^{-p}" for a, p in u if p < 0]
    return "*".join(num) + ("/" + "/".join(den) if den else "")


# Time units the language converts to seconds (period, loop durations, within/by clauses).
SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "min": 60.0, "h": 3600.0}
