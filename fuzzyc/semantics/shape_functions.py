"""The membership functions of the term shapes, vectorized (moved from engine/membership.py
with their arithmetic unchanged, so every engine number stays bit-identical).

Each takes x and params p (T, 4) and broadcasts x against the parameter columns: x (N, 1) gives
(N, T), x (T,) gives each term at its own point (T,).  The registry (`shapes.SHAPES`) holds them.
"""
from __future__ import annotations

import numpy as np


def trapezoid(x, a, b, c, d) -> np.ndarray:
    """The trapezoid membership, broadcasting x against the parameters.

    An infinite a (or d) makes a shoulder: its rise (fall) is 1 everywhere.
    """
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        rise = np.where(x >= b, 1.0, np.where(x > a, (x - a) / (b - a), 0.0))
        fall = np.where(x <= c, 1.0, np.where(x < d, (d - x) / (d - c), 0.0))
    rise = np.where(np.isneginf(a), 1.0, rise)
    fall = np.where(np.isposinf(d), 1.0, fall)
    return np.minimum(rise, fall)


def mu_trapezoid(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return trapezoid(x, p[:, 0], p[:, 1], p[:, 2], p[:, 3])


def mu_gaussian(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    mean, sigma = p[:, 0], p[:, 1]
    return np.exp(-((x - mean) ** 2) / (2.0 * sigma ** 2))


def mu_bell(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, width, slope = p[:, 0], p[:, 1], p[:, 2]
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.abs((x - center) / width) ** (2.0 * slope))


def mu_sigmoid(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, slope = p[:, 0], p[:, 1]
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-slope * (x - center)))


def mu_singleton(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return (x == p[:, 0]).astype(float)


def _s_shape(x: np.ndarray, s: np.ndarray, e: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return np.where(x <= s, 0.0, np.where(
            x <= 0.5 * (s + e), 2.0 * ((x - s) / (e - s)) ** 2,
            np.where(x < e, 1.0 - 2.0 * ((x - e) / (e - s)) ** 2, 1.0)))


def _z_shape(x: np.ndarray, s: np.ndarray, e: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return np.where(x <= s, 1.0, np.where(
            x < 0.5 * (s + e), 1.0 - 2.0 * ((x - s) / (e - s)) ** 2,
            np.where(x < e, 2.0 * ((x - e) / (e - s)) ** 2, 0.0)))


def mu_sshape(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _s_shape(x, p[:, 0], p[:, 1])


def mu_zshape(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _z_shape(x, p[:, 0], p[:, 1])


def mu_pishape(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _s_shape(x, p[:, 0], p[:, 1]) * _z_shape(x, p[:, 2], p[:, 3])


def mu_spike(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, width = p[:, 0], p[:, 1]
    return np.exp(-np.abs(10.0 / width * (x - center)))


def mu_cosine(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    center, width = p[:, 0], p[:, 1]
    inside = np.abs(x - center) <= 0.5 * width
    # cos of an infinite x is NaN, and x is outside there anyway
    arg = np.where(inside, 2.0 * np.pi / width * (x - center), 0.0)
    return np.where(inside, 0.5 * (1.0 + np.cos(arg)), 0.0)


def mu_concave(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    i, e = p[:, 0], p[:, 1]
    rising, falling = (i <= e) & (x < e), (i > e) & (x > e)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return np.where(rising, (e - i) / (2.0 * e - i - x),
                        np.where(falling, (i - e) / (i - 2.0 * e + x), 1.0))


def _sig(x: np.ndarray, center: np.ndarray, slope: np.ndarray) -> np.ndarray:
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp(-slope * (x - center)))


def mu_sigmoid_difference(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.abs(_sig(x, p[:, 0], p[:, 1]) - _sig(x, p[:, 3], p[:, 2]))


def mu_sigmoid_product(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return _sig(x, p[:, 0], p[:, 1]) * _sig(x, p[:, 3], p[:, 2])


def mu_gaussian_product(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    left = np.where(x < p[:, 0], mu_gaussian(x, p[:, 0:2]), 1.0)
    right = np.where(x > p[:, 2], mu_gaussian(x, p[:, 2:4]), 1.0)
    return left * right


def mu_binary(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    start, direction = p[:, 0], p[:, 1]
    return (((direction > start) & (x >= start)) | ((direction < start) & (x <= start))) * 1.0


def _circle(x: np.ndarray, center: np.ndarray, r: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """sqrt(r^2 - (x - center)^2) / |r| where `inside` (elsewhere 0: no root of a negative)."""
    dx = np.where(inside, x - center, 0.0)
    return np.where(inside, np.sqrt(np.maximum(r * r - dx * dx, 0.0)) / np.abs(r), 0.0)


def mu_semi_ellipse(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    s, e = np.minimum(p[:, 0], p[:, 1]), np.maximum(p[:, 0], p[:, 1])
    r = 0.5 * (e - s)
    return _circle(x, s + r, r, (x >= s) & (x <= e))


def mu_arc(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    s, e = p[:, 0], p[:, 1]
    rising = s < e
    between = np.where(rising, (s <= x) & (x <= e), (e <= x) & (x <= s))
    beyond = np.where(rising, x > e, x < e)
    return np.where(beyond, 1.0, _circle(x, e, e - s, between))


def mu_linear(x: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.zeros(np.broadcast(x, p[:, 0]).shape)   # a consequent value, not a shape


def mu_discrete(x: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """A DISCRETE term's points xy (K, 2) at x: np.interp holds the first and last y beyond
    the points, as the model says."""
    return np.interp(x, xy[:, 0], xy[:, 1])


def mu_function(x: np.ndarray, formula) -> np.ndarray:
    """A FUNCTION term's membership at x (N,): the formula of x, 0 where it is not finite; a
    formula of other variables (a Takagi-Sugeno value) has no shape: 0, as a LINEAR term."""
    if not formula.names() <= {"x"}:
        return np.zeros(x.shape[0])
    mu = np.broadcast_to(formula.evaluate({"x": x}), x.shape)
    return np.where(np.isfinite(mu), mu, 0.0)


def discrete_problem(values) -> str:
    """'' when x1 y1 x2 y2 ... make a DISCRETE term, else what is wrong."""
    if len(values) < 2 or len(values) % 2 or not all(map(np.isfinite, values)):
        return "a discrete term needs pairs of finite numbers x y (at least one)"
    xs, ys = values[0::2], values[1::2]
    if any(p >= q for p, q in zip(xs, xs[1:])) or any(not 0 <= y <= 1 for y in ys):
        return "a discrete term's x values must ascend and its y values lie in [0, 1]"
    return ""
