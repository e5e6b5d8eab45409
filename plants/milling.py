"""End-milling force process under a feed-rate command (Tarng, Hua, Huang, ch. 6; seeds/004).

One call of `step` is one spindle revolution (the controller's sample: the controlled value is
the peak resultant force in a revolution). Inputs: `feed` = command feed rate U_com (mm/min).
Outputs: `force` (N, peak resultant in the revolution), `feed_actual` V_f (mm/min), `position`
(tool-centre travel along the path, mm), `done` (1.0 once the tool has left the workpiece),
`cutting` (1.0 in a revolution where the tool takes a chip: force > 0).

Physics, by equation of the chapter:
  (6.1)  V_f/U_com = Kn / ((s/wn)^2 + 2 zeta (s/wn) + 1): solved exactly over the revolution
         for the command held by the controller (zero-order hold).
  (6.2)  f_t = V_f / (N m): feed per tooth from the mean V_f of the revolution.
  (6.3-4) chip thickness with run-out: tooth i at angle theta_i cuts the surface left by the
         last tooth that cut deeper; written closed-form as
         h_i = max(0, min_{k=1..m} (k f_t sin(theta_i) + r_i - r_{i-k})),
         which is the same recursion (the over-cut h_i accumulates k feeds per tooth).
         r_i = R + runout * cos(2 pi i / m - runout_phase).
  (6.5-6) F_t = ks b h, F_r = kr F_t.
  (6.7-10) F_X = sum delta(i) (F_t cos th + F_r sin th),
           F_Y = sum delta(i) (-F_t sin th + F_r cos th).
  (6.11) delta(i) = 1 when the tooth is in the material: theta in [0, pi] (front half, up-milling
         angle measured from the feed normal, h ~ sin theta) and -R cos(theta) <= -R + a_r, i.e.
         theta <= theta_exit = arccos(1 - a_r / R); and the tooth tip's position along the path,
         x_c + R sin(theta), lies in a piece of workpiece with axial depth b > 0.
  (6.12) F_c = sqrt(F_X^2 + F_Y^2); the output is its maximum over the revolution.

The workpiece is a list of pieces along the path, each with a length, an axial depth b and a
radial depth a_r (b = 0 is air). The step cut of Fig. 6.4: 2 mm of air, then b = 6 mm, then
b = 12 mm. The spiral-out pocket of Fig. 6.7 (figure lost) is the path unrolled: its pieces give
the radial depth at each position of the path.

Assumptions (not in the chapter):
- Kn = 1 (the drive follows the command in steady state), wn = 2 pi * 5 Hz, zeta = 0.7: a
  typical machining-centre feed drive; the chapter only says the drive is second order.
- run-out 5 um (a usual value for a collet-held end mill), phase 0.
- 72 angular samples per revolution (5 deg): the peak force changes < 1 % at finer grids.
- radial depth of the step cut 6 mm (half immersion, up-milling): the figure is lost.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


INPUTS = ("feed",)
# the inputs it has no fallback for: a loop must drive them (runtime.simulate.build checks)
REQUIRED_INPUTS = INPUTS
OUTPUTS = ("force", "feed_actual", "position", "done", "cutting")
# every signal's unit, for plot axes ("-": a 0/1 flag)
UNITS = {"feed": "mm/min", "force": "N", "feed_actual": "mm/min", "position": "mm", "done": "-",
         "cutting": "-"}


@dataclass
class Workpiece:
    """Pieces along the path: lengths (mm), axial depths b (mm), radial depths a_r (mm)."""
    lengths: np.ndarray
    axial_depth: np.ndarray
    radial_depth: np.ndarray
    start: float = 0.0          # path position of the first piece's start (tool-tip frame)

    def __post_init__(self) -> None:
        self.lengths = np.asarray(self.lengths, float)
        self.axial_depth = np.asarray(self.axial_depth, float)
        self.radial_depth = np.asarray(self.radial_depth, float)
        if not (self.lengths.shape == self.axial_depth.shape == self.radial_depth.shape):
            raise ValueError("workpiece pieces need as many axial and radial depths as lengths")
        depths = np.concatenate([self.axial_depth, self.radial_depth])
        if np.any(self.lengths <= 0) or np.any(depths < 0):
            raise ValueError("piece lengths must be > 0 and depths >= 0")
        self.edges = self.start + np.concatenate([[0.0], np.cumsum(self.lengths)])

    @property
    def end(self) -> float:
        return float(self.edges[-1])

    def at(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(b, a_r) at path positions x (any shape); zero outside the workpiece."""
        piece = np.searchsorted(self.edges, x, side="right") - 1
        inside = (piece >= 0) & (piece < len(self.lengths))
        piece = np.clip(piece, 0, len(self.lengths) - 1)
        return (np.where(inside, self.axial_depth[piece], 0.0),
                np.where(inside, self.radial_depth[piece], 0.0))


def step_cut(air: float = 2.0, first: float = 20.0, second: float = 20.0,
             radial_depth: float = 6.0) -> Workpiece:
    """Fig. 6.4: the tool edge starts `air` mm before the workpiece; b = 6 mm, then 12 mm."""
    return Workpiece(lengths=[first, second], axial_depth=[6.0, 12.0],
                     radial_depth=[radial_depth, radial_depth], start=air)


def workpiece_from_spec(spec: dict) -> Workpiece:
    """From a scenario's `workpiece: {start: mm, pieces: [[length, b, a_r], ...]}`."""
    if "pieces" not in spec:
        raise ValueError("workpiece needs `pieces: [[length, axial depth, radial depth], ...]`")
    pieces = np.asarray(spec["pieces"], float)
    if pieces.ndim != 2 or pieces.shape[1] != 3:
        raise ValueError("workpiece pieces must be [length, axial depth, radial depth] triples")
    return Workpiece(pieces[:, 0], pieces[:, 1], pieces[:, 2], start=float(spec.get("start", 0.0)))


@dataclass
class MillingParams:
    workpiece: Workpiece = field(default_factory=step_cut)
    diameter: float = 12.0          # mm, HSS end mill (chapter)
    teeth: int = 4                  # (chapter)
    spindle_rpm: float = 400.0      # (chapter)
    ks: float = 1500.0              # N/mm^2, 6061 aluminium (chapter)
    kr: float = 0.6                 # F_r / F_t (chapter)
    runout: float = 0.005           # mm, assumption (see module docstring)
    runout_phase: float = 0.0       # rad
    Kn: float = 1.0                 # assumption
    wn: float = 2 * np.pi * 5.0     # rad/s, assumption
    zeta: float = 0.7               # assumption
    angle_samples: int = 72
    force_noise: float = 0.0        # N, std of dynamometer noise (0: none)

    def __post_init__(self) -> None:
        if isinstance(self.workpiece, dict):   # from a scenario file
            self.workpiece = workpiece_from_spec(self.workpiece)
        elif not isinstance(self.workpiece, Workpiece):
            raise ValueError("workpiece must be a mapping {start: mm, pieces: [[length, axial "
                             f"depth, radial depth], ...]}}, got {type(self.workpiece).__name__}")

    @property
    def radius(self) -> float:
        return self.diameter / 2

    @property
    def revolution(self) -> float:
        """The controller's sample period, s."""
        return 60.0 / self.spindle_rpm


def initial_state(params: MillingParams, batch: int, rng: np.random.Generator | None = None
                  ) -> dict[str, np.ndarray]:
    """Tool centre one radius before the workpiece start (edge just touching x = 0), at rest."""
    zeros = np.zeros(batch)
    return {"x": zeros - params.radius, "v": zeros.copy(), "dv": zeros.copy()}


def peak_force(params: MillingParams, x_centre: np.ndarray, feed_per_tooth: np.ndarray
               ) -> np.ndarray:
    """Peak resultant force over one revolution (eqs. 6.3-6.12), batched over (N,).

    ks, kr, runout and runout_phase may be scalars or (N,) arrays (one per loop).
    """
    m, R = params.teeth, params.radius
    angles = 2 * np.pi * np.arange(params.angle_samples) / params.angle_samples
    tooth = np.arange(m)
    theta = np.mod(angles[:, None] + 2 * np.pi * tooth[None, :] / m, 2 * np.pi)   # (A, m)
    runout, phase = (np.atleast_1d(np.asarray(v, float))[:, None]
                     for v in (params.runout, params.runout_phase))
    radii = R + runout * np.cos(2 * np.pi * tooth / m - phase)                     # (N or 1, m)
    k = np.arange(1, m + 1)
    # r_i - r_{i-k} for every tooth i and look-back k: (N or 1, m, m)
    dr = radii[..., :, None] - radii[..., (tooth[:, None] - k[None, :]) % m]
    sin_t = np.sin(theta)
    ft = feed_per_tooth[:, None, None, None]
    h = np.maximum(0.0, np.min(k * ft * sin_t[None, :, :, None] + dr[:, None], axis=-1))
    tip_x = x_centre[:, None, None] + R * sin_t[None]                               # (N, A, m)
    b, a_r = params.workpiece.at(tip_x)
    cos_t = np.cos(theta)
    engaged = (theta <= np.pi)[None] & (cos_t[None] >= 1.0 - a_r / R) & (b > 0)
    ks, kr = (np.atleast_1d(np.asarray(v, float))[:, None, None] for v in (params.ks, params.kr))
    Ft = ks * b * h * engaged
    Fr = kr * Ft
    FX = np.sum(Ft * cos_t + Fr * sin_t, axis=-1)
    FY = np.sum(-Ft * sin_t + Fr * cos_t, axis=-1)
    return np.max(np.hypot(FX, FY), axis=-1)


def _expm(a: np.ndarray, terms: int = 18) -> np.ndarray:
    """Matrix exponential of (..., n, n) by scaling and squaring a Taylor series."""
    norm = np.max(np.abs(a).sum(axis=-1))
    squarings = max(0, int(np.ceil(np.log2(max(norm, 1e-300)))) + 1)
    scaled = a / 2.0 ** squarings
    result = term = np.broadcast_to(np.eye(a.shape[-1]), a.shape).copy()
    for k in range(1, terms):
        term = term @ scaled / k
        result = result + term
    for _ in range(squarings):
        result = result @ result
    return result


def _servo(params: MillingParams, v: np.ndarray, dv: np.ndarray, command: np.ndarray,
           dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eq. 6.1 over dt, exactly for a command held over the step (zero-order hold).

    Augmented state [v, dv/dt, U_com, integral of v]: its transition matrix exp(A dt) gives
    the new speed and the mean speed over the step (for the distance travelled). mm/min.
    """
    wn, zeta, kn = (np.broadcast_to(np.asarray(x, float), v.shape)
                    for x in (params.wn, params.zeta, params.Kn))
    a = np.zeros(v.shape + (4, 4))
    a[..., 0, 1] = 1.0
    a[..., 1, 0] = -wn ** 2
    a[..., 1, 1] = -2 * zeta * wn
    a[..., 1, 2] = wn ** 2 * kn
    a[..., 3, 0] = 1.0
    x = np.stack([v, dv, command, np.zeros_like(v)], axis=-1)[..., None]
    x = (_expm(a * dt) @ x)[..., 0]
    return x[..., 0], x[..., 1], x[..., 3] / dt


def step(params: MillingParams, state: dict[str, np.ndarray], inputs: dict[str, np.ndarray],
         t: float, dt: float, rng: np.random.Generator | None = None
         ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    command = np.nan_to_num(np.asarray(inputs["feed"], float), nan=0.0)
    v, dv, v_mean = _servo(params, state["v"], state["dv"], command, dt)
    travel = np.maximum(v_mean, 0.0) * dt / 60.0
    x_mid = state["x"] + travel / 2
    ft = np.maximum(v_mean, 0.0) / (params.spindle_rpm * params.teeth)
    force = peak_force(params, x_mid, ft)
    if params.force_noise > 0 and rng is not None:
        force = np.abs(force + params.force_noise * rng.standard_normal(force.shape))
    x = state["x"] + travel
    done = (x - params.radius >= params.workpiece.end).astype(float)
    return ({"x": x, "v": v, "dv": dv},
            {"force": force, "feed_actual": v, "position": x, "done": done,
             "cutting": (force > 0).astype(float)})


def run_constant_feed(params: MillingParams, feeds: np.ndarray, max_time: float
                      ) -> dict[str, np.ndarray]:
    """The baseline: each batch element cuts the whole workpiece at a constant command feed.

    Returns the peak force over the cut and the machining time (s, NaN if not finished).
    """
    feeds = np.asarray(feeds, float)
    state = initial_state(params, len(feeds))
    dt = params.revolution
    peak = np.zeros(len(feeds))
    finish = np.full(len(feeds), np.nan)
    for i in range(int(np.ceil(max_time / dt))):
        state, out = step(params, state, {"feed": feeds}, i * dt, dt)
        peak = np.maximum(peak, out["force"])
        finish = np.where(np.isnan(finish) & (out["done"] > 0), (i + 1) * dt, finish)
        if not np.isnan(finish).any():
            break
    return {"peak_force": peak, "time": finish}


@dataclass
class ConstantFeed:
    """The baseline controller: the constant feed a CAD/CAM program would run (mm/min)."""
    feed: float

    def __post_init__(self) -> None:
        self.input_names: list[str] = []
        self.output_names = ["feed"]
        self.batch = 1

    def reset(self, batch: int) -> None:
        self.batch = batch

    def initial_outputs(self) -> dict[str, float]:
        return {"feed": self.feed}

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        return {"feed": np.full(self.batch, self.feed)}


def max_constant_feed(params: MillingParams, force_limit: float, feed_range=(1.0, 75.0),
                      spacing: float = 0.1, tolerance: float = 0.01) -> float:
    """The largest constant feed (mm/min) whose peak force stays <= force_limit everywhere.

    The baseline a CAD/CAM programmer would pick given the force limit. At a constant feed the
    force at a tool position is the steady one, so the whole path is checked at once (tool
    centre every `spacing` mm) and the feed found by bracketing it (peak force rises with
    feed): the Illinois variant of regula falsi, a few evaluations as the force is nearly
    linear in the feed, and the returned feed always keeps the force within the limit.
    """
    x = np.arange(-params.radius, params.workpiece.end + params.radius, spacing)
    revs_per_min = params.spindle_rpm * params.teeth

    def worst(feed: float) -> float:
        return float(peak_force(params, x, np.full(x.shape, feed / revs_per_min)).max())

    lo, hi = feed_range
    f_lo, f_hi = worst(lo) - force_limit, worst(hi) - force_limit
    if f_lo > 0:
        raise ValueError(f"even {lo} mm/min exceeds the force limit {force_limit} N")
    if f_hi <= 0:
        return hi
    side = 0
    while hi - lo > tolerance:
        mid = float(np.clip(lo - f_lo * (hi - lo) / (f_hi - f_lo), lo + tolerance / 4,
                            hi - tolerance / 4))
        f_mid = worst(mid) - force_limit
        if f_mid <= 0:
            lo, f_lo = mid, f_mid
            f_hi = f_hi / 2 if side == -1 else f_hi     # Illinois: halve the stuck end
            side = -1
        else:
            hi, f_hi = mid, f_mid
            f_lo = f_lo / 2 if side == 1 else f_lo
            side = 1
    return lo


# --- the same plant on sets (fuzzyc verify --prove) -------------------------------------------
SET_VARIABLE = ("ks",)       # params that may be a set (an affine form) in set_initial_state


def set_initial_state(params: MillingParams, ks, noise) -> dict:
    """The state on affine forms: as initial_state, with the cutting coefficient ks (a form
    when it is varied) carried along for set_step."""
    return {"x": -params.radius, "v": 0.0, "dv": 0.0, "ks": ks}


def peak_force_box(params: MillingParams, x_lo: np.ndarray, x_hi: np.ndarray,
                   ft_lo: np.ndarray, ft_hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of peak_force / ks over tool centres in [x_lo, x_hi] and feeds per tooth in
    [ft_lo, ft_hi] (any equal shapes): the chip thickness is nondecreasing in the feed per
    tooth where a tooth cuts (sin theta >= 0 on [0, pi]); the depths are the least and largest
    of the pieces the tooth tip may be in; each force component is bounded term by term by the
    sign of its coefficient; the resultant by the distance from the origin to the box of its
    components and to its farthest corner; the peak by the largest of each."""
    m, R, shape = params.teeth, params.radius, np.shape(x_lo)
    angles = 2 * np.pi * np.arange(params.angle_samples) / params.angle_samples
    tooth = np.arange(m)
    theta = np.mod(angles[:, None] + 2 * np.pi * tooth[None, :] / m, 2 * np.pi)    # (A, m)
    radii = R + params.runout * np.cos(2 * np.pi * tooth / m - params.runout_phase)
    k = np.arange(1, m + 1)
    dr = radii[:, None] - radii[(tooth[:, None] - k[None, :]) % m]                  # (m, m)
    sin_t, cos_t = np.sin(theta), np.cos(theta)
    x_lo, x_hi, ft_lo, ft_hi = (np.reshape(v, (-1, 1, 1)) for v in (x_lo, x_hi, ft_lo, ft_hi))

    def chip(ft):
        return np.maximum(0.0, np.min(k * ft[..., None] * sin_t[..., None] + dr, axis=-1))

    b_lo, b_hi, a_lo, a_hi = _depth_range(params.workpiece, x_lo + R * sin_t, x_hi + R * sin_t)
    front = theta <= np.pi
    sure = front & (cos_t >= 1.0 - a_lo / R) & (b_lo > 0)
    maybe = front & (cos_t >= 1.0 - a_hi / R) & (b_hi > 0)
    ft_min = b_lo * chip(ft_lo) * sure                                               # (N, A, m)
    ft_max = b_hi * chip(ft_hi) * maybe

    def component(coef):
        low = np.sum(np.where(coef >= 0, coef * ft_min, coef * ft_max), axis=-1)
        high = np.sum(np.where(coef >= 0, coef * ft_max, coef * ft_min), axis=-1)
        return low, high

    fx, fy = component(cos_t + params.kr * sin_t), component(-sin_t + params.kr * cos_t)
    near = np.hypot(*(np.maximum(0.0, np.maximum(lo, -hi)) for lo, hi in (fx, fy)))
    far = np.hypot(*(np.maximum(np.abs(lo), np.abs(hi)) for lo, hi in (fx, fy)))
    return near.max(axis=-1).reshape(shape), far.max(axis=-1).reshape(shape)


def _depth_range(work: Workpiece, lo: np.ndarray, hi: np.ndarray):
    """(least b, largest b, least a_r, largest a_r) over the pieces path positions in
    [lo, hi] may fall in (0 outside the workpiece)."""
    b = np.concatenate([[0.0], work.axial_depth, [0.0]])
    a = np.concatenate([[0.0], work.radial_depth, [0.0]])
    first = np.searchsorted(work.edges, lo, side="right")[..., None]      # index into b
    last = np.searchsorted(work.edges, hi, side="right")[..., None]
    inside = (np.arange(len(b)) >= first) & (np.arange(len(b)) <= last)
    return (np.where(inside, b, np.inf).min(-1), np.where(inside, b, -np.inf).max(-1),
            np.where(inside, a, np.inf).min(-1), np.where(inside, a, -np.inf).max(-1))


def set_step(params: MillingParams, state: dict, inputs: dict, t: float, dt: float,
             noise) -> tuple[dict, dict]:
    """`step` on affine forms (fuzzyc.verifier.reach.affine), for every run of the plant from
    the states and inputs in the sets.

    - The feed drive (eq. 6.1) is linear: its transition matrix (the same `_expm`) maps the
      forms exactly; the travel goes through max(mean speed, 0) (monotone).
    - The force is ks times the peak force per unit ks, g(x, f_t): g as the secant slope in
      the feed per tooth plus a new symbol bounding the rest over the sub-intervals of f_t
      that Affine.apply takes (with the whole range of the tool centre) by peak_force_box; then times ks (the
      product of two forms).
    - Dynamometer noise: Gaussian, covered to `noise.sigmas` standard deviations only.
    """
    a = np.zeros((4, 4))
    a[0, 1], a[1, 0], a[1, 1] = 1.0, -params.wn ** 2, -2 * params.zeta * params.wn
    a[1, 2], a[3, 0] = params.wn ** 2 * params.Kn, 1.0
    phi = _expm(a * dt)
    v, dv, command = state["v"], state["dv"], inputs["feed"]
    new_v = v * phi[0, 0] + dv * phi[0, 1] + command * phi[0, 2]
    new_dv = v * phi[1, 0] + dv * phi[1, 1] + command * phi[1, 2]
    mean = noise.monotone((v * phi[3, 0] + dv * phi[3, 1] + command * phi[3, 2]) * (1 / dt),
                          lambda s: np.maximum(s, 0.0))
    x_mid = noise.form(state["x"] + mean * (dt / 120.0))
    ft = noise.form(mean * (1.0 / (params.spindle_rpm * params.teeth)))
    x_lo, x_hi = x_mid.bounds()

    def along(x, like):                    # the tool centre's range beside every f_t piece
        return np.broadcast_to(x.reshape(x.shape + (1,) * (like.ndim - 1)), like.shape)

    per_ks = ft.apply(lambda lo, hi: peak_force_box(params, along(x_lo, lo), along(x_hi, lo),
                                                    lo, hi))
    force = noise.widen(per_ks * state["ks"], params.force_noise * noise.sigmas)
    x = state["x"] + mean * (dt / 60.0)
    done = noise.monotone(x, lambda p: (p - params.radius >= params.workpiece.end).astype(float))
    cutting = noise.monotone(force, lambda f: (f > 0).astype(float))
    return ({**state, "x": x, "v": new_v, "dv": new_dv},
            {"force": force, "feed_actual": new_v, "position": x, "done": done,
             "cutting": cutting})
