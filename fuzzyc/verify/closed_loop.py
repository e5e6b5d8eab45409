"""Closed-loop search (method 3): hypothesis draws plant parameters and disturbance steps, the
whole set runs as ONE batch of loops (the runtime is batched), the temporal checks are
evaluated on every trace, and a failing case is shrunk toward the scenario's nominal values in
batched rounds (each round simulates every simpler candidate at once)."""
from __future__ import annotations

import copy
import dataclasses
import os
import re

import numpy as np
from hypothesis import HealthCheck, Phase, given, seed as hseed, settings, strategies as st

from ..model import Model, Property
from . import temporal
from .result import Evidence, Status

BASELINE = "baseline_"   # a check's `baseline_X`: signal X of the scenario's baseline controller


def check(model: Model, prop: Property, checks: list[Property], options) -> list[list[Evidence]]:
    from fuzzyc.plants import scenario as scenarios
    a = prop.args
    learning = {k.split(".", 1)[1]: v for k, v in a["set"].items() if k.startswith("learn.")}
    overrides = {k: str(v) for k, v in a["set"].items() if not k.startswith("learn.")}
    scen = scenarios.load(a["scenario"], overrides)
    bad = [k for k in a["vary"] if not k.startswith("plant.")]
    if bad:
        return [[Evidence("closed-loop", Status.UNDECIDED, f"`vary {bad[0]}`: only plant "
                          f"parameters (plant.NAME) can vary")] for _ in checks]
    if options.backend == "c":
        try:
            from fuzzyc.backends.cload import CController  # noqa: F401
        except ImportError as exc:
            return [[Evidence("closed-loop", Status.UNDECIDED, f"--backend c: the C back end "
                              f"cannot be loaded ({exc})")] for _ in checks]
    with_baseline = any(n.startswith(BASELINE) for c in checks for n in temporal.names_in(c))
    if with_baseline and not scen.baseline:
        return [[Evidence("closed-loop", Status.UNDECIDED, f"`{BASELINE}...` signals need a "
                          f"scenario with a baseline; {scen.name} names none")] for _ in checks]
    loop = _Loop(model, scen, a["duration"], options.backend, options.seed)
    loop.with_baseline = with_baseline
    loop.progress = None if options.progress else False   # the runtime's bar, on a terminal
    learned = loop.learn(**learning) if learning else ""
    cases = _draw_cases(loop, a["vary"], options.max_examples, options.seed)
    try:
        time, signals = loop.run(cases)
    except (ValueError, TypeError) as exc:   # e.g. a plant that cannot take a param per loop
        return [[Evidence("closed-loop", Status.UNDECIDED, f"the loop did not run with "
                          f"{', '.join(a['vary']) or 'these settings'}: {exc}")] for _ in checks]
    try:
        verdicts = [temporal.evaluate(c, time, signals, loop.params) for c in checks]
    except temporal.UnknownSignal as exc:
        return [[Evidence("closed-loop", Status.UNDECIDED, f"no signal or param named "
                          f"`{exc.args[0]}` in the loop: {', '.join(sorted(signals))}")]
                for _ in checks]
    failing = {i: int(np.argmax(v)) for i, (v, _) in enumerate(verdicts) if v.any()}
    shrunk = _shrink(loop, checks, {i: cases[k] for i, k in failing.items()},
                     {i: _column(time, signals, k) for i, k in failing.items()}, a["vary"],
                     options.shrink_rounds)
    results = []
    for i, (c, (violated, _)) in enumerate(zip(checks, verdicts)):
        if i not in shrunk:
            results.append([Evidence("closed-loop", Status.HELD, f"{len(cases)} loops of "
                                     f"{a['duration']:g} s on scenario {scen.name}{learned}",
                                     cases=len(cases))])
            continue
        case, trace = shrunk[i]
        detail = (f"{int(violated.sum())} of {len(cases)} loops break it; shrunk case: "
                  + (", ".join(f"{k}={v:.6g}" for k, v in case.items() if k != "step")
                     or "nominal plant") + _step_text(case) + learned)
        if options.report_dir:
            from .report import plot_trace
            name = re.sub(r"[^A-Za-z0-9]+", "_", f"{model.name}_{c.text}").strip("_")[:80]
            shown = temporal.names_in(c) + [o.name for o in model.outputs] + sorted(
                {s[0] for s in [case.get("step")] if s})
            trace["plot"] = str(plot_trace(trace, shown, f"{model.name}: {c.text}",
                                           os.path.join(options.report_dir, name + ".png")))
        results.append([Evidence("closed-loop", Status.VIOLATED, detail, cases=len(cases),
                                 trace=trace)])
    return results


def _column(time, signals, k: int):
    return time, {name: v[:, k:k + 1] for name, v in signals.items()}


def _step_text(case: dict) -> str:
    step = case.get("step")
    return "" if not step else f"; step of {step[0]} to {step[2]:.6g} at t={step[1]:.6g} s"


class _Loop:
    """The scenario's blocks around the model's controller, for any batch of cases."""

    def __init__(self, model: Model, scen, duration: float, backend: str, seed: int):
        self.model, self.scen, self.duration, self.backend, self.seed = (
            model, scen, duration, backend, seed)
        self.progress: bool | None = False
        self.with_baseline = False
        self.module = scen.plant_module()
        self.nominal = scen.plant_params(1)
        self.plant_inputs = set(getattr(self.module, "INPUTS", ()))
        self.params = self._controller_model().symbol_values()

    def _controller_model(self) -> Model:
        model = copy.deepcopy(self.model)
        spec = self.scen.controller or {}
        for name, value in (spec.get("params") or {}).items():
            if name in model.params:
                model.params[name].value = float(value)
        for out in model.outputs:
            out.init = float((spec.get("initial") or {}).get(out.name, out.init))
        return model

    def learn(self, cycles: float, eta: float = 0.25, rho: float = 6.0) -> str:
        """`set learn.cycles = N` (and learn.eta, learn.rho): train the file's learnable weights
        on N cycles of the nominal scenario (fuzzyc.learn, batch 1) before the search, so the
        loops check the learned controller."""
        from fuzzyc.controller import Controller
        from fuzzyc.learn import learn
        controller = Controller(self._controller_model(), 1)
        result = learn(controller, self.module, self.scen.plant_params(), int(cycles),
                       self.scen.duration, self.scen.period, eta=float(eta), rho=float(rho))
        self.model = controller.model
        return (f"; after {int(cycles)} learning cycles (PI {result.pi[0]:.4g} -> "
                f"{result.pi[-1]:.4g})")

    def nominal_value(self, key: str) -> float:
        return float(getattr(self.nominal, key.split(".", 1)[1]))

    def run(self, cases: list[dict]):
        """Time and signals of every case; with_baseline adds `baseline_X` for each signal X of
        the scenario's baseline controller on the same cases (plant, steps), e.g. to compare
        the corner error with normal machining."""
        batch = len(cases)
        model = self._controller_model()
        if self.backend == "c":
            from fuzzyc.backends.cload import CController
            controller = CController(model, batch)
        else:
            from fuzzyc.controller import Controller
            controller = Controller(model, batch)
        time, signals = self._run_with(controller, cases)
        if self.with_baseline:
            baseline = self.scen.make("baseline", self.scen.baseline)
            baseline.reset(batch)
            _, theirs = self._run_with(baseline, cases)
            signals.update({BASELINE + name: v for name, v in theirs.items()})
        return time, signals

    def _run_with(self, controller, cases: list[dict]):
        from fuzzyc.runtime import FunctionBlock, PlantBlock, run
        from fuzzyc.runtime.simulate import build
        batch = len(cases)
        blocks = build(self.scen, controller, batch, self.seed)
        k = next(i for i, b in enumerate(blocks) if isinstance(b, PlantBlock))
        varied = {key.split(".", 1)[1]: np.array([c[key] for c in cases], dtype=float)
                  for key in cases[0] if key != "step"}
        blocks[k].params = dataclasses.replace(blocks[k].params, **varied)
        steps = [c.get("step") for c in cases]
        for name in sorted({s[0] for s in steps if s}):
            blocks.insert(k, _disturbance(name, steps, varied, self.nominal, FunctionBlock))
        trace = run(blocks, self.scen.period, self.duration, batch,
                    initial=self.scen.data.get("initial"), progress=self.progress)
        return trace.time, dict(trace.signals)


def _disturbance(name, steps, varied, nominal, FunctionBlock):
    """A per-loop step of a plant input: its varied (or nominal) value, then the step value."""
    before = varied.get(name, np.full(len(steps), float(getattr(nominal, name))))
    at = np.array([s[1] if s and s[0] == name else np.inf for s in steps])
    after = np.array([s[2] if s and s[0] == name else 0.0 for s in steps])

    def value(t):
        return {name: np.where(t >= at, after, before)}
    return FunctionBlock(value, ["t"], [name], name=f"step {name}")


def _draw_cases(loop: _Loop, vary: dict, n: int, seed: int) -> list[dict]:
    """n cases from hypothesis: a value per varied parameter and, for a varied parameter the
    plant also reads as an input (e.g. workpiece height), maybe a step to a new value."""
    fields = {k: st.floats(lo, hi, allow_nan=False) for k, (lo, hi) in vary.items()}
    steppable = [k for k in vary if k.split(".", 1)[1] in loop.plant_inputs]
    step = st.none()
    if steppable:
        step = st.one_of(st.none(), st.sampled_from(steppable).flatmap(
            lambda k: st.tuples(st.just(k.split(".", 1)[1]), st.floats(0, loop.duration),
                                st.floats(*vary[k], allow_nan=False))))
    strategy = st.fixed_dictionaries({**fields, "step": step})
    drawn: list[dict] = []

    @hseed(seed)
    @settings(max_examples=max(1, n), database=None, deadline=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(strategy)
    def collect(case):
        if len(drawn) < n:
            drawn.append(case)

    collect()
    return drawn or [{"step": None}]


def _shrink(loop: _Loop, checks: list[Property], cases: dict[int, dict],
            runs: dict[int, tuple], vary: dict, rounds: int) -> dict[int, tuple[dict, dict]]:
    """Per failing check, simpler failing cases, simplest first: no disturbance step, then each
    parameter at its nominal value, then halfway there; the first that still fails is kept.
    Each round simulates the candidates of every check in one batch."""
    open_ = set(cases)
    for _ in range(rounds):
        groups = {i: _simpler(loop, cases[i], vary) for i in sorted(open_)}
        groups = {i: g for i, g in groups.items() if g}
        if not groups:
            break
        time, signals = loop.run([c for g in groups.values() for c in g])
        offset = 0
        for i, group in groups.items():
            part = {k: v[:, offset:offset + len(group)] for k, v in signals.items()}
            violated, _ = temporal.evaluate(checks[i], time, part, loop.params)
            if violated.any():
                k = int(np.argmax(violated))
                cases[i], runs[i] = group[k], _column(time, part, k)
            else:
                open_.discard(i)
            offset += len(group)
    out = {}
    for i, case in cases.items():
        time, signals = runs[i]
        _, when = temporal.evaluate(checks[i], time, signals, loop.params)
        # keep what the check reads, the controller's outputs and the plant's inputs
        kept = set(temporal.names_in(checks[i])) | set(loop.plant_inputs) | {
            o.name for o in loop.model.outputs}
        out[i] = (case, {"case": {k: v for k, v in case.items() if k != "step"},
                         "step": case.get("step"),
                         "violated_at": None if np.isnan(when[0]) else float(when[0]),
                         "t": time, "signals": {k: v[:, 0] for k, v in signals.items()
                                                if k in kept}})
    return out


def _simpler(loop: _Loop, case: dict, vary: dict) -> list[dict]:
    out = []
    if case.get("step"):
        out.append({**case, "step": None})
    for key, (lo, hi) in vary.items():
        target = min(max(loop.nominal_value(key), lo), hi)
        if abs(case[key] - target) > 1e-9 * max(1.0, abs(target)):
            out.append({**case, key: target})
            out.append({**case, key: 0.5 * (case[key] + target)})
    return out
