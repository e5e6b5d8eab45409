"""Closed-loop search (method 3): hypothesis draws plant parameters, set points, disturbance
steps and sensor faults, the whole set runs as ONE batch of loops (the runtime is batched), the
temporal checks are evaluated on every trace, and a failing case is shrunk toward the
scenario's nominal values in batched rounds (each round simulates every simpler candidate at
once).

A case is a dict: `plant.P` / `controller.P` -> value for the whole run; `step` -> None or
(key, time, value), one varied plant input or controller param stepping to a new value;
`fault` -> None or (signal, kind, start, length), one measured plant output reading NaN or
stuck; `noise` -> the index of the drawn case it comes from: a shrunk variant keeps the plant
noise of its original loop (runtime.noise), so it fails for the same reason. Checks read the
process (a faulty signal's true value); what the sensor said is recorded as `sensed_SIGNAL`."""
from __future__ import annotations

import copy
import dataclasses
import os
import re
from collections.abc import Mapping

import numpy as np
from hypothesis import HealthCheck, Phase, given, seed as hseed, settings, strategies as st

from ..display import plural
from ..escape import OutputFolder
from ..semantics.model import Model, Property
from .draws import without_local_constants
from . import temporal
from .result import Evidence, Status

BASELINE = "baseline_"   # a check's `baseline_X`: signal X of the scenario's baseline controller
SENSED = "sensed_"       # `sensed_X`: what a faulty sensor said of plant output X
EVENTS = ("step", "fault", "noise")   # the entries of a case that are not drawn values


def check(model: Model, prop: Property, checks: list[Property], options) -> list[list[Evidence]]:
    a = prop.args
    learning = {k.split(".", 1)[1]: v for k, v in a["set"].items() if k.startswith("learn.")}
    overrides = {k: str(v) for k, v in a["set"].items() if not k.startswith("learn.")}
    scen = load_scenario(a["scenario"], overrides, options)
    problem = _unsupported(scen, a, options.backend)
    if problem:
        return [[Evidence("closed-loop", Status.UNDECIDED, problem)] for _ in checks]
    with_baseline = any(n.startswith(BASELINE) for c in checks for n in temporal.names_in(c))
    if with_baseline and not scen.baseline:
        return [[Evidence("closed-loop", Status.UNDECIDED, f"`{BASELINE}...` signals need a "
                          f"scenario with a baseline; {scen.name} names none")] for _ in checks]
    proofs = _prove(model, prop, checks, scen, options)
    loop = _Loop(model, scen, a["duration"], options.backend, options.seed)
    loop.with_baseline = with_baseline
    loop.progress = None if options.progress else False   # the runtime's bar, on a terminal
    learned = loop.learn(**learning) if learning else ""
    cases = _draw_cases(loop, a, options.max_examples, options.seed)
    try:
        verdicts, firsts = _search(loop, checks, cases, options.cluster)
    except (ValueError, TypeError) as exc:   # e.g. a plant that cannot take a param per loop
        return [[Evidence("closed-loop", Status.UNDECIDED, f"the loop did not run with "
                          f"{', '.join(a['vary']) or 'these settings'}: {exc}")] for _ in checks]
    except temporal.UnknownSignal as exc:
        return [[Evidence("closed-loop", Status.UNDECIDED, f"no signal or param named "
                          f"`{exc.args[0]}` in the loop: {', '.join(sorted(exc.args[1]))}")]
                for _ in checks]
    failing = {i: int(np.argmax(v)) for i, (v, _) in enumerate(verdicts) if v.any()}
    shrunk = _shrink(loop, checks, {i: cases[k] for i, k in failing.items()}, firsts,
                     a["vary"], options.shrink_rounds)
    results, plots = [], OutputFolder(options.report_dir or ".")
    for i, (c, (violated, _)) in enumerate(zip(checks, verdicts)):
        if i not in shrunk:
            held = Evidence("closed-loop", Status.HELD, f"{plural(len(cases), 'loop')} of "
                            f"{a['duration']:g} s on scenario {scen.name}{learned}",
                            cases=len(cases))
            results.append(proofs[i] + [held])
            continue
        case, trace = shrunk[i]
        detail = (f"{int(violated.sum())} of {len(cases)} loops break it; shrunk case: "
                  + (", ".join(f"{k}={v:.6g}" for k, v in _values(case).items())
                     or "nominal plant") + _event_text(case) + learned
                  + _replay(loop, c, case))
        from .report import plot_trace, trace_marks
        trace.update(trace_marks(c, scen, model, loop.params))   # units and limits, for plots
        trace["shown"] = temporal.names_in(c) + [o.name for o in model.outputs] \
            + _event_signals(case)
        if options.report_dir:
            name = re.sub(r"[^A-Za-z0-9]+", "_", f"{model.name}_{c.text}").strip("_")[:80]
            trace["plot"] = str(plot_trace(trace, trace["shown"], f"{model.name}: {c.text}",
                                           plots.file(name, ".png")))
        results.append(proofs[i] + [Evidence("closed-loop", Status.VIOLATED, detail,
                                             cases=len(cases), trace=trace)])
    return results


def load_scenario(name: str, overrides: dict[str, str], options):
    """The scenario a closed loop names: the user's for that name when the API was given one
    (options.scenarios: a YAML path, or a mapping whose plant may be the user's own object),
    else the shipped scenario of that name."""
    from fuzzyc.plants import scenario as scenarios
    allow = getattr(options, "allow_import", ())
    given = (getattr(options, "scenarios", None) or {}).get(name)
    if given is None:
        return scenarios.load(name, overrides, allow_import=allow)
    if isinstance(given, Mapping):
        return scenarios.from_mapping(name, given, overrides, allow_import=allow)
    if not isinstance(given, (str, os.PathLike)):     # a plant object given bare
        raise TypeError(f"scenario `{name}`: a scenario YAML path or the mapping of its keys "
                        f"({{'plant': ..., 'period': ...}}), not a {type(given).__name__}")
    return scenarios.load(os.fspath(given), overrides, allow_import=allow)


def _search(loop: "_Loop", checks: list[Property], cases: list[dict], cluster=None):
    """Every case against every check: per check (violated (N,), when (N,)) over the cases in
    order, and per failing check the trace of its first failing loop. With a cluster
    (runtime.campaign) the cases run in chunks, there or on Dask; each loop's noise is keyed
    by its case, so the verdicts are those of one batch."""
    if cluster is None:
        parts = [_check_chunk(loop, checks, cases)]
    else:
        import functools
        from fuzzyc.runtime.campaign import chunks, map_chunks
        parts = map_chunks(functools.partial(_check_chunk, loop, checks),
                           [cases[r.start:r.stop] for r in chunks(len(cases), cluster.chunk)],
                           cluster, label="closed loops")
    verdicts = [tuple(np.concatenate([part[0][i][j] for part in parts]) for j in (0, 1))
                for i in range(len(checks))]
    firsts: dict[int, tuple] = {}
    for _, first in parts:
        firsts = {**first, **firsts}      # the earliest chunk's first failing loop wins
    return verdicts, firsts


def _check_chunk(loop: "_Loop", checks: list[Property], cases: list[dict]):
    """One batch of cases: the verdicts of every check and each failing check's first failing
    loop's trace."""
    time, signals = loop.run(cases)
    try:
        verdicts = [temporal.evaluate(c, time, signals, loop.params) for c in checks]
    except temporal.UnknownSignal as exc:    # say which signals there are
        raise temporal.UnknownSignal(exc.args[0], list(signals)) from None
    return verdicts, {i: _column(time, signals, int(np.argmax(v)))
                      for i, (v, _) in enumerate(verdicts) if v.any()}


def _prove(model: Model, prop: Property, checks: list[Property], scen, options
           ) -> list[list[Evidence]]:
    """With --prove: the reachable-set evidence per check (fuzzyc.verifier.reach), timed."""
    if not getattr(options, "prove", False):
        return [[] for _ in checks]
    from .reach.decide import Settings, prove
    settings = Settings(max_boxes=options.prove_boxes, sigmas=options.noise_sigmas)
    return [[e] for e in prove(model, prop, checks, scen, settings)]


def _replay(loop: "_Loop", check: Property, case: dict) -> str:
    """A violation is a plain simulation's: the shrunk case runs again on its own (a batch of
    one, its noise keyed as in the search) and the check is evaluated anew."""
    time, signals = loop.run([case])
    violated, when = temporal.evaluate(check, time, signals, loop.params)
    if violated[0]:
        return f"; replayed alone: violated at t={when[0]:.6g} s"
    return "; replayed alone: not violated (the batch's rounding decided it)"


def _column(time, signals, k: int):
    return time, {name: v[:, k:k + 1] for name, v in signals.items()}


def _unsupported(scen, args: dict, backend: str) -> str:
    """Why this closed loop cannot be searched as written ('' if it can)."""
    setpoints = [k.split(".", 1)[1] for k in args["vary"] if k.startswith("controller.")]
    changing = [n for n in setpoints if len({v for _, v in scen.schedules.get(n, [])}) > 1]
    if changing:
        return (f"`vary controller.{changing[0]}`: scenario {scen.name} already changes "
                f"`{changing[0]}` on a schedule; vary a set point on a scenario that holds it")
    inputs = set(getattr(scen.plant_module(), "INPUTS", ()))
    fixed = [k for k in args.get("steps_before", {})
             if k.startswith("plant.") and k.split(".", 1)[1] not in inputs]
    if fixed:
        return (f"`vary {fixed[0]} ... steps before`: the plant of {scen.name} reads "
                f"`{fixed[0].split('.', 1)[1]}` only at the start; it cannot step")
    outputs = set(getattr(scen.plant_module(), "OUTPUTS", ()))
    unknown = [f[0] for f in args.get("faults", []) if f[0] not in outputs]
    if unknown:
        return (f"`fault {unknown[0]}`: a fault corrupts a measured plant output; the plant of "
                f"{scen.name} has {', '.join(sorted(outputs))}")
    if backend != "c":
        return ""
    try:
        from fuzzyc.backends.c.load import CController  # noqa: F401
    except ImportError as exc:
        return f"--backend c: the C back end cannot be loaded ({exc})"
    return ""


def _values(case: dict) -> dict[str, float]:
    return {k: v for k, v in case.items() if k not in EVENTS}


def _event_text(case: dict) -> str:
    """The shrunk case's step and fault, as the report prints them."""
    text, step, fault = "", case.get("step"), case.get("fault")
    if step:
        text += f"; step of {step[0]} to {step[2]:.6g} at t={step[1]:.6g} s"
    if fault:
        text += (f"; {fault[0]} sensor {'stuck' if fault[1] == 'stuck' else 'reads NaN'} "
                 f"from t={fault[2]:.6g} s for {fault[3]:g} s")
    return text


def _event_signals(case: dict) -> list[str]:
    """Signals a plot of the case should show besides the check's: what stepped, what failed."""
    step, fault = case.get("step"), case.get("fault")
    return ([step[0].split(".", 1)[1]] if step else []) + (
        [fault[0], SENSED + fault[0]] if fault else [])


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
        on N cycles of the nominal scenario (fuzzyc.learning, batch 1) before the search, so the
        loops check the learned controller."""
        from fuzzyc.engine.chain import Controller
        from fuzzyc.learning import learn
        controller = Controller(self._controller_model(), 1)
        result = learn(controller, self.module, self.scen.plant_params(), int(cycles),
                       self.scen.duration, self.scen.period, eta=float(eta), rho=float(rho))
        self.model = controller.model
        return (f"; after {int(cycles)} learning cycles (PI {result.pi[0]:.4g} -> "
                f"{result.pi[-1]:.4g})")

    def nominal_value(self, key: str) -> float:
        kind, name = key.split(".", 1)
        return float(self.params[name] if kind == "controller" else getattr(self.nominal, name))

    def steppable(self, key: str) -> bool:
        """A set point, or a plant parameter the plant also reads as an input (height)."""
        kind, name = key.split(".", 1)
        return kind == "controller" or name in self.plant_inputs

    def run(self, cases: list[dict]):
        """Time and signals of every case; with_baseline adds `baseline_X` for each signal X of
        the scenario's baseline controller on the same cases (plant, steps), e.g. to compare
        the corner error with normal machining."""
        batch = len(cases)
        model = self._controller_model()
        if self.backend == "c":
            from fuzzyc.backends.c.load import CController
            # the header compiles params in: a set point the loop moves (a schedule, a drawn
            # value, a step) becomes an input, read from the bus as the numpy engine follows it
            from fuzzyc.runtime.simulate import params_as_inputs, scheduled_params_as_inputs
            scheduled_params_as_inputs(model, self.scen)
            params_as_inputs(model, self._set_point_values(cases))
            controller = CController(model, batch)
        else:
            from fuzzyc.engine.chain import Controller
            controller = Controller(model, batch)
        time, signals = self._run_with(controller, cases, follow=True)
        if self.with_baseline:
            baseline = self.scen.make("baseline", self.scen.baseline)
            baseline.reset(batch)
            _, theirs = self._run_with(baseline, cases, follow=False)
            signals.update({BASELINE + name: v for name, v in theirs.items()})
        return time, signals

    def _set_point_values(self, cases: list[dict]) -> dict[str, list[float]]:
        """name -> every value the cases give a set point (drawn, or stepped to)."""
        values: dict[str, list[float]] = {}
        for case in cases:
            for key, value in _values(case).items():
                if key.startswith("controller."):
                    values.setdefault(key.split(".", 1)[1], []).append(float(value))
            step = case.get("step")
            if step and step[0].startswith("controller."):
                values.setdefault(step[0].split(".", 1)[1], []).append(float(step[2]))
        return values

    def _run_with(self, controller, cases: list[dict], follow: bool):
        """One batch: plant parameters per loop; a schedule block per stepped or varied key
        before the plant; a sensor-fault block per faulty signal right after it. follow: the
        controller's set points follow their schedules (the baseline has no such params)."""
        from fuzzyc.runtime import ControllerBlock, PlantBlock, ScheduleBlock, run
        from fuzzyc.runtime.simulate import build
        batch = len(cases)
        keys = list(_values(cases[0]))
        drawn = {key.split(".", 1)[1] for key in keys if key.startswith("controller.")}
        # a set point the scenario holds constant on a schedule is drawn instead
        blocks = [b for b in build(self.scen, controller, batch, self.seed)
                  if not (isinstance(b, ScheduleBlock) and b.output in drawn)]
        k = next(i for i, b in enumerate(blocks) if isinstance(b, PlantBlock))
        blocks[k].params = dataclasses.replace(blocks[k].params, **{
            key.split(".", 1)[1]: np.array([c[key] for c in cases], dtype=float)
            for key in keys if key.startswith("plant.")})
        blocks[k].noise_keys = np.array([c.get("noise", i) for i, c in enumerate(cases)])
        scheduled = sorted({c["step"][0] for c in cases if c.get("step")}
                           | {key for key in keys if key.startswith("controller.")})
        faults = sorted({c["fault"][0] for c in cases if c.get("fault")})
        for name in faults:
            blocks.insert(k + 1, _fault(name, cases))
        for key in scheduled:
            blocks.insert(k, _schedule(key, cases, self.nominal_value(key)))
        c = next(i for i, b in enumerate(blocks) if isinstance(b, ControllerBlock))
        unfollowed = sorted(drawn - set(blocks[c].param_inputs))
        if follow and unfollowed and hasattr(controller, "params"):   # C: inputs already
            blocks[c] = dataclasses.replace(blocks[c],
                                            param_inputs=blocks[c].param_inputs + unfollowed)
        trace = run(blocks, self.scen.period, self.duration, batch,
                    initial=self.scen.data.get("initial"), progress=self.progress)
        signals = dict(trace.signals)
        for name in faults:   # checks judge the process; the sensor's reading is kept beside
            signals[SENSED + name] = signals[name]
            signals[name] = signals.pop(f"{name}@plant")
        return trace.time, signals


def _schedule(key: str, cases: list[dict], nominal: float):
    """A per-loop value of a plant input or a set point: the case's value (or the nominal one)
    and, in a case that steps this key, the step value from the step time on."""
    from fuzzyc.runtime import FunctionBlock
    name = key.split(".", 1)[1]
    steps = [c.get("step") if c.get("step") and c["step"][0] == key else None for c in cases]
    before = np.array([c.get(key, nominal) for c in cases], dtype=float)
    at = np.array([s[1] if s else np.inf for s in steps])
    after = np.array([s[2] if s else 0.0 for s in steps])

    def value(t):
        return {name: np.where(t >= at, after, before)}
    return FunctionBlock(value, ["t"], [name], name=f"schedule {name}")


def _fault(signal: str, cases: list[dict]):
    from fuzzyc.runtime import SensorFault
    faults = [c.get("fault") if c.get("fault") and c["fault"][0] == signal else None
              for c in cases]
    return SensorFault(signal, start=np.array([f[2] if f else np.inf for f in faults]),
                       length=np.array([f[3] if f else 0.0 for f in faults]),
                       stuck=np.array([bool(f) and f[1] == "stuck" for f in faults]),
                       name=f"fault {signal}")


def _draw_cases(loop: _Loop, args: dict, n: int, seed: int) -> list[dict]:
    """n cases from hypothesis: a value per varied key; maybe a step of one steppable key (a
    set point, or a plant parameter the plant also reads as an input, e.g. the workpiece
    height) to a new value at a drawn time (before its `steps before` time, if given); maybe
    one of the declared sensor faults, starting at a drawn time."""
    vary, faults = args["vary"], args.get("faults", [])
    fields = {k: st.floats(lo, hi, allow_nan=False) for k, (lo, hi) in vary.items()}
    steppable = [k for k in vary if loop.steppable(k)]
    latest = {k: min(loop.duration, args.get("steps_before", {}).get(k, np.inf))
              for k in steppable}
    step = fault = st.none()
    if steppable:
        step = st.one_of(st.none(), st.sampled_from(steppable).flatmap(
            lambda k: st.tuples(st.just(k), st.floats(0, latest[k]),
                                st.floats(*vary[k], allow_nan=False))))
    if faults:
        fault = st.one_of(st.none(), st.tuples(st.sampled_from(faults),
                                               st.floats(0, loop.duration)).map(
            lambda f: (f[0][0], f[0][1], f[1], f[0][2])))
    strategy = st.fixed_dictionaries({**fields, "step": step, "fault": fault})
    drawn: list[dict] = []

    @hseed(seed)
    @settings(max_examples=max(1, n), database=None, deadline=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(strategy)
    def collect(case):
        if len(drawn) < n:
            drawn.append(case)

    with without_local_constants():
        collect()
    return [{**case, "noise": i} for i, case in enumerate(drawn or [{"step": None,
                                                                     "fault": None}])]


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
        # keep what the check reads, the controller's outputs, the plant's inputs, the set
        # points and what stepped or failed
        kept = set(temporal.names_in(checks[i])) | set(loop.plant_inputs) | {
            o.name for o in loop.model.outputs} | set(_event_signals(case)) | {
            k.split(".", 1)[1] for k in vary if k.startswith("controller.")}
        out[i] = (case, {"case": _values(case), "step": case.get("step"),
                         "fault": case.get("fault"), "noise": case.get("noise"),
                         "violated_at": None if np.isnan(when[0]) else float(when[0]),
                         "t": time, "signals": {k: v[:, 0] for k, v in signals.items()
                                                if k in kept}})
    return out


def _simpler(loop: _Loop, case: dict, vary: dict) -> list[dict]:
    out = []
    for event in ("fault", "step"):
        if case.get(event):
            out.append({**case, event: None})
    for key, (lo, hi) in vary.items():
        target = min(max(loop.nominal_value(key), lo), hi)
        if abs(case[key] - target) > 1e-9 * max(1.0, abs(target)):
            out.append({**case, key: target})
            out.append({**case, key: 0.5 * (case[key] + target)})
    return out
