"""Evaluate the signal chain's sympy expressions with numpy, by walking the expression tree.

No lambdify, eval or exec: each node kind maps to one numpy function, so only the operations
listed here can run.  A tree is compiled once into nested closures (cached per expression);
a caller in a loop keeps the closure (`compile_value`) and sets numpy's error state once.
"""
from __future__ import annotations

from functools import lru_cache, reduce
from typing import Callable

import numpy as np
import sympy

try:        # the ufunc behind np.clip, without its Python wrapper (same results,
    from numpy._core.umath import clip      # noqa: F401  (a quarter of the cost); numpy 2
except ImportError:                         # numpy 1.x
    from numpy.core.umath import clip       # noqa: F401

Env = dict[str, "np.ndarray | float"]
Compiled = Callable[[Env], "np.ndarray | float"]

_NARY = {
    sympy.Add: np.add,
    sympy.Mul: np.multiply,
    sympy.Min: np.minimum,
    sympy.Max: np.maximum,
}
_UNARY = {
    sympy.Abs: np.abs,
    sympy.exp: np.exp,
    sympy.log: np.log,
    sympy.sign: np.sign,
}


def _power(base: np.ndarray | float, exponent: np.ndarray | float) -> np.ndarray:
    if np.isscalar(exponent) and exponent == 0.5:
        return np.sqrt(base)
    if np.isscalar(exponent) and exponent == -1.0:
        return 1.0 / np.asarray(base, dtype=float)
    return np.power(np.asarray(base, dtype=float), exponent)


@lru_cache(maxsize=4096)
def compile_expr(expr: sympy.Expr) -> Compiled:
    """A function env -> value for expr; raises ValueError for a node it does not know."""
    if isinstance(expr, sympy.Symbol):
        name = expr.name

        def symbol(env: Env):
            try:
                return env[name]
            except KeyError:
                raise KeyError(f"no value for `{name}`") from None
        return symbol
    if expr.is_number:
        value = float(expr)
        return lambda env: value
    clamp = _clamp_bounds(expr)
    if clamp is not None:
        inner, lo, hi = clamp
        return lambda env: clip(inner(env), lo, hi)
    negated = _negated(expr)
    if isinstance(expr, sympy.Add) and len(expr.args) == 2 and \
            sum(_negated(a) is not None for a in expr.args) == 1:
        # a - b, which sympy holds as a + (-1) b: a + (-b) is a - b exactly, in one call
        (b,) = [_negated(a) for a in expr.args if _negated(a) is not None]
        (a,) = [a for a in expr.args if _negated(a) is None]
        first, second = compile_expr(a), compile_expr(b)
        return lambda env: np.subtract(first(env), second(env))
    if negated is not None:
        arg = compile_expr(negated)
        return lambda env: np.negative(arg(env))
    args = [compile_expr(a) for a in expr.args]
    for kind, fn in _NARY.items():
        if isinstance(expr, kind):
            if len(args) == 2:      # the common case, without building a list
                first, second = args
                return lambda env: fn(first(env), second(env))
            return lambda env: reduce(fn, [a(env) for a in args])
    for kind, fn in _UNARY.items():
        if isinstance(expr, kind):
            (arg,) = args
            return lambda env: fn(arg(env))
    if isinstance(expr, sympy.Pow):
        base, exponent = args
        return lambda env: _power(base(env), exponent(env))
    raise ValueError(f"cannot evaluate `{expr}`: {type(expr).__name__} is not supported")


def _negated(expr: sympy.Expr) -> sympy.Expr | None:
    """b for an expression -b (sympy's Mul(-1, b)), else None."""
    if isinstance(expr, sympy.Mul) and len(expr.args) == 2 and expr.args[0] == -1:
        return expr.args[1]
    return None


def _clamp_bounds(expr: sympy.Expr) -> tuple[Compiled, float, float] | None:
    """clamp(e, lo, hi) as the language builds it, Min(hi, Max(lo, e)) with number bounds:
    (e compiled, lo, hi), to run as one clip instead of a maximum and a minimum.  clip is
    min(max(e, lo), hi) element by element, NaN propagating, so the values are the same; only
    for nonzero bounds, where no tie between 0.0 and -0.0 can pick a different zero."""
    if not isinstance(expr, sympy.Min) or len(expr.args) != 2:
        return None
    numbers = [a for a in expr.args if a.is_number]
    inner = [a for a in expr.args if isinstance(a, sympy.Max) and len(a.args) == 2]
    if len(numbers) != 1 or len(inner) != 1:
        return None
    lows = [a for a in inner[0].args if a.is_number]
    rest = [a for a in inner[0].args if not a.is_number]
    if len(lows) != 1 or len(rest) != 1:
        return None
    lo, hi = float(lows[0]), float(numbers[0])
    if lo == 0.0 or hi == 0.0 or not (np.isfinite(lo) and np.isfinite(hi)):
        return None
    return compile_expr(rest[0]), lo, hi


def compile_value(expr: "sympy.Expr | float") -> Compiled:
    """compile_expr, also for a plain number (a constant function)."""
    if not isinstance(expr, sympy.Basic):
        value = float(expr)
        return lambda env: value
    return compile_expr(expr)


def evaluate_expr(expr: sympy.Expr, env: Env) -> np.ndarray:
    """The value of expr with symbols taken from env (arrays broadcast), as a float array."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.asarray(compile_value(expr)(env), dtype=float)
