"""Decide a closed loop's temporal checks on its reachable sets, with branch and bound.

Every period, each check's predicate is evaluated on the sets (affine forms of every signal it
reads) in three values per box: true for every loop of the box, false for every loop, or
either. A box proves `always P` when P is true at every period, `eventually within W: P` when
P is true at some period up to W, `settles X to T within tol by b` when |X - T| <= tol at every
period from b on. Boxes that prove nothing are cut in two across their widest side (relative
to the `vary` range) and run again, all of a round in one batch, until every box proves its
checks or the budget of boxes is spent.

The answer per check: PROVED with the bound the sets reached; UNDECIDED (the search then runs
and may find a violation) with the tightest bound, how far in time the proof got in its worst
box, and where splitting stopped.
"""
from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass

import numpy as np
import sympy

from ...semantics.model import Model, Property
from ..result import Evidence, Status
from .affine import Affine
from .chain import Unsupported, evaluate
from .loop import SetLoop, split, step_keys

MARGIN = 1e-9          # a predicate is true on a set only with this much room (rounding)
DEFAULT_MAX_BOXES = 64
DEFAULT_SIGMAS = 0.0   # Gaussian plant noise covered up to this many standard deviations


@dataclass
class Settings:
    max_boxes: int = DEFAULT_MAX_BOXES
    sigmas: float = DEFAULT_SIGMAS

    def __post_init__(self):
        # a NaN bound would make a proof that states "covered to nan sigma"
        if not (isinstance(self.max_boxes, (int, np.integer)) and self.max_boxes >= 1):
            raise ValueError(f"prove_boxes must be an integer of at least 1, got {self.max_boxes}")
        if not (math.isfinite(self.sigmas) and self.sigmas >= 0):
            raise ValueError(f"noise_sigmas must be a finite number >= 0, got {self.sigmas}")


def _names(expr: sympy.Expr) -> set[str]:
    return {s.name for s in expr.free_symbols}


def _predicate(check: Property) -> tuple[sympy.Expr, float, float]:
    """(predicate, from time, until time) of a check."""
    a = check.args
    if check.kind == "always":
        return a["predicate"], 0.0, np.inf
    if check.kind == "eventually":
        return a["predicate"], 0.0, a["within"]
    if check.kind == "settles":
        expr = sympy.Abs(sympy.Symbol(a["signal"]) - a["target"]) <= a["tolerance"]
        return expr, a["by"], np.inf
    if check.kind == "overshoot":     # decided at the end of the run (_overshoot)
        return sympy.Symbol(a["signal"]) <= a["limit"], 0.0, np.inf
    raise Unsupported(f"`{check.text}`: no set-valued decision for `{check.kind}` checks")


def truth(expr, env: dict, batch: int) -> tuple[np.ndarray, np.ndarray]:
    """(true (B,), slack (B,)): whether expr holds for every loop of each box, and by how much
    (the least value of lhs - rhs, oriented so that > 0 holds; min/max through and/or)."""
    if isinstance(expr, (sympy.And, sympy.Or)):
        parts = [truth(a, env, batch) for a in expr.args]
        true = np.stack([p[0] for p in parts])
        slack = np.stack([p[1] for p in parts])
        if isinstance(expr, sympy.And):
            return true.all(axis=0), slack.min(axis=0)
        return true.any(axis=0), slack.max(axis=0)
    if isinstance(expr, (sympy.StrictGreaterThan, sympy.GreaterThan)):
        diff = evaluate(expr.lhs - expr.rhs, env)
    elif isinstance(expr, (sympy.StrictLessThan, sympy.LessThan)):
        diff = evaluate(expr.rhs - expr.lhs, env)
    elif expr in (sympy.true, sympy.false):
        return np.full(batch, bool(expr)), np.full(batch, 1.0 if expr else -1.0)
    else:
        raise Unsupported(f"`{expr}`: no set-valued truth for {type(expr).__name__}")
    low = diff.lo() if isinstance(diff, Affine) else np.full(batch, float(diff))
    margin = MARGIN * (1.0 + np.abs(low))
    strict = isinstance(expr, (sympy.StrictGreaterThan, sympy.StrictLessThan))
    return (low > margin) if strict else (low >= margin), low


def _bound_text(expr, slack: float) -> str:
    """The bound reached, said on the signal: `gap >= 7.31` for gap > 5 with slack 2.31."""
    if not np.isfinite(slack):
        return f"`{expr}` (no period of the run falls in its window)"
    if isinstance(expr, sympy.Rel) and expr.rhs.is_number:
        sign = 1 if isinstance(expr, (sympy.StrictGreaterThan, sympy.GreaterThan)) else -1
        op = ">=" if sign > 0 else "<="
        return f"{expr.lhs} {op} {float(expr.rhs) + sign * slack:.6g}"
    return f"margin {slack:.6g} on `{expr}`"


@dataclass
class _Tally:
    """Per check and box: proved so far, the least slack seen in the window (the largest, for
    `eventually`), the time up to which the predicate held (when it first held); for
    `overshoot` the signal's least and largest value at every period."""
    proved: np.ndarray
    slack: np.ndarray
    reached: np.ndarray
    lows: list | None = None
    highs: list | None = None
    downward: np.ndarray | None = None      # overshoot: the box may start above its final value


def _overshoot(check: Property, tally: _Tally, t: float) -> None:
    """`overshoot X below L`: sign(final - X(0)) * (X - final) <= L at every period, final the
    mean of X over the last 10 % of the periods (temporal.py, runtime.metrics). On the sets,
    upward: the largest upper bound of X less the mean of the lower bounds over the last 10 %;
    downward the mirror; a box whose start may lie on either side of its final value must bound
    both (the correlation between the peak and the final value is dropped: sound, looser)."""
    lows, highs = np.array(tally.lows), np.array(tally.highs)
    tail = max(1, len(lows) // 10)
    final_lo, final_hi = lows[-tail:].mean(axis=0), highs[-tail:].mean(axis=0)
    may_down = ~(highs[0] <= final_lo)             # written so that a NaN bound keeps both
    up = np.where(~(lows[0] >= final_hi), highs.max(axis=0) - final_lo, -np.inf)
    down = np.where(may_down, final_hi - lows.min(axis=0), -np.inf)
    need = np.maximum(up, down)
    tally.downward = may_down
    final = final_lo
    slack = check.args["limit"] - np.where(np.isneginf(need), 0.0, need)   # starts at final
    tally.slack = slack
    tally.proved = np.isfinite(slack) & (slack >= MARGIN * (1.0 + np.abs(final)))
    tally.reached = np.where(tally.proved, t, 0.0)


def _run(model, scen, args, boxes, checks, settings) -> list[_Tally]:
    loop = SetLoop(model, scen, args, boxes, settings.sigmas)
    preds = [_predicate(c) for c in checks]
    record = sorted(set().union(*(_names(p) for p, _, _ in preds)) - {"t"})
    batch, rows = loop.batch, loop.batch * loop.copies
    # `always`-like checks start proved and lose boxes; `eventually` starts open and gains
    tallies = [_Tally(np.full(batch, c.kind != "eventually"),
                      np.full(batch, np.inf if c.kind != "eventually" else -np.inf),
                      np.zeros(batch)) for c in checks]
    for t, signals in loop.run(record):
        env = {**signals, "t": t}
        alive = False
        for c, (check, (pred, start, end)) in enumerate(zip(checks, preds)):
            tally = tallies[c]
            if t < start - 1e-9 or t > end + 1e-9:
                alive |= t < start
                continue
            if check.kind == "overshoot":
                low, high = (np.broadcast_to(np.asarray(b, float), (rows,)) for b in
                             _bounds(env[check.args["signal"]]))
                if loop.once:            # a step taken once: the box's copies
                    low, high = loop.once.fold_bounds(low, high)
                tally.lows = (tally.lows or []) + [low]
                tally.highs = (tally.highs or []) + [high]
                alive = True
                continue
            true, slack = truth(pred, env, rows)
            if loop.once:
                true, slack = loop.once.fold_truth(true, slack)
            true &= np.isfinite(slack)
            if check.kind == "eventually":
                tally.slack = np.where(tally.proved, tally.slack, np.fmax(tally.slack, slack))
                newly = true & ~tally.proved
                tally.reached = np.where(newly, t, tally.reached)
                tally.proved |= true
                alive |= not tally.proved.all()
            else:
                held = tally.proved & true
                tally.slack = np.where(held, np.fmin(tally.slack, slack), tally.slack)
                tally.proved &= true
                tally.reached = np.where(tally.proved, t, tally.reached)
                alive |= bool(tally.proved.any())
        if not alive:
            break
    for check, tally in zip(checks, tallies):
        if check.kind == "overshoot":
            _overshoot(check, tally, t)
    return tallies


def _bounds(x) -> tuple:
    return x.bounds() if isinstance(x, Affine) else (x, x)


def prove(model: Model, prop: Property, checks: list[Property], scen,
          settings: Settings | None = None) -> list[Evidence]:
    """One Evidence per check (method "reach")."""
    settings = settings or Settings()
    a = prop.args
    start = _time.perf_counter()
    ranges = {**a["vary"], **step_keys(a, a["duration"],
                                       getattr(scen.plant_module(), "INPUTS", ()))}
    full = {k: (float(lo), float(hi)) for k, (lo, hi) in ranges.items()}
    boxes = {k: (np.array([lo]), np.array([hi])) for k, (lo, hi) in full.items()}
    leaves: list[tuple[dict, list[_Tally]]] = []
    try:
        while True:
            tallies = _run(model, scen, a, boxes, checks, settings)
            open_ = ~np.all([t.proved for t in tallies], axis=0)
            # after a split: the leaves so far, this round's proved boxes, two per open one
            if not open_.any() or not boxes or \
                    total_boxes(leaves) + len(open_) + int(open_.sum()) > settings.max_boxes:
                leaves.append((boxes, tallies))
                break
            done = np.flatnonzero(~open_)
            if len(done):
                leaves.append((_take(boxes, done), [_take_tally(t, done) for t in tallies]))
            boxes = split(boxes, np.flatnonzero(open_), full)
    except Unsupported as exc:
        return [Evidence("reach", Status.UNDECIDED, f"no proof: {exc}") for _ in checks]
    seconds = _time.perf_counter() - start
    return [_evidence(c, i, leaves, full, a["duration"], seconds, settings)
            for i, c in enumerate(checks)]


def total_boxes(leaves) -> int:
    return sum(_size(boxes) for boxes, _ in leaves)


def _size(boxes: dict) -> int:
    return len(next(iter(boxes.values()))[0]) if boxes else 1


def _take(boxes: dict, idx: np.ndarray) -> dict:
    return {k: (lo[idx], hi[idx]) for k, (lo, hi) in boxes.items()}


def _take_tally(t: _Tally, idx: np.ndarray) -> _Tally:
    return _Tally(t.proved[idx], t.slack[idx], t.reached[idx],
                  downward=None if t.downward is None else t.downward[idx])


def _evidence(check: Property, i: int, leaves, full: dict, duration: float, seconds: float,
              settings: Settings) -> Evidence:
    pred, start, end = _predicate(check)
    two_sided = check.kind == "overshoot" and any(
        tallies[i].downward is not None and tallies[i].downward.any() for _, tallies in leaves)
    proved = np.concatenate([tallies[i].proved for _, tallies in leaves])
    slack = np.concatenate([tallies[i].slack for _, tallies in leaves])
    reached = np.concatenate([tallies[i].reached for _, tallies in leaves])
    n = len(proved)
    where = ", ".join(f"{k} in [{lo:g}, {hi:g}]" for k, (lo, hi) in full.items()) or \
        "the nominal loop"
    assumption = ("Gaussian plant noise not covered (--noise-sigmas 0); bounded noise as the "
                  "plant's set step states" if settings.sigmas == 0 else
                  f"Gaussian plant noise covered to {settings.sigmas:g} sigma; bounded noise as "
                  f"the plant's set step states")
    horizon = f"{min(duration, end):g} s" if np.isfinite(end) else f"{duration:g} s"
    if proved.all():
        bound = _bound_text(pred, float(slack.min())) if check.kind != "eventually" else \
            f"`{pred}` holds by t = {reached.max():.6g} s"
        if check.kind == "overshoot":
            bound = _overshoot_text(check, float(slack.min()), two_sided)
        return Evidence("reach", Status.PROVED,
                        f"{bound} for all loops with {where} over {horizon} ({n} boxes, "
                        f"{seconds:.2f} s; {assumption})", cases=n)
    worst = int(np.argmin(np.where(proved, np.inf, reached)))
    tight = _bound_text(pred, float(np.nanmin(np.where(np.isfinite(slack), slack, np.nan))))\
        if np.isfinite(slack).any() else "no bound"
    got = f"{reached[worst]:g} s of {horizon}" if check.kind != "eventually" else \
        f"not decided within {horizon}"
    held = f"hold `{pred}` only up to t = {got}"
    if check.kind == "overshoot":          # decided at the end, in the box that overshoots most
        worst = int(np.argmin(slack))
        held = (f"bound the overshoot only by "
                f"{_overshoot_text(check, float(slack[worst]), two_sided)}")
        tight = "the same"
    box_lo, box_hi = _leaf_box(leaves, worst)
    box = ", ".join(f"{k} in [{box_lo[k]:.6g}, {box_hi[k]:.6g}]" for k in box_lo)
    return Evidence("reach", Status.UNDECIDED,
                    f"unknown: the sets {held} in the worst box "
                    f"({box or 'the nominal loop'}); tightest bound while it held: {tight}; "
                    f"splitting stopped at {n} boxes ({n - int(proved.sum())} open, budget "
                    f"{settings.max_boxes}; {seconds:.2f} s; {assumption})", cases=n)


def _overshoot_text(check: Property, slack: float, two_sided: bool = False) -> str:
    past = (f"the overshoot of {check.args['signal']} past final" if two_sided else
            f"{check.args['signal']} - final")     # upward only when every box starts below
    return (f"{past} <= {check.args['limit'] - slack:.6g} (final: the mean of the last 10 % of "
            f"the run)")


def _leaf_box(leaves, index: int) -> tuple[dict, dict]:
    for boxes, _ in leaves:
        size = _size(boxes)
        if index < size:
            return ({k: float(lo[index]) for k, (lo, _) in boxes.items()},
                    {k: float(hi[index]) for k, (_, hi) in boxes.items()})
        index -= size
    return {}, {}
