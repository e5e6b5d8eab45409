"""EDM sinking gap servo plant: moving-coil actuator, spark gap, erosion, noise (seeds/002).

Roberts (2014) gives the facts; the missing numbers are ours and marked "assumption".

Actuator (SMAC LCA25-010 moving coil, thesis): R = 12.4 ohm, Kf = 7 N/A, Kb = 8 V/(m/s),
12 mm stroke, supply <= 48 V. The thesis's most stable scheme is a cascade: the gap-voltage
servo commands a velocity, an inner loop makes the coil follow it. Here the inner loop is a
proportional velocity drive, coil voltage u = sat_48V(Kv (v_cmd - v)), and with the coil
inductance neglected (assumption: L/R is far below the 1 ms sample)
    i = (u - Kb v) / R,   m dv/dt = Kf i - c v.
assumption: moving mass m = 0.15 kg (coil, shaft and a small electrode), viscous damping
c = 5 N s/m (bearing and seal friction), Kv = 400 V/(m/s) (inner loop a few ms fast).

Gap (thesis: open circuit about 100 V, burn about 40 V, short about 0 V, normal mean about 50 V
at gaps of 20-100 um; the mean voltage grows with the gap "mainly through longer ignition delay,
not necessarily linearly"):
    V(g) = 0                                  g <= g_short (short circuit)
    V(g) = V_burn + (V_open - V_burn) * min(1, ((g - g_short) / (g_open - g_short))^2)
assumption: g_short = 5 um, g_open = 100 um, quadratic ignition-delay law (50 V at about 44 um).

Erosion (thesis): the workpiece surface recedes at dWSH/dt = max(0, C - k |e|), e = V - V_best.
assumption: C = 0.2 mm/min (the thesis's overall feed), V_best = 50 V (normal sparking), and
k = C / 30 V so erosion stops at a short (0 V) and at an open gap (100 V).

Noise on the measured voltage (thesis: 50 Hz mains, its 100 Hz harmonic, spark interference):
assumption: 5 V at 50 Hz, 2 V at 100 Hz (random phases per batch element), white spark noise of
8 V standard deviation per sample (drawn from the rng `step` is given; none without one).

Input `velocity` (mm/s, > 0 advances the electrode and closes the gap). Outputs:
`measured_voltage` (noisy, V), `mean_voltage` (noise-free V(g)), `gap` (um), `velocity_actual`
(mm/s), `removal` (workpiece surface advance, mm), `short` (1 while the gap is shorted).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


INPUTS = ("velocity",)
# the inputs it has no fallback for: a loop must drive them (runtime.simulate.build checks)
REQUIRED_INPUTS = INPUTS
OUTPUTS = ("measured_voltage", "mean_voltage", "gap", "velocity_actual", "removal", "short")
# every signal's unit, for plot axes ("-": a 0/1 flag)
UNITS = {"velocity": "mm/s", "measured_voltage": "V", "mean_voltage": "V", "gap": "um",
         "velocity_actual": "mm/s", "removal": "mm", "short": "-"}


@dataclass
class EdmSinkParams:
    R: float = 12.4               # ohm (thesis)
    Kf: float = 7.0               # N/A (thesis)
    Kb: float = 8.0               # V/(m/s) (thesis)
    supply: float = 48.0          # V (thesis)
    mass: float = 0.15            # kg, assumption
    damping: float = 5.0          # N s/m, assumption
    Kv: float = 400.0             # V/(m/s), inner velocity loop, assumption
    g_short: float = 0.005        # mm, assumption
    g_open: float = 0.100         # mm, assumption
    V_open: float = 100.0         # V (thesis)
    V_burn: float = 40.0          # V (thesis)
    V_best: float = 50.0          # V (thesis: normal mean gap voltage)
    erosion_rate: float = 0.2 / 60.0   # mm/s, C (thesis: overall feed about 0.2 mm/min)
    erosion_stop: float = 30.0    # V, k = C / erosion_stop, assumption
    mains: float = 5.0            # V at 50 Hz, assumption
    harmonic: float = 2.0         # V at 100 Hz, assumption
    spark_noise: float = 8.0      # V std per sample, assumption
    gap0: float = 0.080           # mm, initial gap, assumption
    substeps: int = 10            # mechanical sub-steps per sample


def gap_voltage(params: EdmSinkParams, gap: np.ndarray) -> np.ndarray:
    """Mean gap voltage V(g) (V) for gap g (mm)."""
    x = np.clip((gap - params.g_short) / (params.g_open - params.g_short), 0.0, 1.0)
    sparking = params.V_burn + (params.V_open - params.V_burn) * x ** 2
    return np.where(gap <= params.g_short, 0.0, sparking)


def erosion_speed(params: EdmSinkParams, voltage: np.ndarray) -> np.ndarray:
    """dWSH/dt = max(0, C - k |V - V_best|), mm/s."""
    k = params.erosion_rate / params.erosion_stop
    return np.maximum(0.0, params.erosion_rate - k * np.abs(voltage - params.V_best))


def initial_state(params: EdmSinkParams, batch: int, rng: np.random.Generator | None = None
                  ) -> dict[str, np.ndarray]:
    rng = rng or np.random.default_rng(0)
    zeros = np.zeros(batch)
    return {"z": zeros.copy(), "v": zeros.copy(), "surface": zeros + params.gap0,
            "phase50": rng.uniform(0, 2 * np.pi, batch),
            "phase100": rng.uniform(0, 2 * np.pi, batch)}


def step(params: EdmSinkParams, state: dict[str, np.ndarray], inputs: dict[str, np.ndarray],
         t: float, dt: float, rng: np.random.Generator | None = None
         ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    command = np.nan_to_num(np.asarray(inputs["velocity"], float), nan=0.0) * 1e-3   # m/s
    z, v, surface = state["z"], state["v"], state["surface"]      # mm, m/s, mm
    h = dt / params.substeps
    for _ in range(params.substeps):   # sub-steps in time, each vectorised over the batch
        u = np.clip(params.Kv * (command - v), -params.supply, params.supply)
        current = (u - params.Kb * v) / params.R
        v = v + h * (params.Kf * current - params.damping * v) / params.mass
        z = z + h * v * 1e3
        surface = surface + h * erosion_speed(params, gap_voltage(params, surface - z))
    gap = surface - z
    mean = gap_voltage(params, gap)
    t_end = t + dt
    noise = (params.mains * np.sin(2 * np.pi * 50 * t_end + state["phase50"])
             + params.harmonic * np.sin(2 * np.pi * 100 * t_end + state["phase100"]))
    if rng is not None and params.spark_noise > 0:
        noise = noise + params.spark_noise * rng.standard_normal(gap.shape)
    new_state = {**state, "z": z, "v": v, "surface": surface}
    return new_state, {"measured_voltage": mean + noise, "mean_voltage": mean, "gap": gap * 1e3,
                       "velocity_actual": v * 1e3, "removal": surface - params.gap0,
                       "short": (gap <= params.g_short).astype(float)}


@dataclass
class PIGapServo:
    """The thesis's crisp baseline: PI on the gap-voltage error with conditional integration.

    v_cmd = sat(Kp e + I), e = V - Vset; I integrates Ki e only while the output is not
    saturated or the error drives it back out of saturation (no wind-up during a short).
    Gains: the thesis's stable velocity cascade "P = 20, I = 10" (section 7.1), read as um/s
    per V and um/s per V s (our reading: the units are not printed).
    """
    Kp: float = 0.020             # mm/s per V
    Ki: float = 0.010             # mm/s per V s
    Vset: float = 50.0
    vmax: float = 2.0             # mm/s, the fuzzy servo's limit too
    period: float = 1e-3
    input_name: str = "gap_voltage"
    output_name: str = "velocity"

    def __post_init__(self) -> None:
        self.input_names = [self.input_name]
        self.output_names = [self.output_name]
        self.integral = np.zeros(1)

    def reset(self, batch: int) -> None:
        self.integral = np.zeros(batch)

    def initial_outputs(self) -> dict[str, float]:
        return {self.output_name: 0.0}

    def error(self, signals: dict[str, np.ndarray]) -> np.ndarray:
        return np.nan_to_num(np.asarray(signals[self.input_name], float) - self.Vset)

    def step(self, signals: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        e = self.error(signals)
        raw = self.Kp * e + self.integral
        saturated = np.abs(raw) >= self.vmax
        unwinding = np.sign(e) != np.sign(raw)
        self.integral = np.where(~saturated | unwinding,
                                 self.integral + self.Ki * e * self.period, self.integral)
        return {self.output_name: np.clip(self.Kp * e + self.integral, -self.vmax, self.vmax)}


# --- the same plant on sets (fuzzyc verify --prove) -------------------------------------------
SET_VARIABLE = ("gap0",)     # params that may be a set (an affine form) in set_initial_state


def set_initial_state(params: EdmSinkParams, gap0, noise) -> dict:
    """The state on affine forms: gap (mm, the form of gap0), coil velocity v (m/s), and the
    unknown phases of the mains and harmonic pick-up as (cos, sin) pairs, each a symbol in
    [-1, 1] for the whole run (the square holds the circle)."""
    state = {"gap": gap0, "v": 0.0}
    for name in ("cos50", "sin50", "cos100", "sin100"):
        state[name] = noise.widen(0.0, 1.0)
    return state


def set_step(params: EdmSinkParams, state: dict, inputs: dict, t: float, dt: float,
             noise) -> tuple[dict, dict]:
    """`step` on affine forms (fuzzyc.verifier.reach.affine), for every run of the plant from
    the states and inputs in the sets.

    - The actuator is linear in (v, command) but for the 48 V clip of the coil voltage, which
      goes through Affine.clip; the gap is tracked directly (surface - z) so its feedback keeps
      its correlation with v.
    - Erosion only widens the gap: over one sample the surface advances by some amount in
      [0, C dt] (erosion_speed is in [0, C]), a new symbol per sample.
    - V(g) is nondecreasing in g (0 up to the short, then the quadratic ignition law): its
      interval extension is its values at the ends.
    - Noise: the mains and harmonic terms are A sin(w t + phase) = A (sin(w t) cos(phase) +
      cos(w t) sin(phase)), linear in the state's phase symbols, so the filters see them as
      the sinusoids they are; the spark noise is Gaussian and unbounded, so the set covers it
      only up to `noise.sigmas` standard deviations, a new symbol per sample (an assumption
      the proof states; 0 leaves it out).
    Outputs: mean_voltage, measured_voltage, gap (um), velocity_actual (mm/s), short.
    """
    command = inputs["velocity"] * 1e-3
    gap, v = state["gap"], state["v"]
    h = dt / params.substeps
    for _ in range(params.substeps):
        u = _clip_form(params.Kv * (command - v), params.supply)
        current = (u - v * params.Kb) * (1.0 / params.R)
        v = v + (current * params.Kf - v * params.damping) * (h / params.mass)
        gap = gap - v * (h * 1e3)
    erosion = 0.5 * params.erosion_rate * dt
    gap = noise.widen(gap + erosion, erosion)
    mean = noise.monotone(gap, lambda g: gap_voltage(params, g))
    t_end = t + dt
    w50, w100 = 2 * np.pi * 50 * t_end, 2 * np.pi * 100 * t_end
    pickup = (state["cos50"] * (params.mains * np.sin(w50))
              + state["sin50"] * (params.mains * np.cos(w50))
              + state["cos100"] * (params.harmonic * np.sin(w100))
              + state["sin100"] * (params.harmonic * np.cos(w100)))
    measured = noise.widen(mean + pickup, params.spark_noise * noise.sigmas)
    short = noise.monotone(gap, lambda g: (g <= params.g_short).astype(float), increasing=False)
    return {**state, "gap": gap, "v": v}, {"measured_voltage": measured, "mean_voltage": mean,
                                  "gap": gap * 1e3, "velocity_actual": v * 1e3, "short": short}


def _clip_form(u, limit: float):
    return u.clip(-limit, limit) if hasattr(u, "clip") else float(np.clip(u, -limit, limit))
