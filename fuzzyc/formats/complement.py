"""A term's complement as a formula of x: what a negated FIS consequent concludes in a Mamdani
system (the Octave toolkit's eval_rules_mamdani.m evaluates the consequent's membership
function with the rule's hedge and not flag, evalmf_private.m: y = mu(x) ^ hedge, then
1 - y, and applies the implication to that set).  The model has no negated conclusion, so the
FIS reader gives such a rule a further output term, `1 - mu(x)^p` written as a Function term
(fuzzylite's formula language, `fuzzyc.engine.formula`), built here from the term's numbers,
never from file text.  Each formula is the model's own membership function of that kind
(`fuzzyc.semantics.shape_functions`), piecewise parts written with the comparison functions
(`gt(x, a)` is 1 where x > a, else 0)."""
from __future__ import annotations

from ..semantics.model import TermKind


def _n(value: float) -> str:
    return f"({float(value)!r})"


def _sig(centre: float, slope: float) -> str:
    return f"1 / (1 + exp(-{_n(slope)} * (x - {_n(centre)})))"


def _gauss(mean: float, sigma: float) -> str:
    return f"exp(-((x - {_n(mean)}) ^ 2) / (2 * {_n(sigma)} ^ 2))"


def _s(s: float, e: float) -> str:
    if s == e:                  # a step: its branches below would divide 0 by 0 at x = s
        return f"gt(x, {_n(s)})"
    mid, w = 0.5 * (s + e), e - s
    return (f"(gt(x, {_n(s)}) * le(x, {_n(mid)}) * 2 * ((x - {_n(s)}) / {_n(w)}) ^ 2"
            f" + gt(x, {_n(mid)}) * lt(x, {_n(e)}) * (1 - 2 * ((x - {_n(e)}) / {_n(w)}) ^ 2)"
            f" + ge(x, {_n(e)}))")


def _z(s: float, e: float) -> str:
    if s == e:
        return f"le(x, {_n(s)})"
    mid, w = 0.5 * (s + e), e - s
    return (f"(le(x, {_n(s)})"
            f" + gt(x, {_n(s)}) * lt(x, {_n(mid)}) * (1 - 2 * ((x - {_n(s)}) / {_n(w)}) ^ 2)"
            f" + ge(x, {_n(mid)}) * lt(x, {_n(e)}) * 2 * ((x - {_n(e)}) / {_n(w)}) ^ 2)")


def _trapezoid(a: float, b: float, c: float, d: float) -> str:
    rise = f"ge(x, {_n(b)})" if a == b else f"min(1, max(0, (x - {_n(a)}) / {_n(b - a)}))"
    fall = f"le(x, {_n(c)})" if c == d else f"min(1, max(0, ({_n(d)} - x) / {_n(d - c)}))"
    return f"min({rise}, {fall})"


def membership_formula(kind: TermKind, params) -> str | None:
    """The membership of a term of `kind` with the model's params (4,) as formula text, or
    None for a kind written here in no formula (the caller refuses it)."""
    a, b, c, d = (float(p) for p in params)
    finite = all(abs(p) != float("inf") for p in (a, b, c, d))
    if kind == TermKind.TRAPEZOID and finite:
        return _trapezoid(a, b, c, d)
    if kind == TermKind.GAUSSIAN:
        return _gauss(a, b)
    if kind == TermKind.BELL:
        return f"1 / (1 + abs((x - {_n(a)}) / {_n(b)}) ^ (2 * {_n(c)}))"
    if kind == TermKind.SIGMOID:
        return _sig(a, b)
    if kind == TermKind.SSHAPE and a <= b:
        return _s(a, b)
    if kind == TermKind.ZSHAPE and a <= b:
        return _z(a, b)
    if kind == TermKind.PISHAPE and a <= b and c <= d:
        return f"{_s(a, b)} * {_z(c, d)}"
    if kind == TermKind.SIGMOID_DIFFERENCE:       # (c1, a1, a2, c2), fuzzylite's |difference|
        return f"abs({_sig(a, b)} - {_sig(d, c)})"
    if kind == TermKind.SIGMOID_PRODUCT:
        return f"{_sig(a, b)} * {_sig(d, c)}"
    if kind == TermKind.GAUSSIAN_PRODUCT:         # (m1, s1, m2, s2): flat between the means
        return (f"(lt(x, {_n(a)}) * {_gauss(a, b)} + ge(x, {_n(a)}))"
                f" * (gt(x, {_n(c)}) * {_gauss(c, d)} + le(x, {_n(c)}))")
    return None


def complement_formula(kind: TermKind, params, power: float = 1.0) -> str | None:
    """1 - mu(x)^power as formula text (power 1: no hedge), or None (`membership_formula`)."""
    mu = membership_formula(kind, params)
    if mu is None:
        return None
    return f"1 - ({mu})" if power == 1.0 else f"1 - ({mu}) ^ {_n(power)}"
