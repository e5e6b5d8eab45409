"""Superlevel sets {x : mu(x) >= lam} of the quasi-concave and monotone shapes, in closed
form: one closed interval (lo, hi), or None when empty.  `strict` asks for {mu > lam}, given
as its closure's end points.  The caller has handled lam <= 0 (everything) and lam > 1.
"""
from __future__ import annotations

import numpy as np

INF = np.inf


def trapezoid(p, lam: float, strict: bool):
    a, b, c, d = p
    lo = -INF if np.isneginf(a) else a + lam * (b - a)
    hi = INF if np.isposinf(d) else d - lam * (d - c)
    return (lo, hi) if lo <= hi else None


def singleton(p, lam: float, strict: bool):
    a = p[0]
    return None if strict and lam >= 1 else ((a, a) if lam > 0 else (-INF, INF))


def gaussian(p, lam: float, strict: bool):
    a, b = p[0], p[1]
    half = abs(b) * np.sqrt(-2.0 * np.log(lam)) if lam > 0 else INF
    return (a - half, a + half)


def bell(p, lam: float, strict: bool):
    a, b, c = p[0], p[1], p[2]
    half = abs(b) * (1.0 / lam - 1.0) ** (1.0 / (2.0 * c)) if lam > 0 else INF
    return (a - half, a + half)


def sigmoid(p, lam: float, strict: bool):
    """mu = 1/(1+exp(-s(x-c))) never reaches 1."""
    a, b = p[0], p[1]
    if lam >= 1:
        return None
    edge = a + np.log(lam / (1.0 - lam)) / b if lam > 0 else -INF * np.sign(b)
    return (edge, INF) if b > 0 else (-INF, edge)
