"""Derivatives of the term shapes' memberships with respect to their parameters, analytic.

Each takes x and params p (T, 4), broadcasting like the membership functions, and returns
d mu / d p as (..., 4) (the last axis the parameter; unused parameters 0).  At a kink (a
trapezoid's corner, where two pieces meet) the derivative of the piece the membership
function takes there is returned; infinite parameters (shoulders) have derivative 0.
Shapes that are step functions (singleton, binary), point lists and formulas have none: the
registry says None for them.
"""
from __future__ import annotations

import numpy as np


def _stack(*columns) -> np.ndarray:
    shape = np.broadcast(*columns).shape
    return np.stack([np.broadcast_to(c, shape) for c in columns], axis=-1)


def _zero(x, p) -> np.ndarray:
    return np.zeros(np.broadcast(x, p[:, 0]).shape)


def d_trapezoid(x, p) -> np.ndarray:
    a, b, c, d = p[:, 0], p[:, 1], p[:, 2], p[:, 3]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        on_rise = np.isfinite(a) & (x > a) & (x < b)
        on_fall = np.isfinite(d) & (x > c) & (x < d)
        rise = np.where(on_rise, (x - a) / (b - a), 1.0)
        fall = np.where(on_fall, (d - x) / (d - c), 1.0)
        rising = on_rise & (rise < fall)        # min(rise, fall) takes the rise
        falling = on_fall & ~rising
        da = np.where(rising, (x - b) / (b - a) ** 2, 0.0)
        db = np.where(rising, -(x - a) / (b - a) ** 2, 0.0)
        dc = np.where(falling, (d - x) / (d - c) ** 2, 0.0)
        dd = np.where(falling, (x - c) / (d - c) ** 2, 0.0)
    return _stack(da, db, dc, dd)


def _gauss(x, mean, sigma):
    g = np.exp(-((x - mean) ** 2) / (2.0 * sigma ** 2))
    return g, g * (x - mean) / sigma ** 2, g * (x - mean) ** 2 / sigma ** 3


def d_gaussian(x, p) -> np.ndarray:
    _, dm, ds = _gauss(x, p[:, 0], p[:, 1])
    zero = _zero(x, p)
    return _stack(dm, ds, zero, zero)


def d_bell(x, p) -> np.ndarray:
    c, w, b = p[:, 0], p[:, 1], p[:, 2]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        z = (x - c) / w
        u = np.abs(z) ** (2.0 * b)
        f = 1.0 / (1.0 + u)
        off = z != 0
        dc = np.where(off, f * f * 2.0 * b * u / (z * w), 0.0)
        dw = np.where(off, f * f * 2.0 * b * u / w, 0.0)
        db = np.where(off, -f * f * 2.0 * u * np.log(np.abs(z)), 0.0)
    return _stack(dc, dw, db, _zero(x, p))


def _sig(x, center, slope):
    with np.errstate(over="ignore"):
        s = 1.0 / (1.0 + np.exp(-slope * (x - center)))
    return s, -slope * s * (1.0 - s), (x - center) * s * (1.0 - s)   # value, d/center, d/slope


def d_sigmoid(x, p) -> np.ndarray:
    _, dc, dk = _sig(x, p[:, 0], p[:, 1])
    zero = _zero(x, p)
    return _stack(dc, dk, zero, zero)


def _s_pieces(x, s, e):
    """SSHAPE(s, e) at x and its derivatives by s and e."""
    w = e - s
    # s = e: a step, both pieces empty (their 0/0 and x/0 are never picked)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t, u = (x - s) / w, (x - e) / w
        first, second = (x > s) & (x <= 0.5 * (s + e)), (x > 0.5 * (s + e)) & (x < e)
        value = np.where(x <= s, 0.0, np.where(first, 2.0 * t * t,
                                               np.where(second, 1.0 - 2.0 * u * u, 1.0)))
        ds = np.where(first, 4.0 * t * (x - e) / w ** 2,
                      np.where(second, -4.0 * u * (x - e) / w ** 2, 0.0))
        de = np.where(first, -4.0 * t * (x - s) / w ** 2,
                      np.where(second, 4.0 * u * (x - s) / w ** 2, 0.0))
    return value, ds, de


def _z_pieces(x, s, e):
    """ZSHAPE(s, e) = 1 - SSHAPE(s, e) except on the measure-zero joins: value and derivatives."""
    value, ds, de = _s_pieces(x, s, e)
    return 1.0 - value, -ds, -de


def d_sshape(x, p) -> np.ndarray:
    _, ds, de = _s_pieces(x, p[:, 0], p[:, 1])
    zero = _zero(x, p)
    return _stack(ds, de, zero, zero)


def d_zshape(x, p) -> np.ndarray:
    _, ds, de = _z_pieces(x, p[:, 0], p[:, 1])
    zero = _zero(x, p)
    return _stack(ds, de, zero, zero)


def d_pishape(x, p) -> np.ndarray:
    s, ds_a, ds_b = _s_pieces(x, p[:, 0], p[:, 1])
    z, dz_c, dz_d = _z_pieces(x, p[:, 2], p[:, 3])
    return _stack(ds_a * z, ds_b * z, s * dz_c, s * dz_d)


def d_spike(x, p) -> np.ndarray:
    c, w = p[:, 0], p[:, 1]
    f = np.exp(-np.abs(10.0 / w * (x - c)))
    zero = _zero(x, p)
    return _stack(f * 10.0 * np.sign(x - c) / w, f * 10.0 * np.abs(x - c) / w ** 2, zero, zero)


def d_cosine(x, p) -> np.ndarray:
    c, w = p[:, 0], p[:, 1]
    inside = np.abs(x - c) <= 0.5 * w
    theta = np.where(inside, 2.0 * np.pi / w * (x - c), 0.0)
    dc = np.where(inside, np.pi * np.sin(theta) / w, 0.0)
    dw = np.where(inside, 0.5 * np.sin(theta) * theta / w, 0.0)
    zero = _zero(x, p)
    return _stack(dc, dw, zero, zero)


def d_concave(x, p) -> np.ndarray:
    i, e = p[:, 0], p[:, 1]
    # both branches: mu = |e - i| / D with D = 2e - i - x (rising) or i - 2e + x (falling)
    sloped = ((i <= e) & (x < e)) | ((i > e) & (x > e))
    with np.errstate(divide="ignore", invalid="ignore"):
        denominator = np.where(i <= e, 2.0 * e - i - x, i - 2.0 * e + x) ** 2
        di = np.where(sloped, (x - e) / denominator, 0.0)
        de = np.where(sloped, (i - x) / denominator, 0.0)
    zero = _zero(x, p)
    return _stack(di, de, zero, zero)


def d_sigmoid_difference(x, p) -> np.ndarray:
    s1, dc1, dk1 = _sig(x, p[:, 0], p[:, 1])
    s2, dc2, dk2 = _sig(x, p[:, 3], p[:, 2])
    sign = np.sign(s1 - s2)
    return _stack(sign * dc1, sign * dk1, -sign * dk2, -sign * dc2)


def d_sigmoid_product(x, p) -> np.ndarray:
    s1, dc1, dk1 = _sig(x, p[:, 0], p[:, 1])
    s2, dc2, dk2 = _sig(x, p[:, 3], p[:, 2])
    return _stack(dc1 * s2, dk1 * s2, s1 * dk2, s1 * dc2)


def d_gaussian_product(x, p) -> np.ndarray:
    ga, dma, dsa = _gauss(x, p[:, 0], p[:, 1])
    gb, dmb, dsb = _gauss(x, p[:, 2], p[:, 3])
    left, right = x < p[:, 0], x > p[:, 2]
    a, b = np.where(left, ga, 1.0), np.where(right, gb, 1.0)
    return _stack(np.where(left, dma * b, 0.0), np.where(left, dsa * b, 0.0),
                  np.where(right, a * dmb, 0.0), np.where(right, a * dsb, 0.0))


def d_semi_ellipse(x, p) -> np.ndarray:
    s, e = np.minimum(p[:, 0], p[:, 1]), np.maximum(p[:, 0], p[:, 1])
    r, dx = 0.5 * (e - s), x - 0.5 * (s + e)
    inside = (x > s) & (x < e)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(r * r - dx * dx, 0.0))
        by_r = np.where(inside, dx * dx / (r * r * root), 0.0)
        by_centre = np.where(inside, dx / (r * root), 0.0)
    d_low, d_high = 0.5 * (by_centre - by_r), 0.5 * (by_centre + by_r)
    first_low = p[:, 0] <= p[:, 1]
    return _stack(np.where(first_low, d_low, d_high), np.where(first_low, d_high, d_low),
                  _zero(x, p), _zero(x, p))


def d_arc(x, p) -> np.ndarray:
    s, e = p[:, 0], p[:, 1]
    r = e - s
    between = np.where(r > 0, (s < x) & (x < e), (e < x) & (x < s))
    with np.errstate(divide="ignore", invalid="ignore"):
        q = r * r - (x - e) ** 2
        root = np.sqrt(np.maximum(q, 0.0))
        ds = np.where(between, -np.sign(r) * (x - e) ** 2 / (r * r * root), 0.0)
        de = np.where(between, (r + x - e) / (np.abs(r) * root) - np.sign(r) * root / (r * r),
                      0.0)
    zero = _zero(x, p)
    return _stack(ds, de, zero, zero)
