"""Corner error and machining time of wire EDM along a test path (seeds/001, Table 2, eq. 3).

The corner controller lowers the feed by y % near each corner; this plant says what that does to
the corner error and to the machining time.

Corner error model, from the paper's physics and fitted to its Table 2 (SKD-11, 0.25 mm wire,
950 gf). The wire lags its guides by the static deflection of eq. 3,
    lag = D + d = q0 h H / (2F) + q0 h^2 / (8F) = Q (H/2 + h/8) / F,   Q = q0 h,
and the total pulling-back force Q is "roughly proportional to the energy invested in the
erosion", i.e. to the removal rate, i.e. to the feed f (mm^2/min). So lag ~ f (H/2 + h/8) / F.
At a corner of angle theta the lag cuts the corner short by g(theta) * lag, and the edge effects
of section 2 (enhanced sparking at a sharp edge, < 30 deg; vibration at 30-135 deg) add an error
E0(theta) that does not scale with the feed (Table 2 keeps ~110-140 um at 30 deg even at
40 mm^2/min). Hence, per angle column of Table 2, a straight line in x = f (H/2 + h/8):
    E(f, h, theta) = E0(theta) + s(theta) * f * (H/2 + h/8)
E0 and s are fitted per measured angle by least squares, H (guide-to-workpiece distance, not in
the paper) is fitted once over the whole table; between the measured angles both are
interpolated linearly, at 180 deg (no corner) both are 0, below 30 deg the 30 deg values hold.

Corner zone (assumption): the feed reduction acts while the wire is within one kerf width of the
corner vertex, before and after it (kerf = wire 0.25 mm + 2 x 0.03 mm spark gap): that is where
the asymmetric load of section 2.2 acts. The error of a corner is set by the feed at the vertex.
`step` moves the wire exactly (zone edges inside a period included), so a run of the loop and
`evaluate_path` (closed form over the whole path) agree to the period's time resolution.

What this model cannot give: the paper's headline (corner errors below 50 % of normal machining
at <= 10 % more time). The edge error E0 does not fall with the feed (Table 2 itself says so),
so slowing down only removes the lag part; with the 27-rule controller the path's summed error
falls to about 67-75 % for the rough cuts at 5-7 % more time.

Test path: the ISO program of section 3.2 (incremental G01 moves, F in mm/min), which cuts the
five angles 150, 120, 90, 60, 30 deg on each side of a symmetric part.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

# Table 2: corner error (um) in normal machining; rows (thickness mm, feed mm^2/min).
TABLE2_ANGLES = np.array([30.0, 60.0, 90.0, 120.0, 150.0])
TABLE2_CONDITIONS = np.array([
    [50, 160], [50, 120], [50, 80], [50, 40],
    [43, 180], [43, 120], [43, 60],
    [30, 150], [30, 100], [30, 50],
    [21, 175], [21, 125], [21, 75], [21, 40]], float)
TABLE2_ERRORS = np.array([
    [218.2, 97.4, 75.3, 39.8, 22.0], [183.0, 76.8, 60.5, 28.0, 16.1],
    [155.2, 58.9, 44.9, 24.2, 15.8], [137.7, 42.8, 28.6, 21.3, 14.2],
    [220.4, 100.2, 73.0, 39.6, 23.0], [180.0, 73.2, 58.4, 25.4, 16.0],
    [145.3, 55.4, 30.1, 20.3, 14.3],
    [173.0, 79.8, 61.3, 30.0, 16.2], [166.4, 63.4, 45.3, 22.2, 16.0],
    [130.9, 48.4, 23.5, 19.5, 13.5],
    [180.1, 82.8, 62.2, 30.8, 15.6], [164.2, 63.7, 50.8, 24.8, 15.5],
    [154.3, 54.5, 28.7, 19.9, 13.4], [130.0, 39.7, 22.7, 16.8, 12.0]])

# Section 3.2 test program (G92X0Y0 G94F3, then incremental G01 moves; the paper's
# `X-13.856.Y8.` has a stray dot, dropped here).
TEST_PROGRAM = """G01X-5. G01Y4. G01X-4.6189Y8. G01X-8. G01Y-8. G01X-13.856Y8. G01Y-8.
G01X-4.6189Y8. G01Y-24. G01X4.6189Y8. G01Y-8. G01X13.856Y8. G01Y-8. G01X8. G01X4.6189Y8.
G01Y4."""

KERF = 0.25 + 2 * 0.03   # mm, assumption: wire diameter plus two spark gaps

INPUTS = ("reduction",)
OUTPUTS = ("feed", "thickness", "angle", "in_corner", "feed_actual", "corner_error",
           "error_sum", "done")


def parse_moves(program: str) -> np.ndarray:
    """(M, 2) incremental moves of a G01-only ISO program (a missing axis moves 0)."""
    moves = []
    for block in re.findall(r"G01((?:[XY][-+]?[\d.]+)+)", program.replace(" ", "")):
        words = dict(re.findall(r"([XY])([-+]?[\d.]+)", block))
        moves.append([float(words.get(axis, "0").rstrip(".") or 0) for axis in "XY"])
    return np.array(moves)


@dataclass
class ToolPath:
    """A polyline cut at constant steady feed: segment lengths and the part's corners."""
    lengths: np.ndarray          # (M,) mm
    corner_at: np.ndarray        # (C,) path position of each corner vertex, mm
    corner_angle: np.ndarray     # (C,) included angle, degrees (180 = straight)

    @property
    def length(self) -> float:
        return float(self.lengths.sum())


def path_from_moves(moves: np.ndarray, lead_in: int = 1) -> ToolPath:
    """Corners between consecutive moves; the first `lead_in` moves reach the part, so the
    junction after them is the entry point, not a corner of the part."""
    lengths = np.hypot(moves[:, 0], moves[:, 1])
    heading = np.arctan2(moves[:, 1], moves[:, 0])
    turn = np.angle(np.exp(1j * (heading[1:] - heading[:-1])))      # wrapped to (-pi, pi]
    angle = 180.0 - np.degrees(np.abs(turn))
    at = np.cumsum(lengths)[:-1]
    return ToolPath(lengths, at[lead_in:], angle[lead_in:])


def test_path() -> ToolPath:
    return path_from_moves(parse_moves(TEST_PROGRAM))


@dataclass(frozen=True)
class CornerFit:
    """E(f, h, theta) = E0(theta) + s(theta) * f * (H/2 + h/8), fitted to Table 2."""
    angles: np.ndarray
    edge: np.ndarray       # E0 per angle, um
    slope: np.ndarray      # s per angle, um / (mm^2/min * mm)
    guide_gap: float       # H, mm
    rms: float             # residual over Table 2, um


def lag_factor(feed, thickness, guide_gap):
    """f * (H/2 + h/8): the wire lag of eq. 3 up to the constant of proportionality."""
    return np.asarray(feed, float) * (guide_gap / 2 + np.asarray(thickness, float) / 8)


GUIDE_GAPS = np.linspace(0.5, 60.0, 240)   # mm, the H values searched


def fit_table2(guide_gaps: np.ndarray = GUIDE_GAPS) -> CornerFit:
    """Least squares per angle column; H by a grid search over one shared value."""
    best = None
    for gap in guide_gaps:   # a 1-D search over the one nonlinear parameter
        x = lag_factor(TABLE2_CONDITIONS[:, 1], TABLE2_CONDITIONS[:, 0], gap)
        design = np.column_stack([np.ones_like(x), x])
        coef, residual, *_ = np.linalg.lstsq(design, TABLE2_ERRORS, rcond=None)
        sse = float(residual.sum())
        if best is None or sse < best[0]:
            best = (sse, gap, coef)
    sse, gap, coef = best
    rms = np.sqrt(sse / TABLE2_ERRORS.size)
    return CornerFit(TABLE2_ANGLES, coef[0], coef[1], float(gap), float(rms))


FIT = fit_table2()


@dataclass
class CornerParams:
    feed: float | np.ndarray = 160.0          # steady cutting feed, mm^2/min
    thickness: float | np.ndarray = 50.0      # mm
    path: ToolPath = field(default_factory=test_path)
    fit: CornerFit = FIT
    zone: float = KERF                        # reduction acts within this distance of a vertex


def corner_error(fit: CornerFit, feed, thickness, angle) -> np.ndarray:
    """Corner error (um) at feed f (mm^2/min), thickness h (mm), included angle (deg)."""
    angle = np.clip(np.asarray(angle, float), fit.angles[0], 180.0)
    knots = np.append(fit.angles, 180.0)
    edge = np.interp(angle, knots, np.append(fit.edge, 0.0))
    slope = np.interp(angle, knots, np.append(fit.slope, 0.0))
    return edge + slope * lag_factor(feed, thickness, fit.guide_gap)


def linear_speed(params: CornerParams) -> np.ndarray:
    """Wire speed along the path, mm/s, from the removal-rate feed f (mm^2/min) = v * h."""
    return np.asarray(params.feed, float) / np.asarray(params.thickness, float) / 60.0


def evaluate_path(params: CornerParams, reduction: np.ndarray) -> dict[str, np.ndarray]:
    """Closed form for a whole path: reduction (N, C) in % per corner (0 = no corner control).

    Returns the corner errors (N, C) in um and the machining time (N,) in s. Zones of
    neighbouring corners are taken as disjoint (true on the test path: >= 4 mm between corners).
    """
    path = params.path
    reduction = np.asarray(reduction, float)
    keep = 1.0 - np.clip(reduction, 0.0, 100.0) / 100.0
    feed = np.asarray(params.feed, float)[..., None]
    thickness = np.asarray(params.thickness, float)[..., None]
    errors = corner_error(params.fit, feed * keep, thickness, path.corner_angle)
    v = linear_speed(params)
    zone_length = 2 * params.zone
    slow = np.sum(zone_length / np.maximum(keep, 1e-9) - zone_length, axis=-1)
    return {"errors": errors, "time": (path.length + slow) / v}


def initial_state(params: CornerParams, batch: int, rng: np.random.Generator | None = None
                  ) -> dict[str, np.ndarray]:
    zeros = np.zeros(batch)
    return {"s": zeros, "errors": np.zeros((batch, len(params.path.corner_at)))}


def step(params: CornerParams, state: dict[str, np.ndarray], inputs: dict[str, np.ndarray],
         t: float, dt: float, rng: np.random.Generator | None = None
         ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Advance the wire by one period. Input `reduction` (%) acts only inside a corner zone.

    Outputs: `feed` (steady feed, what the controller's feed input sees), `thickness`,
    `angle` (of the nearest corner), `in_corner`, `feed_actual`, `corner_error` (um, the last
    corner passed; 0 before the first), `error_sum` (um, all corners passed), `done`.
    """
    path = params.path
    s = state["s"]
    reduction = np.nan_to_num(np.asarray(inputs["reduction"], float), nan=0.0)
    keep = np.broadcast_to(1.0 - np.clip(reduction, 0.0, 100.0) / 100.0, s.shape)
    s_new = _advance(params, s, keep, dt)
    # corners whose vertex was passed in this step get the error of the feed used there
    passed = (path.corner_at[None, :] > s[:, None]) & (path.corner_at[None, :] <= s_new[:, None])
    feed = np.broadcast_to(np.asarray(params.feed, float), s.shape)
    thickness = np.broadcast_to(np.asarray(params.thickness, float), s.shape)
    now = corner_error(params.fit, (feed * keep)[:, None], thickness[:, None], path.corner_angle)
    errors = np.where(passed, now, state["errors"])
    last = np.searchsorted(path.corner_at, s_new, side="right") - 1
    ahead = _nearest_corner(path, s_new)
    in_zone = np.abs(path.corner_at[ahead] - s_new) <= params.zone
    outputs = {"feed": feed.copy(), "thickness": thickness.copy(),
               "angle": path.corner_angle[ahead],
               "in_corner": in_zone.astype(float),
               "feed_actual": np.where(in_zone, feed * keep, feed),
               "corner_error": np.where(last >= 0, errors[np.arange(len(s)), last], 0.0),
               "error_sum": errors.sum(axis=1),
               "done": (s_new >= path.length).astype(float)}
    return {"s": s_new, "errors": errors}, outputs


def _advance(params: CornerParams, s: np.ndarray, keep: np.ndarray, dt: float) -> np.ndarray:
    """Path position after dt, exact: speed v*keep inside corner zones, v outside.

    The time to reach a position is piecewise linear in it, with knots at the zone edges;
    invert it per batch element at the start time + dt.
    """
    path = params.path
    knots = np.unique(np.clip(np.concatenate([[0.0, path.length], path.corner_at - params.zone,
                                              path.corner_at + params.zone]), 0.0, path.length))
    middle = 0.5 * (knots[1:] + knots[:-1])
    zone = np.abs(path.corner_at[_nearest_corner(path, middle)] - middle) <= params.zone
    v = np.broadcast_to(linear_speed(params), s.shape)[:, None]
    pace = np.where(zone[None, :], 1.0 / (v * np.maximum(keep, 1e-9)[:, None]), 1.0 / v)  # s/mm
    elapsed = np.concatenate([np.zeros((len(s), 1)), np.cumsum(np.diff(knots) * pace, axis=1)],
                             axis=1)
    rows = np.arange(len(s))
    here = np.clip(np.searchsorted(knots, s, side="right") - 1, 0, len(knots) - 2)
    target = elapsed[rows, here] + (s - knots[here]) * pace[rows, here] + dt
    there = np.clip(np.sum(elapsed <= target[:, None], axis=1) - 1, 0, len(knots) - 2)
    return np.minimum(knots[there] + (target - elapsed[rows, there]) / pace[rows, there],
                      path.length)


def _nearest_corner(path: ToolPath, s: np.ndarray) -> np.ndarray:
    right = np.clip(np.searchsorted(path.corner_at, s), 0, len(path.corner_at) - 1)
    left = np.clip(right - 1, 0, len(path.corner_at) - 1)
    closer_left = np.abs(path.corner_at[left] - s) < np.abs(path.corner_at[right] - s)
    return np.where(closer_left, left, right)


@dataclass
class NoCornerControl:
    """The baseline: normal machining, the feed is never reduced at corners."""

    def __post_init__(self) -> None:
        self.input_names: list[str] = []
        self.output_names = ["reduction"]
        self.batch = 1

    def reset(self, batch: int) -> None:
        self.batch = batch

    def initial_outputs(self) -> dict[str, float]:
        return {"reduction": 0.0}

    def step(self, signals: dict) -> dict[str, np.ndarray]:
        return {"reduction": np.zeros(self.batch)}
