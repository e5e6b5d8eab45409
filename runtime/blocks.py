"""Blocks: the pieces a loop is made of, wired together by signal name.

A block is anything with `input_names`, `output_names`, `reset(batch)` and
`step(signals) -> dict[str, (N,) array]`. The loop keeps one dict of signals (the bus); each
block reads its inputs from it and its outputs are written back, so a later block in the list
sees them in the same period and an earlier one sees them one period later. The bus also holds
two floats, `t` (the time at the start of the period, s) and `dt` (the period, s).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import ModuleType
from typing import Any, Callable

import numpy as np

from .noise import KeyedNoise


def column(value: Any, batch: int) -> np.ndarray:
    """A scalar or (N,) value as a fresh float (N,) array."""
    return np.broadcast_to(np.asarray(value, dtype=float), (batch,)).copy()


def _read(signals: dict, names: list[str], owner: str) -> dict[str, np.ndarray]:
    missing = [n for n in names if n not in signals]
    if missing:
        raise KeyError(f"{owner}: no signal named {', '.join(missing)} on the bus yet "
                       f"(put the block that writes it earlier, or give it an initial value)")
    return {n: signals[n] for n in names}


@dataclass
class PlantBlock:
    """A plant module (`initial_state`, `step`) with its params: a pure function made a block.

    inputs: the plant's input names (read from the bus when present; a plant input that is not
    on the bus is not passed, so the plant uses its params, e.g. a fixed workpiece height);
    None passes every array signal on the bus.
    outputs: the output names the plant returns. `seed` makes the plant's noise reproducible.
    noise_keys: loop i draws the noise stream of key noise_keys[i] (runtime.noise.KeyedNoise:
    its place in a campaign, whatever the chunk; the verifier's shrinking keeps a loop's
    noise); None: one generator for the batch.
    """
    plant: ModuleType
    params: Any
    inputs: list[str] | None
    outputs: list[str]
    seed: int | None = 0
    name: str = "plant"
    noise_keys: np.ndarray | None = None

    def __post_init__(self) -> None:
        self.input_names = list(self.inputs or [])
        self.output_names = list(self.outputs)
        self.state: dict[str, np.ndarray] = {}

    def reset(self, batch: int) -> None:
        self.rng = (np.random.default_rng(self.seed) if self.noise_keys is None
                    else KeyedNoise(self.seed, self.noise_keys))
        self.state = self.plant.initial_state(self.params, batch, self.rng)

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        if self.inputs is None:
            inputs = {n: v for n, v in signals.items() if isinstance(v, np.ndarray)}
        else:
            inputs = {n: signals[n] for n in self.input_names if n in signals}
        self.state, outputs = self.plant.step(self.params, self.state, inputs,
                                              signals["t"], signals["dt"], self.rng)
        return outputs


@dataclass
class ControllerBlock:
    """Anything with input_names/output_names/reset(batch)/step(dict) -> dict.

    `fuzzyc.engine.chain.Controller` and the C-backed controller both fit. `param_inputs` names
    controller params that follow a bus signal (a set-point schedule): each period the value
    on the bus is written into `controller.params` before the step. `rename` maps controller
    output names to bus names. `expose` puts internal signals of the controller (its
    `.signals` after a step, e.g. the scaled errors e1, e2) on the bus for traces and plots.
    """
    controller: Any
    param_inputs: list[str] = field(default_factory=list)
    rename: dict[str, str] = field(default_factory=dict)
    expose: list[str] = field(default_factory=list)
    name: str = "controller"

    def __post_init__(self) -> None:
        self.input_names = list(self.controller.input_names) + list(self.param_inputs)
        self.output_names = ([self.rename.get(n, n) for n in self.controller.output_names]
                             + list(self.expose))

    def reset(self, batch: int) -> None:
        self.controller.reset(batch)

    def initial_outputs(self) -> dict[str, float]:
        """u(-1) of each output, what the plant sees in the first period: from the
        controller's own `initial_outputs()` or else its model's output inits."""
        own = getattr(self.controller, "initial_outputs", None)
        model = getattr(self.controller, "model", None)
        values = own() if own is not None else (
            {o.name: float(o.init) for o in model.outputs} if model is not None else {})
        return {self.rename.get(k, k): v for k, v in values.items()}

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        for name in self.param_inputs:
            self.controller.params[name] = signals[name]
        try:
            inputs = {n: signals[n] for n in self.controller.input_names}
        except KeyError:        # say which ones, and what to do
            inputs = _read(signals, list(self.controller.input_names), self.name)
        outputs = self.controller.step(inputs)
        outputs = {self.rename.get(k, k): v for k, v in outputs.items()} if self.rename \
            else dict(outputs)
        if not self.expose:
            return outputs
        internal = getattr(self.controller, "signals", {})
        missing = [n for n in self.expose if n not in internal]
        if missing:
            raise KeyError(f"{self.name}: the controller has no internal signal "
                           f"{', '.join(missing)}")
        outputs.update({n: internal[n] for n in self.expose})
        return outputs


@dataclass
class FunctionBlock:
    """A stateless function of named inputs: fn(**inputs) -> dict of outputs."""
    fn: Callable[..., dict[str, np.ndarray]]
    input_names: list[str]
    output_names: list[str]
    name: str = "function"

    def reset(self, batch: int) -> None:
        self.batch = batch

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        return self.fn(**_read(signals, self.input_names, self.name))


@dataclass
class ScheduleBlock:
    """A piecewise-constant signal over time: [(t0, v0), (t1, v1), ...], vk from tk on.

    Set-point changes and disturbances (workpiece-height steps) are schedules on the bus.
    """
    output: str
    points: list[tuple[float, float]]
    name: str = "schedule"

    def __post_init__(self) -> None:
        pts = sorted((float(t), float(v)) for t, v in self.points)
        if not pts:
            raise ValueError(f"schedule {self.output}: no points")
        self._times = np.array([t for t, _ in pts])
        self._values = np.array([v for _, v in pts])
        self.input_names: list[str] = []
        self.output_names = [self.output]

    def _points_up_to(self, t: float) -> int:
        """How many points lie at or before t (a float step landing a hair before a point
        counts as on it)."""
        return int(np.searchsorted(self._times, t + 1e-12, side="right"))

    def value_at(self, t: float) -> float:
        return float(self._values[max(self._points_up_to(t) - 1, 0)])

    def reset(self, batch: int) -> None:
        self.batch = batch
        self._held: tuple[float, np.ndarray] | None = None
        self._since, self._until = np.inf, -np.inf     # where value_at gives the held value

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        # the same array while the value holds (blocks never write into the bus's arrays);
        # value_at's search only when t leaves the interval between the points around it
        t = signals["t"] + 1e-12
        if not self._since <= t < self._until:
            k = self._points_up_to(signals["t"])
            self._since = self._times[k - 1] if k > 0 else -np.inf
            self._until = self._times[k] if k < len(self._times) else np.inf
            value = self.value_at(signals["t"])
            if self._held is None or self._held[0] != value:
                self._held = (value, np.full(self.batch, value))
        return {self.output: self._held[1]}
