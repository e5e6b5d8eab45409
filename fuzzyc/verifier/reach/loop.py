"""The closed loop of a `closed_loop` property on affine forms, for a batch of boxes of its
`vary` ranges: the scenario's plant (its `set_step`), its observers (their `set_step`) and the
model's chain, in the order the runtime runs them (plant, observers, controller; the plant
reads the controller's outputs of the period before).

What the sets stand for, per loop of a box:
- `vary plant.P`: one value in the box for the whole run (the plant must list P in its
  SET_VARIABLE);
- `vary controller.P`, and `vary plant.P` of a P the plant also reads as an input (the
  workpiece height): a value for the start and, as the search may step P once, a value it
  steps to and the time of the step (before its `steps before` time, or the run's end): three
  box dimensions (`step_keys`); no step is the step to the same value. A stepped plant input
  reaches the plant as its input, the start value as the param. With one stepped key the
  step is taken once: each box runs as two copies, the loops before and after their step,
  joined where the step may happen, beside a third where each period may choose either value
  anew (once.py); with several stepped keys only that per-period choice (`per_period`);
- plant noise: whatever the plant's `set_step` covers (it says which bound it assumes).
Sensor faults, `baseline_` signals and observers without `set_step` are refused by name.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ...semantics.model import Model
from .affine import Affine, Symbols, monotone, reduce
from .chain import SetController, Unsupported
from .param_step import StepOnce, per_period

STEP = "step:"         # the box dimensions of a set-point step: step:controller.P:value/time
KEEP_SYMBOLS = 80      # symbols kept when the run reduces (plus one per live form)


class Noise:
    """What a plant's set_step uses to make new symbols: `widen(x, radius)`,
    `monotone(x, f)` and the Gaussian bound `sigmas`."""

    def __init__(self, sym: Symbols, sigmas: float):
        self.sym, self.sigmas = sym, sigmas

    def form(self, x) -> Affine:
        return x if isinstance(x, Affine) else Affine(self.sym, x)

    def widen(self, x, radius) -> Affine:
        return self.form(x).with_error(radius)

    def monotone(self, x, f, increasing: bool = True) -> Affine:
        return self.form(x).apply(monotone(f, increasing))


class SetLoop:
    def __init__(self, model: Model, scen, args: dict, boxes: dict[str, tuple], sigmas: float):
        """boxes: vary key -> (lo (B,), hi (B,))."""
        if args.get("faults"):
            raise Unsupported("sensor faults (`fault ...`): no set-valued model of a stuck or "
                              "NaN sensor")
        self.model, self.scen, self.args = model, scen, args
        self.module = scen.plant_module()
        missing = [f for f in ("set_step", "set_initial_state") if not hasattr(self.module, f)]
        if missing:     # a plant of the user's may have one without the other
            raise Unsupported(f"plant `{scen.data['plant']['model']}` has no set-valued step "
                              f"({missing[0]})")
        self.batch = len(next(iter(boxes.values()))[0]) if boxes else 1
        self.boxes, self.sigmas = boxes, sigmas
        self.duration, self.period = args["duration"], scen.period
        stepped = [k for k in boxes if k.startswith(STEP) and k.endswith(":time")]
        # one stepped key: three copies per box (once.py); several keep the per-period choice
        self.once = StepOnce(boxes[stepped[0]], self.period,
                             getattr(self.module, "SET_JOIN", {})) if len(stepped) == 1 else None
        self.copies = StepOnce.COPIES if self.once else 1
        movable = getattr(self.module, "SET_VARIABLE", ())
        for key in boxes:
            if key.startswith(STEP):
                continue
            kind, name = key.split(".", 1)
            if kind == "plant" and name not in movable:
                raise Unsupported(f"`vary {key}`: the set step of "
                                  f"{scen.data['plant']['model']} takes only "
                                  f"{', '.join(movable) or 'no parameter'} as a set")
        self.observers = [scen.make(f"observers.{i}", spec)
                          for i, spec in enumerate(scen.data.get("observers") or [])]
        for block in self.observers:
            if not hasattr(block, "set_step"):
                raise Unsupported(f"observer `{type(block).__name__}` has no set-valued step")

    def run(self, record: list[str], on_step=None):
        """Yield (time, {signal: Affine}) after every period (the runtime records the bus
        after the period, at t = (k + 1) period). With a step taken once (`copies` 3) the
        forms have three rows per box: box b's loops that have not stepped in row b, those
        that have in row batch + b, all of them by the per-period choice in row 2 batch + b
        (once.py)."""
        sym = Symbols(self.batch * self.copies)
        noise = Noise(sym, self.sigmas)
        nominal = self.scen.plant_params(1)
        boxes = StepOnce.copied(self.boxes) if self.once else self.boxes
        plant_sets = {k.split(".", 1)[1]: Affine.interval(sym, *v)
                      for k, v in boxes.items() if k.startswith("plant.")}
        params = dataclasses.replace(nominal)
        state = self.module.set_initial_state(params, noise=noise, **{
            name: plant_sets.get(name, getattr(nominal, name))
            for name in getattr(self.module, "SET_VARIABLE", ())})
        varied = {**{f"plant.{name}": form for name, form in plant_sets.items()},
                  **{k: Affine.interval(sym, *v) for k, v in boxes.items()
                     if k.startswith("controller.")}}
        after = {key: Affine.interval(sym, *boxes[f"{STEP}{key}:value"])
                 for key in varied if f"{STEP}{key}:value" in boxes}
        at = {key: boxes[f"{STEP}{key}:time"] for key in after}
        params_c = self._controller_params()
        controller = SetController(self._controller_model(params_c), sym, dict(params_c))
        for block in self.observers:
            block.set_reset()
        bus = {o.name: float(o.init) for o in controller.model.outputs}
        bus.update({k: float(v) for k, v in (self.scen.data.get("initial") or {}).items()})
        inputs = set(getattr(self.module, "INPUTS", ()))
        steps = int(round(self.duration / self.period))
        for k in range(steps):
            t = k * self.period
            if self.once:
                self.once.advance(t, [state, bus, controller.state] +
                                  [block.set_state for block in self.observers])
            for name, points in self.scen.schedules.items():
                value = float([v for at, v in points if at <= t + 1e-12][-1])
                bus[name] = value
                if name in controller.params:
                    controller.params[name] = value
            for key, form in varied.items():
                kind, name = key.split(".", 1)
                value = form
                if key in after:
                    stepped = self.once.param if self.once else per_period
                    value = stepped(sym, form, after[key], at[key], t)
                if kind == "controller":
                    controller.params[name] = value
                elif key in after:          # a stepped plant input (the workpiece height)
                    bus[name] = value
            state, out = self.module.set_step(params, state, {n: bus[n] for n in inputs
                                                               if n in bus}, t, self.period,
                                              noise)
            bus.update(out)
            for block in self.observers:
                bus.update(block.set_step(bus))
            bus.update(controller.step({n: bus[n] for n in self._signal_names()}))
            signals = {**controller.signals, **bus}
            missing = [n for n in record if n not in signals and n not in controller.params]
            if missing:
                raise Unsupported(f"no signal `{missing[0]}` in the set-valued loop")
            yield (k + 1) * self.period, {n: signals.get(n, controller.params.get(n))
                                          for n in record}
            if sym.count > 2 * KEEP_SYMBOLS:
                self._reduce(sym, state, bus, controller, varied, after)

    def _signal_names(self) -> list[str]:
        return [s.name for s in self.model.signals]

    def _reduce(self, sym, state, bus, controller, varied, after) -> None:
        """Reduce the symbols of every form that lives into the next period (a form held in
        two places stays one form)."""
        places = [state, bus, controller.state, controller.params, varied, after] + \
            [block.set_state for block in self.observers]
        live = [(d, k, v) for d in places for k, v in d.items() if isinstance(v, Affine)]
        unique = list({id(v): v for _, _, v in live}.values())
        reduced = dict(zip(map(id, unique), reduce(sym, unique, KEEP_SYMBOLS,
                                                     self.once and self.once.groups)))
        for d, k, v in live:
            d[k] = reduced[id(v)]

    def _controller_params(self) -> dict:
        values = self.model.symbol_values()
        spec = self.scen.controller or {}
        values.update({k: float(v) for k, v in (spec.get("params") or {}).items()
                       if k in values})
        return values

    def _controller_model(self, params: dict) -> Model:
        spec = self.scen.controller or {}
        model = dataclasses.replace(self.model, outputs=[
            dataclasses.replace(o, init=float((spec.get("initial") or {}).get(o.name, o.init)))
            for o in self.model.outputs])
        return model


def step_keys(args: dict, duration: float, plant_inputs=()) -> dict[str, tuple[float, float]]:
    """The extra dimensions of a `vary` range the search may step (a `controller.P`, or a
    `plant.P` the plant also reads as an input, one of plant_inputs): the value it may step to
    and when (before its `steps before` time, or the run's end), as `vary` ranges."""
    out = {}
    for key, rng in args["vary"].items():
        kind, name = key.split(".", 1)
        if kind == "controller" or name in plant_inputs:
            out[f"{STEP}{key}:value"] = tuple(rng)
            out[f"{STEP}{key}:time"] = (0.0, min(duration, args.get("steps_before", {}).get(
                key, duration)))
    return out


def split(boxes: dict[str, tuple], which: np.ndarray, full: dict[str, tuple]
          ) -> dict[str, tuple]:
    """The boxes `which` (indices), each cut in two across its widest side (relative to the
    whole range)."""
    if not boxes:
        return boxes
    keys = list(boxes)
    lo = np.stack([boxes[k][0][which] for k in keys], axis=1)
    hi = np.stack([boxes[k][1][which] for k in keys], axis=1)
    span = np.array([full[k][1] - full[k][0] for k in keys], dtype=float)
    axis = np.argmax((hi - lo) / np.where(span > 0, span, 1.0), axis=1)
    mid = 0.5 * (lo + hi)
    rows = np.arange(len(lo))
    lo2, hi1 = lo.copy(), hi.copy()
    hi1[rows, axis] = mid[rows, axis]
    lo2[rows, axis] = mid[rows, axis]
    new_lo, new_hi = np.concatenate([lo, lo2]), np.concatenate([hi1, hi])
    return {k: (new_lo[:, i], new_hi[:, i]) for i, k in enumerate(keys)}
