"""Temporal checks over a batch of closed-loop traces: always, eventually within, settles,
overshoot. Each returns, per loop, whether it is violated and when (first time it shows)."""
from __future__ import annotations

import numpy as np
import sympy

from ..semantics.model import Property
from ..runtime.metrics import overshoot_excess


class UnknownSignal(KeyError):
    pass


def _values(expr: sympy.Expr, signals: dict[str, np.ndarray], params: dict[str, float],
            shape: tuple[int, int], time: np.ndarray) -> np.ndarray:
    """Evaluate an expression (relational or arithmetic) over (T, N) signals; `t` is the time
    (s) unless a signal has that name."""
    names = sorted(s.name for s in expr.free_symbols)
    env = []
    for name in names:
        if name == "t" and name not in signals:
            env.append(np.broadcast_to(time[:, None], shape))
        elif name in signals:
            env.append(signals[name])
        elif name in params:
            env.append(np.full(shape, params[name]))
        else:
            raise UnknownSignal(name)
    f = sympy.lambdify([sympy.Symbol(n) for n in names], expr, modules="numpy")
    with np.errstate(invalid="ignore"):
        return np.broadcast_to(np.asarray(f(*env)), shape)


def names_in(check: Property) -> list[str]:
    exprs = [check.args[k] for k in ("predicate", "target") if k in check.args]
    names = sorted({s.name for e in exprs for s in e.free_symbols})
    return ([check.args["signal"]] if "signal" in check.args else []) + names


def evaluate(check: Property, time: np.ndarray, signals: dict[str, np.ndarray],
             params: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """(violated (N,) bool, first violation time (N,), NaN where it holds). A NaN signal value
    makes a predicate false: it never passes silently."""
    shape = next(iter(signals.values())).shape
    a = check.args
    if check.kind in ("always", "eventually"):
        ok = _values(a["predicate"], signals, params, shape, time).astype(bool)
        if check.kind == "always":
            bad = ~ok
            return bad.any(axis=0), _first(time, bad)
        window = time <= a["within"] + 1e-9
        met = (ok & window[:, None]).any(axis=0)
        return ~met, np.where(met, np.nan, a["within"])
    y = _values(sympy.Symbol(a["signal"]), signals, params, shape, time).astype(float)
    if check.kind == "settles":
        target = _values(a["target"], signals, params, shape, time).astype(float)
        bad = ~(np.abs(y - target) <= a["tolerance"]) & (time >= a["by"] - 1e-9)[:, None]
        return bad.any(axis=0), _first(time, bad)
    # overshoot: runtime.metrics' definition with the final value (mean of the last 10 %) as
    # the target: how far S goes past it on the far side from where S started
    final = np.mean(y[-max(1, len(y) // 10):], axis=0)
    bad = ~(overshoot_excess(y, final) <= a["limit"])
    return bad.any(axis=0), _first(time, bad)


def _first(time: np.ndarray, bad: np.ndarray) -> np.ndarray:
    return np.where(bad.any(axis=0), time[np.argmax(bad, axis=0)], np.nan)
