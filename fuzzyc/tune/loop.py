"""Tuning against a closed loop: the cost is a metric of a scenario's batched loop run with the
candidate rule base, the search derivative-free (scipy's Powell or Nelder-Mead within the
tune section's bounds), and the result keeps what the file had proved.

Kept: the file's monotone / covers / bounded properties that held before (as a fit to data
keeps them, fuzzyc.tune.constraints), its closed-loop properties that held before
(re-verified by search, as `fuzzyc verify` does, on the same seed; with `prove`, by the
reachable-set proof first, and one proved before must be proved again) and any `limits` the
caller adds (a metric at most a value, e.g. the overshoot). A search result that loses one is
rejected with the reason, and the result is the point nearest it, on the way back to the
numbers as written (which kept them), that keeps everything (bisection).

Nothing here draws a random number: the optimizers are deterministic and the loop and the
verifier's searches run on the seed, so the same file, scenario and seed give the same
numbers, bit for bit."""
from __future__ import annotations

import copy
import re
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from ..semantics.model import Model
from ..semantics.tunable import TunedNumber
from ..verifier.result import Status
from .constraints import KEPT, PropertyCheck, kept_properties, status
from .space import Space

METHODS = ("powell", "nelder-mead")
REJECT_COST = 1e300            # a loop whose metric is not finite (NaN: never settled)
LIMIT_WEIGHT = 1e3             # the penalty per unit a limited metric goes over its limit
METRIC_CALL = re.compile(r"^\s*(\w+)\s*\(\s*(\w+)\s*(?:,\s*([\w.+-]+)\s*)?\)\s*$")


@dataclass
class LoopFit:
    """The tuned numbers, the cost before and after, and the properties (and limits) before
    and after. `evaluations`: the cost's evaluations (closed-loop runs unless a cost is given)."""
    numbers: list[TunedNumber]
    values: np.ndarray
    model: Model
    cost_before: float
    cost_after: float
    method: str
    properties: list[PropertyCheck] = field(default_factory=list)
    rejected: list[str] = field(default_factory=list)
    seed: int = 0
    evaluations: int = 0


# -- the metric -------------------------------------------------------------------------------

def metric_function(scenario, metric: str) -> Callable:
    """trace -> (N,) values of `metric`: a label of the scenario's metrics (as `simulate`
    prints them), or NAME(SIGNAL) / NAME(SIGNAL, TARGET) with NAME one of the runtime's metrics
    or `iae` (the integral of |SIGNAL - TARGET| over the run, sampled: sum times the period).
    TARGET is a signal or a number; left out, it is the target the scenario's metrics give
    SIGNAL (0 if none)."""
    from fuzzyc.runtime.simulate import METRICS, loop_metrics, references
    labels = [spec.get("label") or f"{spec.get('name')}({spec.get('signal')})"
              for spec in scenario.metrics]
    if metric in labels:
        return lambda trace: loop_metrics(scenario, trace)[metric]
    match = METRIC_CALL.match(metric)
    if not match or (match.group(1) not in METRICS and match.group(1) != "iae"):
        known = ", ".join(["iae", *sorted(METRICS)])
        raise ValueError(f"--minimize {metric!r}: write NAME(SIGNAL) or NAME(SIGNAL, TARGET) "
                         f"with NAME one of {known}, or a metric label of scenario "
                         f"{scenario.name}: {'; '.join(labels) or 'it has none'}")
    name, signal, target = match.groups()
    if target is None:
        target = references(scenario).get(signal, 0.0)
    else:
        target = _number_or_name(target)

    def values(trace) -> np.ndarray:
        for needed in [signal] + ([target] if isinstance(target, str) else []):
            if needed not in trace:
                raise ValueError(f"--minimize {metric!r}: no recorded signal `{needed}`")
        y = trace[signal]
        goal = trace[target] if isinstance(target, str) else target
        if name == "iae":
            return np.sum(np.abs(y - goal), axis=0) * trace.period
        return np.broadcast_to(METRICS[name](trace.time, y, goal, {"band": 0.05}),
                               (trace.batch,)).astype(float)
    return values


def _number_or_name(text: str) -> float | str:
    try:
        return float(text)
    except ValueError:
        return text


def parse_limit(text: str) -> tuple[str, float]:
    """`METRIC <= VALUE` -> (METRIC, VALUE)."""
    metric, sep, value = text.rpartition("<=")
    try:
        number = float(value)
    except ValueError:
        number = None
    if not sep or not metric.strip() or number is None:
        raise ValueError(f"--limit {text!r}: write METRIC<=VALUE, e.g. 'overshoot(y)<=0.02'")
    return metric.strip(), number


# -- the loop as a cost -----------------------------------------------------------------------

class ClosedLoop:
    """cost(theta): the scenario's loop run with the rule base at theta, `batch` loops (plant
    params drawn when `randomize`), each metric the mean over the batch.

    cluster (runtime.campaign.Cluster): the batch run in chunks of loops where it says (in
    this process or as Dask tasks), each chunk returning its loops' metric values.  A loop
    draws its plant and noise from its own stream and keeps its place modulo 8 in any chunk
    (runtime.campaign.chunks), so the values, their means and the tuned numbers are the same
    bits as one batch in this process."""

    def __init__(self, scenario, space: Space, metric: str, *, batch: int = 1, seed: int = 0,
                 randomize: bool = False, limits: tuple[tuple[str, float], ...] = (),
                 cluster=None):
        self.scenario, self.space = scenario, space
        self.batch, self.seed, self.randomize = batch, seed, randomize
        self.cluster = cluster
        self.texts = [metric, *(text for text, _ in limits)]
        self.metric = metric_function(scenario, metric)
        self.limits = [(text, value, metric_function(scenario, text)) for text, value in limits]
        _apply_scenario(scenario, space)

    def trace(self, theta):
        return _run_loops(self.scenario, self.space.apply(theta), range(self.batch), self.seed,
                          self.randomize)

    def values(self, theta) -> list[np.ndarray]:
        """Per loop (batch,): the metric's values, then each limited metric's."""
        if self.cluster is None:
            trace = self.trace(theta)
            return [self.metric(trace), *(f(trace) for _, _, f in self.limits)]
        import functools

        from fuzzyc.runtime.campaign import chunks, map_chunks
        task = functools.partial(_chunk_values, self.scenario, self.space.apply(theta),
                                 self.texts, self.seed, self.randomize)
        parts = map_chunks(task, chunks(self.batch, self.cluster.chunk), self.cluster,
                           label="loops")
        return [np.concatenate([part[k] for part in parts]) for k in range(len(self.texts))]

    def measure(self, theta) -> tuple[float, list[float]]:
        """The metric and each limited metric, means over the batch (NaN: some loop has none)."""
        values = self.values(theta)
        return _mean(values[0]), [_mean(v) for v in values[1:]]

    def __call__(self, theta) -> float:
        cost, limited = self.measure(theta)
        over = sum(max(0.0, v - limit) if np.isfinite(v) else np.inf
                   for v, (_, limit, _) in zip(limited, self.limits))
        total = cost + LIMIT_WEIGHT * over
        return float(total) if np.isfinite(total) else REJECT_COST


def _run_loops(scenario, model: Model, loops: range, seed: int, randomize: bool):
    """The trace of the scenario's loops `loops` (their campaign numbers) as one batch."""
    from fuzzyc.engine.chain import Controller
    from fuzzyc.runtime.loop import run
    from fuzzyc.runtime.simulate import build
    controller = Controller(model, len(loops))
    blocks = build(scenario, controller, len(loops), seed, randomize, first=loops.start)
    return run(blocks, scenario.period, scenario.duration, len(loops),
               initial=scenario.data.get("initial"))


def _chunk_values(scenario, model: Model, texts: list[str], seed: int, randomize: bool,
                  loops: range) -> list[np.ndarray]:
    """One chunk's task (module level: it travels to Dask workers by pickle): the values of
    each metric text on the loops `loops`."""
    trace = _run_loops(scenario, model, loops, seed, randomize)
    return [np.asarray(metric_function(scenario, text)(trace), dtype=float) for text in texts]


def _mean(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.mean(values)) if np.all(np.isfinite(values)) else float("nan")


def _apply_scenario(scenario, space: Space) -> None:
    """The scenario's controller params and initial outputs on the working copy, except the
    params being tuned (their candidate values win)."""
    model = space.model
    tuned = {n.param for n in space.numbers if n.kind == "param"}
    spec = scenario.controller
    for name, value in (spec.get("params") or {}).items():
        if name not in model.params:
            raise scenario.error(f"controller.params.{name}",
                                 f"the rule base has no param `{name}`; known: "
                                 + (", ".join(model.params) or "none"))
        if name not in tuned:
            model.params[name] = replace(model.params[name], value=float(value))
    outputs = {o.name: o for o in model.outputs}
    for name, value in (spec.get("initial") or {}).items():
        if name in outputs:
            outputs[name].init = float(value)


# -- the search -------------------------------------------------------------------------------

class _BudgetSpent(Exception):
    """The search asked for one evaluation more than max_evaluations."""


def minimize_within(cost: Callable, x0, lo, hi, method: str = "powell",
                    max_evaluations: int | None = None) -> np.ndarray:
    """scipy's derivative-free minimize within [lo, hi] (deterministic: no random start).
    Powell's line searches keep to the bounds; Nelder-Mead's simplex is clipped to them.

    max_evaluations: at most this many calls of `cost` at distinct points, x0's included (a
    point asked again is not run again). scipy's own `maxfev` is checked only between its
    steps (Powell ran 83 for 80), so the budget is enforced here: the search stops at the
    call that would pass it, with the best point seen. The result is never worse than x0."""
    from scipy.optimize import minimize
    if method not in METHODS:
        raise ValueError(f"method {method!r}: one of {', '.join(METHODS)}")
    x0, lo, hi = (np.asarray(v, dtype=float) for v in (x0, lo, hi))
    seen: dict[bytes, float] = {}
    best = [x0, np.inf]

    def budgeted(theta) -> float:
        theta = np.asarray(theta, dtype=float)
        key = theta.tobytes()
        if key not in seen:
            if max_evaluations is not None and len(seen) >= max_evaluations:
                raise _BudgetSpent
            value = float(cost(theta))
            seen[key] = np.inf if np.isnan(value) else value
            if seen[key] < best[1]:             # the first of equals kept: x0 before others
                best[0], best[1] = theta.copy(), seen[key]
        return seen[key]

    options = {"maxfev": max_evaluations, "xtol": 1e-4, "ftol": 1e-6}
    if method == "nelder-mead":
        options = {"maxfev": max_evaluations, "xatol": 1e-4, "fatol": 1e-6}
    try:
        budgeted(x0)
        result = minimize(budgeted, x0, method="Powell" if method == "powell" else "Nelder-Mead",
                          bounds=list(zip(lo, hi)), options=options)
        budgeted(np.clip(result.x, lo, hi))
    except _BudgetSpent:
        pass
    return np.clip(best[0], lo, hi)


@dataclass(frozen=True)
class LoopChecks:
    """How the closed-loop properties are checked: searched (`max_examples` loops on `seed`),
    proved first with `prove` (reachable sets in at most `prove_boxes` boxes), on the user's
    own scenarios by name (`scenarios`, as fuzzyc.verify takes them)."""
    seed: int = 0
    max_examples: int = 30
    prove: bool = False
    prove_boxes: int = 64
    scenarios: dict | None = None


def closed_loop_checks(model: Model, how: LoopChecks) -> list[tuple[str, str, str]]:
    """(text, verdict, why) of each check of the model's closed-loop properties, as
    `fuzzyc verify` decides them (on the seed: the same verdicts every run)."""
    from ..verifier.runner import Options, verify_model
    loops = [_with_params(p, model) for p in model.properties if p.kind == "closed_loop"]
    if not loops:
        return []
    only = replace(model, properties=loops)
    results = verify_model(only, Options(seed=how.seed, max_examples=how.max_examples,
                                         prove=how.prove, prove_boxes=how.prove_boxes,
                                         scenarios=dict(how.scenarios or {})))
    out = []
    for r in results:
        bad = r.violation
        if bad is None and how.prove and r.status != Status.PROVED:   # where the proof stopped
            bad = next((e for e in r.evidence if e.method == "reach"), None)
        out.append((r.prop.text, r.status.value, bad.detail if bad is not None else ""))
    return out


def _with_params(prop, model: Model):
    """The closed-loop property with the model's params set in its scenario: the verifier
    applies the scenario's controller params over the model's, which would undo tuned ones."""
    tuned = {n.param for n in model.tunables if n.kind == "param"}
    sets = dict(prop.args["set"])
    sets.update({f"controller.params.{name}": repr(float(model.params[name].value))
                 for name in sorted(tuned)})
    return replace(prop, args={**prop.args, "set": sets})


def tune_loop(model: Model, scenario, metric: str, *, seed: int = 0, batch: int = 1,
              randomize: bool = False, method: str = "powell",
              max_evaluations: int | None = None, limits: tuple[tuple[str, float], ...] = (),
              max_examples: int = 30, cost: Callable | None = None, prove: bool = False,
              prove_boxes: int = 64, scenarios: dict | None = None,
              cluster=None) -> LoopFit:
    """Tune `model`'s tuned numbers (its `tune` section) to minimize `metric` of `scenario`'s
    loop (a scenario object, plants.scenario.load), keeping its properties (module docstring).
    cost: another cost of theta instead of the metric (then `metric` only names it).
    prove, prove_boxes, scenarios: how its closed-loop properties are checked (LoopChecks).
    cluster: where the cost's loops run (ClosedLoop); the property checks run here."""
    how = LoopChecks(seed, max_examples, prove, prove_boxes, scenarios)
    space = Space(model)
    loop = ClosedLoop(scenario, space, metric, batch=batch, seed=seed, randomize=randomize,
                      limits=limits, cluster=cluster)
    given = cost
    calls = [0]
    costs: dict[bytes, float] = {}

    def counted(theta) -> float:
        """The cost, each point run once (the search's start and its result are asked again):
        calls[0] counts the runs, as many as the search's budget allows."""
        key = np.asarray(theta, dtype=float).tobytes()
        if key not in costs:
            calls[0] += 1
            costs[key] = (given or loop)(theta)
        return costs[key]
    props = kept_properties(model)
    checks = [PropertyCheck(p.text, status(model, p, seed)[0].value) for p in props]
    loop_before = closed_loop_checks(model, how)
    checks += [PropertyCheck(text, verdict) for text, verdict, _ in loop_before]
    limit_before = _limits(loop, space.x0)
    checks += [PropertyCheck(f"{text} <= {limit:g}", _limit_verdict(v, limit))
               for (text, limit, _), v in zip(loop.limits, limit_before)]
    kept = {c.text for c in checks if c.before in {s.value for s in KEPT}}
    proved = {text for text, said, _ in loop_before if said == Status.PROVED.value}
    before = counted(space.x0)

    def lost(theta) -> list[str]:
        candidate = space.apply(theta)
        why = []
        for p in props:
            if p.text in kept:
                verdict, detail = status(candidate, p, seed)
                if verdict not in KEPT:
                    why.append(f"loses `{p.text}` ({verdict.value}: {detail})")
        for text, said, detail in closed_loop_checks(copy.deepcopy(candidate), how):
            if text in proved and said != Status.PROVED.value:
                why.append(f"loses the proof of `{text}` ({said}: {detail})")
            elif text in kept and said not in {s.value for s in KEPT}:
                why.append(f"loses `{text}` ({said}: {detail})")
        for (text, limit, _), v in zip(loop.limits, _limits(loop, theta)):
            if f"{text} <= {limit:g}" in kept and _limit_verdict(v, limit) != "held":
                why.append(f"loses `{text} <= {limit:g}` ({text} = {v:.6g})")
        return why

    found = minimize_within(counted, space.x0, space.lo, space.hi, method, max_evaluations)
    runs = "closed-loop runs" if given is None else "evaluations of the given cost"
    name = f"scipy {method} within the bounds, {calls[0]} {runs}"
    rejected = []
    reasons = lost(found)
    if reasons:
        rejected.append(f"the search's optimum: {'; '.join(reasons)}")
        found, share = _keeping(space.x0, found, lost)
        name += f", then {share:.4g} of the way from the written numbers (the most that " \
                "keeps the properties)"
    tuned = copy.deepcopy(space.apply(found))
    for c in checks:
        c.after = c.before
    after_props = {p.text: status(tuned, p, seed) for p in props}
    after_loop = {t: (v, d) for t, v, d in closed_loop_checks(copy.deepcopy(tuned), how)}
    after_limits = _limits(loop, found)
    for c in checks:
        if c.text in after_props:
            c.after, c.detail = after_props[c.text][0].value, after_props[c.text][1]
        elif c.text in after_loop:
            c.after, c.detail = after_loop[c.text]
    for (text, limit, _), v in zip(loop.limits, after_limits):
        check = next(c for c in checks if c.text == f"{text} <= {limit:g}")
        check.after, check.detail = _limit_verdict(v, limit), f"{text} = {v:.6g}"
    return LoopFit(space.numbers, np.asarray(found, dtype=float), tuned, float(before),
                   float(counted(found)), name, checks, rejected, seed, calls[0])


def _limits(loop: ClosedLoop, theta) -> list[float]:
    """The limited metrics at theta (no loop is run when there are none: a custom cost)."""
    return loop.measure(theta)[1] if loop.limits else []


def _limit_verdict(value: float, limit: float) -> str:
    return "held" if np.isfinite(value) and value <= limit else "violated"


def _keeping(x0, candidate, lost: Callable, steps: int = 8):
    """x0 + t (candidate - x0) for the largest t (bisection) with nothing lost: t = 0, the
    written numbers, kept everything."""
    good, bad = 0.0, 1.0
    for _ in range(steps):
        t = 0.5 * (good + bad)
        if lost(x0 + t * (candidate - x0)):
            bad = t
        else:
            good = t
    return x0 + good * (candidate - x0), good
