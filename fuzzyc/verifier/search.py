"""Search over the rule base's input space (method 3): a dense vectorized grid, then hypothesis,
which shrinks a failing input to a minimal one. Used where no proof method applies."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import HealthCheck, given, seed as hseed, settings, strategies as st

from ..engine import inference as engine
from ..semantics.model import CondOp, RuleBase
from .draws import without_local_constants
from .result import Evidence, Status
from .space import dense_grid, tensor_points

TOL = 1e-9


def _settings(max_examples: int):
    return settings(max_examples=max_examples, database=None, deadline=None, derandomize=False,
                    suppress_health_check=list(HealthCheck), print_blob=False)


def _hypothesis(check, strategy, max_examples: int, seed: int):
    """Run `check(example) -> str | None` (None: holds) under hypothesis; the shrunk failing
    example and its message, or None."""
    failures: list = []

    @hseed(seed)
    @_settings(max_examples)
    @given(strategy)
    def run(example):
        message = check(example)
        if message is not None:
            failures.append((example, message))
            raise AssertionError(message)

    try:
        with without_local_constants():
            run()
    except AssertionError:
        return failures[-1]     # hypothesis replays the minimal example last
    return None


def _point(rb: RuleBase, x: np.ndarray) -> dict[str, float]:
    return {v.name: float(x[i]) for i, v in enumerate(rb.inputs)}


def _input_strategy(rb: RuleBase, where):
    """Floats over each input's range, on guarded inputs only where the guard is fully true."""
    parts = []
    for i, v in enumerate(rb.inputs):
        base = st.floats(v.lo, v.hi, allow_nan=False)
        if any(rb.input_index(w[0]) == i for w in where):
            axis = dense_grid(rb, where, 1)[i]
            base = st.sampled_from(axis.tolist()) if len(axis) else st.nothing()
        parts.append(base)
    return st.tuples(*parts).map(np.array)


def monotone(rb: RuleBase, output: str, input_: str, direction: str, where,
             budget: int, max_examples: int, seed: int) -> list[Evidence]:
    o, k = rb.output_index(output), rb.input_index(input_)
    sign = 1.0 if direction == "increasing" else -1.0
    axes = dense_grid(rb, where, budget)
    if any(len(a) == 0 for a in axes):
        return [Evidence("grid", Status.UNDECIDED, "the guard is never fully true")]
    y = engine.evaluate(rb, tensor_points(axes))[:, o].reshape([len(a) for a in axes])
    step = np.diff(y, axis=k) * sign
    grid = Evidence("grid", Status.HELD, f"{y.size} grid points", cases=y.size)
    if step.size and step.min() < -TOL:
        idx = np.unravel_index(int(np.argmin(step)), step.shape)
        a = np.array([ax[j] for ax, j in zip(axes, idx)])
        b = a.copy()
        b[k] = axes[k][idx[k] + 1]
        grid = Evidence("grid", Status.VIOLATED, _against(rb, o, k, direction, a, b),
                        cases=y.size, point=_point(rb, a), to_point=_point(rb, b))
        return [grid]

    var = rb.inputs[k]
    strategy = st.tuples(_input_strategy(rb, where), st.floats(0.0, 1.0))

    def moved(example):
        x, frac = example
        x2 = x.copy()
        x2[k] = x[k] + frac * (var.hi - x[k])
        return x, x2

    def check(example):
        x, x2 = moved(example)
        y2 = engine.evaluate(rb, np.stack([x, x2]))[:, o]
        return None if (y2[1] - y2[0]) * sign >= -TOL else _against(rb, o, k, direction, x, x2)

    found = _hypothesis(check, strategy, max_examples, seed)
    if found:
        x, x2 = moved(found[0])
        return [grid, Evidence("hypothesis", Status.VIOLATED, found[1], cases=max_examples,
                               point=_point(rb, x), to_point=_point(rb, x2))]
    return [grid, Evidence("hypothesis", Status.HELD, f"{max_examples} examples",
                           cases=max_examples)]


def _against(rb, o, k, direction, a, b) -> str:
    ya, yb = engine.evaluate(rb, np.stack([a, b]))[:, o]
    others = ", ".join(f"{v.name}={a[i]:.6g}" for i, v in enumerate(rb.inputs) if i != k)
    return (f"{rb.outputs[o].name} = {ya:.6g} at {rb.inputs[k].name}={a[k]:.6g} but {yb:.6g} at "
            f"{rb.inputs[k].name}={b[k]:.6g} ({others}): not {direction}")


def bounded(rb: RuleBase, output: str, lo: float, hi: float, budget: int,
            max_examples: int, seed: int) -> list[Evidence]:
    o = rb.output_index(output)

    def outside(y):
        return np.maximum(y - hi, lo - y)

    points = tensor_points(dense_grid(rb, [], budget))
    y = engine.evaluate(rb, points)[:, o]
    worst = int(np.argmax(outside(y)))
    if outside(y)[worst] > TOL:
        return [Evidence("grid", Status.VIOLATED, f"{output} = {y[worst]:.6g} outside "
                         f"[{lo:g}, {hi:g}]", cases=len(y), point=_point(rb, points[worst]))]
    grid = Evidence("grid", Status.HELD, f"{len(y)} grid points", cases=len(y))

    def check(x):
        v = engine.evaluate(rb, x[None])[0, o]
        return None if outside(v) <= TOL else f"{output} = {v:.6g} outside [{lo:g}, {hi:g}]"

    found = _hypothesis(check, _input_strategy(rb, []), max_examples, seed)
    if found:
        return [grid, Evidence("hypothesis", Status.VIOLATED, found[1], cases=max_examples,
                               point=_point(rb, found[0]))]
    return [grid, Evidence("hypothesis", Status.HELD, f"{max_examples} examples",
                           cases=max_examples)]


def covers(rb: RuleBase, inputs: list[str], level: float, budget: int) -> Evidence:
    """Grid fallback for coverage: the strongest firing at each grid point, clauses on inputs
    outside the list ignored (a wildcard there)."""
    keep = [rb.input_index(n) for n in inputs]
    projected = _projected(rb, keep)
    if projected is None:
        return Evidence("grid", Status.UNDECIDED, f"{rb.nested_rules()} has a nested condition "
                        "on an input outside the list, which has no wildcard to stand in for it")
    points = tensor_points(dense_grid(projected, [], budget))
    best = engine.activations(projected, points).max(axis=1)
    worst = int(np.argmin(best))
    if best[worst] < level - TOL:
        return Evidence("grid", Status.VIOLATED, f"the strongest rule fires only "
                        f"{best[worst]:.6g} < {level:g}", cases=len(points),
                        point=_point(projected, points[worst]))
    return Evidence("grid", Status.HELD, f"{len(points)} grid points", cases=len(points))


def _projected(rb: RuleBase, keep: list[int]) -> RuleBase | None:
    """rb over the inputs `keep` only; None when a clause program reads another input."""
    new_index = np.full(len(rb.inputs), -1)
    new_index[keep] = np.arange(len(keep))
    conditions = {}
    for r, program in rb.conditions.items():
        clause = program[:, 0] == CondOp.CLAUSE
        if np.any(new_index[program[clause, 1]] < 0):
            return None
        conditions[r] = program.copy()
        conditions[r][clause, 1] = new_index[program[clause, 1]]
    return replace(rb, inputs=[rb.inputs[i] for i in keep],
                   antecedents=rb.antecedents[:, keep], negated=rb.negated[:, keep],
                   hedges=rb.hedges[:, keep], conditions=conditions)

