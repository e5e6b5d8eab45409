"""A generic first-order-plus-dead-time plant, for quick studies: K e^(-L s) / (T s + 1).

    T dy/dt = K u(t - L) - y,   u = input `u` plus input `disturbance` (a load at the input)

Exact for an input held over each period (zero-order hold): over a period the delayed input
is u(k-d-1) for the first f dt and u(k-d) for the rest, where L = (d + f) dt (d whole periods,
0 <= f < 1), and a constant input v held for h gives y -> b y + K (1 - b) v, b = e^(-h/T).
A dead time that is not a whole number of periods is therefore exact too. Gain, time
constant and dead time may be (N,) arrays (a randomized batch); the input history is kept
for the longest dead time of the batch.

Params: gain K, time_constant T (s), dead_time L (s), y0 (the output at t = 0), u0 (the input
before t = 0, what the dead time delivers first). Input `u` (and optional `disturbance`,
added to u), output `y`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .edm_sink import PIGapServo

INPUTS = ("u", "disturbance")
OUTPUTS = ("y",)
# a generic plant: its signals are in whatever unit the study gives them ("-" on the plots)
UNITS = {"u": "-", "disturbance": "-", "y": "-"}


@dataclass
class FopdtParams:
    gain: float = 1.0
    time_constant: float = 1.0    # s
    dead_time: float = 0.0        # s
    y0: float = 0.0
    u0: float = 0.0

    def __post_init__(self) -> None:
        if np.any(np.asarray(self.time_constant) <= 0):
            raise ValueError("time_constant must be > 0 s")
        if np.any(np.asarray(self.dead_time) < 0):
            raise ValueError("dead_time must be >= 0 s")


def initial_state(params: FopdtParams, batch: int, rng: np.random.Generator | None = None
                  ) -> dict[str, np.ndarray]:
    # history[j] = the input j periods ago, grown to the longest dead time at the first step
    # (the period is known only then); rows beyond what was given hold u0
    return {"y": np.broadcast_to(np.asarray(params.y0, float), (batch,)).copy(),
            "history": np.empty((0, batch))}


def _whole_and_fraction(dead_time, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """L / dt split into whole periods d and a fraction f in [0, 1); a ratio within 1e-9 of
    a whole number is that number (0.3 / 0.1 is 2.9999999999999996)."""
    ratio = np.asarray(dead_time, float) / dt
    whole = np.where(np.abs(ratio - np.round(ratio)) < 1e-9, np.round(ratio), np.floor(ratio))
    return whole.astype(int), np.maximum(ratio - whole, 0.0)


def step(params: FopdtParams, state: dict[str, np.ndarray], inputs: dict[str, np.ndarray],
         t: float, dt: float, rng: np.random.Generator | None = None
         ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    y = state["y"]
    batch = y.shape[0]
    u = np.asarray(inputs.get("u", params.u0), float) + np.asarray(
        inputs.get("disturbance", 0.0), float)
    u = np.broadcast_to(u, (batch,))
    whole, fraction = _whole_and_fraction(params.dead_time, dt)
    whole, fraction = np.broadcast_to(whole, (batch,)), np.broadcast_to(fraction, (batch,))
    rows = int(whole.max()) + 2
    past = state["history"][:rows - 1]
    filler = np.broadcast_to(np.asarray(params.u0, float), (rows - 1 - len(past), batch))
    history = np.vstack([u[None, :], past, filler])          # history[j] = u(k - j)
    loops = np.arange(batch)
    early, late = history[whole + 1, loops], history[whole, loops]
    gain, tau = np.asarray(params.gain, float), np.asarray(params.time_constant, float)
    b1, b2 = np.exp(-fraction * dt / tau), np.exp(-(1.0 - fraction) * dt / tau)
    y = b1 * y + gain * (1.0 - b1) * early
    y = b2 * y + gain * (1.0 - b2) * late
    return {"y": y, "history": history}, {"y": y}


@dataclass
class PI(PIGapServo):
    """The crisp PI baseline: the EDM servo's law (conditional integration, output held in
    [-vmax, vmax]) on e = setpoint - y, the set point the bus signal `r`. Default gains: the
    SIMC rule for the scenario's plant (K = 1, T = 5 s, L = 1 s: Kp = T / (K 2L) = 2.5,
    Ti = min(T, 8L) = 5 s, Ki = Kp / Ti = 0.5 /s)."""
    Kp: float = 2.5
    Ki: float = 0.5               # 1/s
    vmax: float = 10.0
    period: float = 0.1
    input_name: str = "y"
    output_name: str = "u"
    setpoint_name: str = "r"

    def __post_init__(self) -> None:
        super().__post_init__()
        self.input_names.append(self.setpoint_name)

    def error(self, signals: dict[str, np.ndarray]) -> np.ndarray:
        return np.asarray(signals[self.setpoint_name], float) - np.asarray(
            signals[self.input_name], float)
