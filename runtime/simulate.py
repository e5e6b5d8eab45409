"""A scenario made runnable: the blocks it describes, the run, and its summary.

Block order in every period: schedules (set points, disturbances) -> plant (driven by the
controller outputs of the previous period, u(-1) the first time) -> observers (estimators,
filters) -> controller (reads this period's measurements; its outputs act next period).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from . import metrics as M
from .blocks import ControllerBlock, PlantBlock, ScheduleBlock
from .loop import run
from .noise import KeyedNoise
from .trace import Trace

METRICS = {
    "settling_time": lambda t, y, target, spec: M.settling_time(t, y, target, spec["band"]),
    "overshoot": lambda t, y, target, spec: M.overshoot(y, target),
    "steady_state_error": lambda t, y, target, spec: M.steady_state_error(
        y, target, spec.get("tail", 0.2)),
    "chattering": lambda t, y, target, spec: M.chattering(y, spec.get("tail", 0.5)),
    "steady_change": lambda t, y, target, spec: M.steady_change(y, spec.get("tail", 0.2)),
    "events": lambda t, y, target, spec: M.event_count(y),
    "max": lambda t, y, target, spec: np.max(y, axis=0),
    "std": lambda t, y, target, spec: np.std(y, axis=0),
    "mean_abs_error": lambda t, y, target, spec: np.mean(np.abs(y - target), axis=0),
    # (last - first) / elapsed: a removal or erosion rate from a cumulative signal
    "rate": lambda t, y, target, spec: (y[-1] - y[0]) / max(t[-1] - t[0], 1e-300),
    "min": lambda t, y, target, spec: np.min(y, axis=0),
    "final": lambda t, y, target, spec: np.mean(y[-max(1, len(y) // 20):], axis=0),
    "mean": lambda t, y, target, spec: np.mean(y[int(len(y) * (1 - spec.get("tail", 1.0))):],
                                               axis=0),
    # the first time a 0/1 signal turns on (machining time: `done`); NaN if never
    "time_until": lambda t, y, target, spec: np.where(
        (y > 0.5).any(axis=0), t[np.argmax(y > 0.5, axis=0)], np.nan),
}


def load_controller(scenario, batch: int, backend: str = "numpy", semantics: str = "exact"):
    """The scenario's rule base (.fz, .fll, .fcl, .fis or FILE.fcl::NAME, through
    fuzzyc.formats.load_any) with its params and initial outputs applied, as a controller.

    An imported model's output `X_out` (the importers' pass-through of rule-base output X) is
    the bus signal X, so an FLL `OutputVariable: velocity` drives the plant's `velocity` (and
    `controller.initial` names it `velocity`). Inputs the loop does not have, or outputs no
    block reads, are an error naming them (check_signals)."""
    from fuzzyc.formats import load_any, split_block
    ref = rulebase_ref(scenario)
    model = load_any(ref)
    imported = split_block(ref)[0].suffix.lower() != ".fz"
    rename = _rulebase_names(model) if imported else {}
    check_signals(scenario, model, rename)
    spec = scenario.controller
    for name, value in (spec.get("params") or {}).items():
        if name not in model.params:
            raise scenario.error(f"controller.params.{name}",
                                 f"the rule base has no param `{name}`; known: "
                                 + (", ".join(model.params) or "none"))
        model.params[name].value = float(value)
    outputs = {rename.get(o.name, o.name): o for o in model.outputs}
    for name, value in (spec.get("initial") or {}).items():
        if name not in outputs:
            raise scenario.error(f"controller.initial.{name}",
                                 f"the rule base has no output `{name}`")
        outputs[name].init = float(value)
    if backend == "c":
        from fuzzyc.backends.c.load import CController
        from fuzzyc.formats.tool_semantics import with_tool_semantics
        scheduled_params_as_inputs(model, scenario)
        controller = CController(with_tool_semantics(model, semantics, "--backend c"), batch)
    else:
        from fuzzyc.engine.chain import Controller
        controller = Controller(model, batch, semantics)
    return BusNames(controller, rename) if rename else controller


def scheduled_params_as_inputs(model, scenario) -> list[str]:
    """Turn each param the scenario schedules (a set point `r`) into an input signal of the
    model, in place; the names turned. The C header compiles a param in as a constant
    (`static const NAME_real NAME_PARAM_r`), so a schedule could not move it; as an input it is
    read from in[] each step, where the loop puts the schedule's value from the bus (the numpy
    engine instead follows the param, ControllerBlock.param_inputs). The input's range is the
    schedule's values and the param's own (the C reads inputs as they come: the range is
    documentation, no clamp)."""
    return params_as_inputs(model, {name: [v for _, v in points]
                                    for name, points in scenario.schedules.items()})


def params_as_inputs(model, values: dict[str, list[float]]) -> list[str]:
    """Each param of `values` (name -> the values the loop gives it) as an input signal of the
    model, in place (see scheduled_params_as_inputs); the names turned."""
    from fuzzyc.semantics.model import Signal
    turned = []
    for name, given in values.items():
        param = model.params.get(name)
        if param is None:
            continue
        span = [float(v) for v in given] + [float(param.value)]
        model.signals.append(Signal(name, min(span), max(span), param.unit, param.loc))
        del model.params[name]
        turned.append(name)
    return turned


def rulebase_ref(scenario) -> str:
    """The scenario's rule file as load_any takes it (a `::NAME` block choice kept)."""
    ref = scenario.rulebase_ref()
    if ref is None:
        raise scenario.error("controller", "this scenario names no rule base: give FILE")
    return ref


def _rulebase_names(model) -> dict[str, str]:
    """{X_out: X} for each output that is the importers' pass-through of rule-base output X."""
    names = {v.name for v in model.rulebase.outputs}
    return {o.name: o.name[:-4] for o in model.outputs
            if o.name.endswith("_out") and o.name[:-4] in names and str(o.expr) == o.name[:-4]}


class BusNames:
    """A controller whose outputs go on the bus under other names; all else is the wrapped
    controller's (model, params, signals, reset...). The model keeps its names: the C back end
    would refuse an output named like a rule-base variable."""

    def __init__(self, controller, rename: dict[str, str]):
        self.controller, self.rename = controller, rename
        self.output_names = [rename.get(n, n) for n in controller.output_names]

    def __getattr__(self, name: str):
        if name == "controller":        # not yet set (a copy being made): no recursion
            raise AttributeError(name)
        return getattr(self.controller, name)

    def step(self, inputs: dict) -> dict:
        return {self.rename.get(k, k): v for k, v in self.controller.step(inputs).items()}

    def initial_outputs(self) -> dict[str, float]:
        return {self.rename.get(o.name, o.name): float(o.init)
                for o in self.controller.model.outputs}


def check_signals(scenario, model, rename: dict[str, str] | None = None) -> None:
    """Every input of the model is a signal of the scenario's loop and every output (by its bus
    name, see BusNames) is read by the plant or an observer; otherwise a FuzzycError at the
    rule file's declarations naming them (a misspelt name would otherwise stop the run with a
    KeyError or, for a plant that falls back to its params, run the loop open)."""
    from fuzzyc.errors import Reporter
    outputs = [((rename or {}).get(o.name, o.name), o) for o in model.outputs]
    offered, read = _loop_signals(scenario)
    report = Reporter(model.source_path or model.name, model.source_text or "")
    where = f"scenario `{scenario.name}` (plant {scenario.plant_name})"
    if offered is not None:
        offered |= {name for name, _ in outputs}     # its own outputs, one period late
        for signal in model.signals:
            if signal.name not in offered:
                report.error(signal.loc, f"input `{signal.name}` is not a signal of {where}; "
                                         f"it has: {', '.join(sorted(offered))}")
    if read is not None:
        for name, out in outputs:
            if name not in read:
                report.error(out.loc, f"output `{name}` drives nothing in {where}; it reads: "
                                      f"{', '.join(sorted(read))}")
    report.raise_if_any()


def _loop_signals(scenario) -> tuple[set[str] | None, set[str] | None]:
    """The signals the loop offers a controller and those it reads from one; None where the
    plant does not declare its OUTPUTS or INPUTS (then nothing can be checked)."""
    module = scenario.plant_module()
    observers = make_observers(scenario)
    plant_in, plant_out = getattr(module, "INPUTS", None), getattr(module, "OUTPUTS", None)
    offered = None if plant_out is None else {
        *scenario.schedules, *plant_out, *(scenario.data.get("initial") or {}),
        *(n for b in observers for n in b.output_names)}
    read = None if plant_in is None else {*plant_in, *(n for b in observers for n in b.input_names)}
    return offered, read


def make_observers(scenario) -> list:
    """The scenario's observer blocks (estimators, filters), in its order."""
    return [scenario.make(f"observers.{i}", spec)
            for i, spec in enumerate(scenario.data.get("observers") or [])]


def signal_units(scenario) -> dict[str, str]:
    """signal -> unit, for plot axes: the plant module's UNITS, the observers' (`units(known)`:
    a filter's output has its input's unit), then the rule file's declarations (its inputs,
    outputs and `let` steps). A signal none of them names has none."""
    from fuzzyc.formats import load_any
    units = dict(getattr(scenario.plant_module(), "UNITS", {}))
    for block in make_observers(scenario):
        if hasattr(block, "units"):
            units.update(block.units(units))
    ref = scenario.rulebase_ref()
    if ref is not None:
        model = load_any(ref)
        for item in (*model.signals, *model.outputs, *model.steps):
            if item.unit:
                units.setdefault(item.name, item.unit)
    for signal, target in references(scenario).items():   # a set point has its signal's unit
        if isinstance(target, str) and signal in units:
            units.setdefault(target, units[signal])
    return units


def build(scenario, controller: Any, batch: int = 1, seed: int = 0,
          randomize: bool = False, expose: list[str] | tuple = (), first: int = 0) -> list:
    """The blocks of one scenario around `controller` (a rule-base controller or a baseline).

    expose: internal controller signals to put on the bus (the numpy engine has them all;
    the C back end only its inputs and outputs). first: the campaign's number of the batch's
    first loop: loop k draws its plant params and noise from stream first + k
    (runtime.noise.KeyedNoise), so a campaign split into batches runs the same loops."""
    loops = np.arange(first, first + batch)
    module = scenario.plant_module()
    params = scenario.plant_params(batch, KeyedNoise(seed, loops, stream=1), randomize)
    schedules = [ScheduleBlock(name, points) for name, points in scenario.schedules.items()]
    inputs = getattr(module, "INPUTS", None)
    plant = PlantBlock(module, params, None if inputs is None else list(inputs),
                       list(getattr(module, "OUTPUTS", ())), seed=seed, noise_keys=loops)
    observers = make_observers(scenario)
    followed = _followed_params(scenario, controller)
    control = ControllerBlock(controller, followed, expose=list(expose))
    _check_observer_inputs(scenario, module, observers, control)
    _check_plant_inputs(scenario, module, observers, control)
    return [*schedules, plant, *observers, control]


def _check_plant_inputs(scenario, module, observers: list, control) -> None:
    """The plant inputs it has no fallback for (REQUIRED_INPUTS) come from the controller, a
    schedule, `initial` or an observer; otherwise a FuzzycError at the plant, not a KeyError
    in its first step (a baseline of another process drives none of them)."""
    offered = {*scenario.schedules, *(scenario.data.get("initial") or {}), *control.output_names}
    for block in observers:
        offered |= set(getattr(block, "output_names", []))
    missing = [n for n in getattr(module, "REQUIRED_INPUTS", ()) if n not in offered]
    if missing:
        raise scenario.error("plant.model",
                             f"the plant needs `{missing[0]}` from the controller, a schedule or "
                             f"`initial`; the controller gives "
                             f"{', '.join(control.output_names) or 'nothing'}")


def _check_observer_inputs(scenario, module, observers: list, control) -> None:
    """Each observer reads signals that are on the bus when it runs (schedules, the plant's
    outputs, initial values, the controller's u(-1), earlier observers' outputs); otherwise a
    FuzzycError at the observer, not a KeyError in its first step. Not checkable for a plant
    that does not declare its OUTPUTS."""
    outputs = getattr(module, "OUTPUTS", None)
    if outputs is None:
        return
    offered = {"t", "dt", *scenario.schedules, *outputs, *(scenario.data.get("initial") or {}),
               *control.initial_outputs()}
    for i, block in enumerate(observers):
        missing = [n for n in getattr(block, "input_names", []) if n not in offered]
        if missing:
            raise scenario.error(f"observers.{i}",
                                 f"reads `{missing[0]}`, which is not on the bus before it; "
                                 f"there are: {', '.join(sorted(offered))}")
        offered |= set(getattr(block, "output_names", []))


def _followed_params(scenario, controller) -> list[str]:
    """The controller params that follow a schedule. A controller without a `params` dict
    (the C back end compiles them in) can only run schedules that keep the compiled value."""
    model = getattr(controller, "model", None)
    names = [n for n in scenario.schedules if model is not None and n in model.params]
    if hasattr(controller, "params"):
        return names
    for name in names:
        values = {v for _, v in scenario.schedules[name]}
        if values != {model.params[name].value}:
            raise scenario.error(f"schedules.{name}",
                                 f"this back end compiles `{name}` in as "
                                 f"{model.params[name].value:g}; a schedule that changes it "
                                 f"needs --backend numpy")
    return []


def simulate(scenario, batch: int = 1, baseline: bool = False, backend: str = "numpy",
             seed: int = 0, randomize: bool = False, progress: bool | None = False,
             record: list[str] | None = None, pace: str = "sim", first: int = 0,
             semantics: str = "exact") -> Trace:
    """Run a scenario with its rule base (or, with baseline=True, its baseline controller).
    first: the campaign's number of the first loop (build; runtime.campaign)."""
    if baseline:
        if not scenario.baseline:
            raise scenario.error("baseline", "this scenario names no baseline")
        controller = scenario.make("baseline", scenario.baseline)
    else:
        controller = load_controller(scenario, batch, backend, semantics)
    own_signals = backend == "numpy" and not baseline
    expose = (scenario.controller.get("expose") or []) if own_signals else []
    blocks = build(scenario, controller, batch, seed, randomize, expose, first)
    trace = run(blocks, scenario.period, scenario.duration, batch, pace=pace, progress=progress,
                initial=scenario.data.get("initial"), record=record)
    trace.meta.update(scenario=scenario.name, controller="baseline" if baseline else "fuzzy")
    return trace


def _target(scenario, trace: Trace, spec: dict, dotted: str):
    target = spec.get("target")
    if isinstance(target, str):
        if target not in trace:
            raise scenario.error(f"{dotted}.target", f"`{target}` is not a recorded signal",
                                 of_value=True)
        return trace[target]
    return 0.0 if target is None else float(target)


def references(scenario) -> dict[str, str | float]:
    """signal -> its target in the metrics (a set-point signal or a number), for plots."""
    return {m["signal"]: m["target"] for m in scenario.metrics
            if m.get("signal") and m.get("target") is not None}


def summarize(scenario, trace: Trace) -> dict[str, dict[str, float]]:
    """metric label -> {mean, min, max, unit} over the batch (one loop: all three equal)."""
    return summarize_values(scenario, loop_metrics(scenario, trace))


def summarize_values(scenario, values: dict[str, np.ndarray]) -> dict[str, dict[str, float]]:
    """metric label -> {mean, min, max, unit} of loop_metrics' per-loop values (NaN where no
    loop has a finite value)."""
    units = {_label(spec): spec.get("unit", "") for spec in scenario.metrics}
    out: dict[str, dict[str, float]] = {}
    for label, v in values.items():
        finite = np.isfinite(v).any()
        out[label] = {key: float(fn(v)) if finite else float("nan") for key, fn in
                      (("mean", np.nanmean), ("min", np.nanmin), ("max", np.nanmax))}
        out[label]["unit"] = units[label]
    return out


def _label(spec: dict) -> str:
    return spec.get("label") or f"{spec.get('name')}({spec.get('signal')})"


def loop_metrics(scenario, trace: Trace) -> dict[str, np.ndarray]:
    """metric label -> its (N,) values, one per loop of the batch.

    A metric spec may say `smooth: SECONDS` (trailing moving average of signal and target
    first: a 40-ms count is noisy), `after: SECONDS` (judge only from then on), `where: FLAG`
    (judge only the samples where the 0/1 signal FLAG is on: the force error while the tool
    cuts) and `scale: K` (the value times K: mm/s as mm/min)."""
    out: dict[str, np.ndarray] = {}
    for i, spec in enumerate(scenario.metrics):
        kind, signal = spec.get("name"), spec.get("signal")
        if kind not in METRICS:
            raise scenario.error(f"metrics.{i}.name",
                                 f"unknown metric `{kind}`; known: {' '.join(sorted(METRICS))}")
        if signal not in trace:
            raise scenario.error(f"metrics.{i}.signal", f"no recorded signal `{signal}`",
                                 of_value=True)
        y, target = trace[signal], _target(scenario, trace, spec, f"metrics.{i}")
        if spec.get("smooth"):
            y = M.moving_average(y, int(round(float(spec["smooth"]) / trace.period)))
            if isinstance(target, np.ndarray):
                target = M.moving_average(target, int(round(float(spec["smooth"]) / trace.period)))
        keep = trace.time >= float(spec.get("after", 0.0))
        if not keep.any():
            raise scenario.error(f"metrics.{i}.after", f"the run ends at {trace.time[-1]:g} s, "
                                 "before this metric starts", of_value=True)
        target = target[keep] if isinstance(target, np.ndarray) else target
        values = METRICS[kind](trace.time[keep], y[keep], target, spec)
        if spec.get("where"):
            values = _where(scenario, trace, spec, i, kind, y[keep], target, keep)
        out[_label(spec)] = np.broadcast_to(values * float(spec.get("scale", 1.0)),
                                            (trace.batch,)).astype(float)
    return out


def _where(scenario, trace: Trace, spec: dict, i: int, kind: str, y: np.ndarray, target,
           keep: np.ndarray) -> np.ndarray:
    """mean_abs_error or mean of y over the samples where spec['where'] is on, per loop
    (NaN for a loop where it never is)."""
    flag_name = spec["where"]
    if flag_name not in trace:
        raise scenario.error(f"metrics.{i}.where", f"no recorded signal `{flag_name}`")
    if kind not in ("mean", "mean_abs_error"):
        raise scenario.error(f"metrics.{i}.where", f"`where` goes with mean and "
                             f"mean_abs_error, not {kind}")
    on = trace[flag_name][keep] > 0.5
    value = np.abs(y - target) if kind == "mean_abs_error" else y
    count = on.sum(axis=0)
    total = np.where(on, value, 0.0).sum(axis=0)
    return np.where(count > 0, total / np.maximum(count, 1), np.nan)
