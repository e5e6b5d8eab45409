"""WEDM corner plant: the paper's test path, Table 2, eq. 3, and the corner controller on it."""
import numpy as np
import pytest

from fuzzyc.plants import scenario, wedm_corner as wc
from fuzzyc.runtime.simulate import load_controller, simulate, summarize

ROUGH = [(50.0, 160.0), (43.0, 180.0), (30.0, 150.0), (21.0, 175.0)]   # top feed per thickness


def test_iso_program_path():
    moves = wc.parse_moves(wc.TEST_PROGRAM)
    np.testing.assert_allclose(moves.sum(axis=0), [-5.0, 0.0], atol=1e-9)   # back at the entry
    path = wc.test_path()
    # (-4.6189, 8) is a 120 deg heading: after +Y (90 deg) a 30 deg turn, a 150 deg corner, ...
    expected = [150, 120, 90, 60, 60, 30, 30, 30, 30, 60, 60, 90, 120, 150]
    np.testing.assert_allclose(path.corner_angle, expected, atol=1e-3)
    # 2*(4 + 9.2378*2 + 8*3 + 16 + 4.6189... ) -> sum of |moves| = 153.95 mm
    assert path.length == pytest.approx(np.hypot(moves[:, 0], moves[:, 1]).sum())
    assert path.length == pytest.approx(153.9499, abs=1e-3)


def test_fit_reproduces_table2():
    fit = wc.FIT
    model = wc.corner_error(fit, wc.TABLE2_CONDITIONS[:, 1:2], wc.TABLE2_CONDITIONS[:, 0:1],
                            wc.TABLE2_ANGLES)
    residual = model - wc.TABLE2_ERRORS
    assert np.sqrt(np.mean(residual ** 2)) < 3.5       # um, over 70 measurements
    assert np.abs(residual).max() < 12.0
    # the paper's observations: error grows with feed and thickness, falls with the angle
    assert np.all(fit.slope > 0) and np.all(np.diff(fit.slope) <= 0.002)
    e = wc.corner_error(fit, 160.0, 50.0, wc.TABLE2_ANGLES)
    assert np.all(np.diff(e) < 0)
    assert wc.corner_error(fit, 160.0, 50.0, 90.0) > wc.corner_error(fit, 160.0, 21.0, 90.0)
    assert wc.corner_error(fit, 100.0, 30.0, 180.0) == 0.0          # a straight line


def test_closed_form_path_hand_computed():
    params = wc.CornerParams(feed=160.0, thickness=50.0)
    v = 160.0 / 50.0 / 60.0                                  # mm/s
    n = len(params.path.corner_at)
    base = wc.evaluate_path(params, np.zeros((1, n)))
    assert base["time"][0] == pytest.approx(params.path.length / v)
    half = wc.evaluate_path(params, np.full((1, n), 50.0))
    # each zone (2 x 0.31 mm) and the catch-up (half the 50.3 um lag) are cut at half speed:
    # 0.62 + 0.025 mm extra per corner
    lag = wc.steady_lag(wc.FIT, 160.0, 50.0)
    assert lag == pytest.approx(0.0503, abs=1e-4)
    assert half["time"][0] == pytest.approx((params.path.length + n * (2 * wc.KERF + lag / 2))
                                            / v)
    # halving the force halves the force-driven part of the error and keeps the edge part (the
    # zones are ten relaxation lengths long: the lag has settled at half before the vertex)
    x = wc.lag_factor(160.0, 50.0, wc.FIT.guide_gap)
    e0 = np.interp(90.0, wc.FIT.angles, wc.FIT.edge)
    s = np.interp(90.0, wc.FIT.angles, wc.FIT.slope)
    assert half["errors"][0, 2] == pytest.approx(e0 + 0.5 * s * x, abs=1e-3)


def test_pursuit_of_a_lagging_wire_at_a_right_angle():
    # Turn 90 deg, lag 1: guides at (S, 0), wire at (S - cos psi, sin psi), tan(psi/2) = e^-S.
    # It crosses the bisector y = x where S = sin psi + cos psi; solve by bisection, then the
    # cut along the bisector is sqrt(2) * sin psi.
    lo, hi = 0.0, 3.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        psi = 2 * np.arctan(np.exp(-mid))
        lo, hi = (mid, hi) if mid < np.sin(psi) + np.cos(psi) else (lo, mid)
    psi = 2 * np.arctan(np.exp(-lo))
    assert wc.pursuit_tip(np.pi / 2, 1.0) == pytest.approx(np.sqrt(2) * np.sin(psi), rel=1e-4)
    assert np.sqrt(2) * np.sin(psi) == pytest.approx(0.682, abs=1e-3)
    # scale-free: twice the lag cuts twice as deep; a straight line is not cut at all
    assert wc.pursuit_tip(np.pi / 2, 2.0) == pytest.approx(2 * 0.682, abs=2e-3)
    tips = wc.pursuit_tip(np.radians(180.0 - wc.TABLE2_ANGLES), 1.0)
    np.testing.assert_allclose(tips, [1.863, 1.080, 0.682, 0.412, 0.196], atol=2e-3)


def test_table2_slopes_are_the_pursuit_plus_class_2_vibration():
    # The 150 deg column (class 1: wire lag only) sets the lag: s(150) x / 0.1958.
    fit = wc.FIT
    lag = wc.steady_lag(fit, 160.0, 50.0)
    x = wc.lag_factor(160.0, 50.0, fit.guide_gap)
    assert lag == pytest.approx(1e-3 * fit.slope[4] * x / 0.1958, rel=1e-3)
    assert 0.045 < lag < 0.055                              # mm: about 50 um in the roughest cut
    # pursuit alone, scaled from 150 deg, against the fitted slopes
    tips = wc.pursuit_tip(np.radians(180.0 - fit.angles), 1.0)
    predicted = fit.slope[4] * tips / tips[4]
    assert predicted[0] == pytest.approx(fit.slope[0], rel=0.07)   # 30 deg: the lag explains it
    # 60, 90, 120 deg (class 2, 30-135 deg): more than the lag, the vibration of section 2.2
    assert np.all(fit.slope[1:4] > 1.15 * predicted[1:4])


def test_lag_history_and_zones():
    # Force at a quarter in the zones. One kerf each side: the full gain, keep * s * x.
    angles = wc.TABLE2_ANGLES
    def lost(before, after):
        params = wc.CornerParams(zone_before=before, zone_after=after)
        controlled = wc.corner_errors(params, np.full((1, 5), 0.25), angles)[0]
        steady = wc.corner_error(wc.FIT, 160.0, 50.0, angles)
        ideal = wc.corner_error(wc.FIT, 40.0, 50.0, angles)
        return (controlled - ideal) / (steady - ideal)       # share of the gain lost
    np.testing.assert_allclose(lost(wc.KERF, wc.KERF), 0.0, atol=1e-4)   # e^-(0.31/0.03) left
    # slowing only at the vertex: the lag has had no travel to relax, half the gain is lost
    # (more at wide angles, where the cut is made further past the vertex)
    assert np.all((lost(0.0, wc.KERF) > 0.3) & (lost(0.0, wc.KERF) < 0.6))
    # three relaxation lengths before the vertex: e^-3 of the lag step remains, ~4 % lost
    assert np.all(lost(3 * wc.RELAX, wc.KERF) < 0.05)
    # speeding up at the vertex: the lag grows back while the wire still turns
    assert np.all(lost(wc.KERF, 0.0) > 0.3)
    # the turn is over within ~2 reduced lags (2 x 12.6 um): 50 um after the vertex suffice
    np.testing.assert_allclose(lost(wc.KERF, 0.05), 0.0, atol=1e-4)


def test_table2_itself_bounds_the_path_error_ratio():
    # Cutting every corner as the slowest normal cut of Table 2 (a quarter of the rough feed)
    # against the rough cut, path weights 4 x 30, 4 x 60, 2 x 90, 2 x 120, 2 x 150 deg.
    # 50 mm, 40 vs 160: (4*137.7 + 4*42.8 + 2*28.6 + 2*21.3 + 2*14.2)
    #                 / (4*218.2 + 4*97.4 + 2*75.3 + 2*39.8 + 2*22.0) = 850.2 / 1536.6 = 0.553
    weights = np.array([4, 4, 2, 2, 2])
    e = wc.TABLE2_ERRORS @ weights
    assert e[3] / e[0] == pytest.approx(850.2 / 1536.6, abs=1e-4)
    slow_over_rough = e[[3, 6, 9, 13]] / e[[0, 4, 7, 10]]      # 50, 43, 30, 21 mm
    np.testing.assert_allclose(slow_over_rough, [0.553, 0.600, 0.677, 0.616], atol=1e-3)
    # per corner, only the 90 deg (and at 50 / 21 mm the 60 deg) corners fall below half
    per_corner = wc.TABLE2_ERRORS[3] / wc.TABLE2_ERRORS[0]
    np.testing.assert_allclose(per_corner, [0.631, 0.439, 0.380, 0.535, 0.645], atol=1e-3)


def test_stepping_agrees_with_closed_form():
    params = wc.CornerParams(feed=np.array([160.0, 160.0]), thickness=np.array([50.0, 50.0]))
    reduction = np.array([0.0, 40.0])
    state = wc.initial_state(params, 2)
    dt, t, finish = 2.0, 0.0, np.full(2, np.nan)
    while np.isnan(finish).any():
        state, out = wc.step(params, state, {"reduction": reduction}, t, dt)
        t += dt
        finish = np.where(np.isnan(finish) & (out["done"] > 0), t, finish)
    exact = wc.evaluate_path(params, np.repeat(reduction[:, None], 14, axis=1))
    np.testing.assert_allclose(state["errors"], exact["errors"], rtol=1e-12)
    np.testing.assert_allclose(finish, exact["time"], atol=2 * dt)
    # per Table 2 angle, the mean of the path's corners at it: 30 deg is corners 5-8, 60 deg
    # corners 3, 4, 9, 10, 90 deg corners 2 and 11 (test_iso_program_path)
    e = exact["errors"]
    np.testing.assert_allclose(out["error_30"], e[:, 5:9].mean(axis=1), rtol=1e-12)
    np.testing.assert_allclose(out["error_60"], e[:, [3, 4, 9, 10]].mean(axis=1), rtol=1e-12)
    np.testing.assert_allclose(out["error_90"], e[:, [2, 11]].mean(axis=1), rtol=1e-12)
    # uncontrolled: Table 2's fitted row (to 1e-4: the ISO program's 4.6189 and 13.856 put
    # the corners within 1e-3 deg of 30, 60, 120 and 150 deg, not on them)
    np.testing.assert_allclose(
        [out[f"error_{int(a)}"][0] for a in wc.TABLE2_ANGLES],
        wc.corner_error(wc.FIT, 160.0, 50.0, wc.TABLE2_ANGLES), rtol=1e-4)
    np.testing.assert_allclose(out["error_sum"], exact["errors"].sum(axis=1), rtol=1e-12)


def corner_reductions(like=1.0):
    """The 27-rule controller's y for every (rough cut, corner): one batch of 4 x 14."""
    corner = scenario.load("corner_path")
    corner.data["controller"]["params"]["like"] = like
    path = wc.test_path()
    n = len(path.corner_angle)
    controller = load_controller(corner, batch=len(ROUGH) * n)
    inputs = {"feed": np.repeat([f for _, f in ROUGH], n),
              "thickness": np.repeat([h for h, _ in ROUGH], n),
              "angle": np.tile(path.corner_angle, len(ROUGH))}
    return controller.step(inputs)["reduction"].reshape(len(ROUGH), n)


def path_ratios(reduction):
    params = wc.CornerParams(feed=np.array([f for _, f in ROUGH]),
                             thickness=np.array([h for h, _ in ROUGH]))
    ctl = wc.evaluate_path(params, reduction)
    base = wc.evaluate_path(params, np.zeros_like(reduction))
    return ctl["errors"].sum(axis=1) / base["errors"].sum(axis=1), ctl["time"] / base["time"]


def test_corner_controller_on_rough_cuts_costs_under_10_percent_time():
    y = corner_reductions()
    assert np.all(y > 0) and np.all(y <= 90)
    # sharper corners get more reduction (rules: angle S -> bigger y than angle B)
    assert np.all(y[:, 5] >= y[:, 0])
    # 50 mm, 160 mm^2/min: 150 deg corners y = 30 %, 30 deg corners y = 60 % (rules 21, 25)
    assert y[0, 0] == pytest.approx(30.0, abs=0.1) and y[0, 5] == pytest.approx(60.0, abs=0.1)
    error_ratio, time_ratio = path_ratios(y)
    # measured (50, 43, 30, 21 mm): summed error 0.668 0.677 0.754 0.743 of normal machining,
    # time 1.070 1.062 1.048 1.051 (50 mm: 14 strips of 0.62 mm + (y/100) 50.3 um catch-up,
    # each costing strip (1/keep - 1): 10.7 mm more on a 153.95 mm path)
    np.testing.assert_allclose(error_ratio, [0.668, 0.677, 0.754, 0.743], atol=2e-3)
    np.testing.assert_allclose(time_ratio, [1.070, 1.062, 1.048, 1.051], atol=2e-3)
    strip = 2 * wc.KERF + y[0] / 100 * wc.steady_lag(wc.FIT, 160.0, 50.0)
    assert time_ratio[0] == pytest.approx(1 + np.sum(strip / (1 - y[0] / 100) - strip)
                                          / wc.test_path().length, rel=1e-9)


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="finding: with the 27 rules the path's summed corner error falls only "
                   "to 67-75 % of normal machining (time +5-7 %); the edge error of sharp "
                   "corners does not fall with the sparking force (iso-energy pulses: the "
                   "discharges per mm of path do not change with the off-time), and Table 2 "
                   "itself leaves 55-68 % even at a quarter of the rough feed; the best "
                   "strategy within +10 % time reaches 52-59 % (below half only for the thick cuts of an "
                   "idealised corner, see test_what_the_headline_would_take)")
def test_paper_headline_50_percent_error_at_10_percent_time():
    error_ratio, time_ratio = path_ratios(corner_reductions())
    assert np.all(error_ratio <= 0.5) and np.all(time_ratio <= 1.10)


def test_the_best_strategy_within_ten_percent_time_stays_above_half():
    """The limit, for the user: the least summed error any choice of per-corner reductions
    reaches within +10 % machining time, on the rough cuts of Table 2."""
    feed = np.array([f for _, f in ROUGH])
    thickness = np.array([h for h, _ in ROUGH])

    def best(zone, keep_min):
        params = wc.CornerParams(feed=feed, thickness=thickness, zone_before=zone,
                                 zone_after=zone)
        reduction = wc.best_reductions(params, 1.10, keep_min)
        ctl = wc.evaluate_path(params, reduction)
        base = wc.evaluate_path(params, np.zeros_like(reduction))
        return (ctl["errors"].sum(1) / base["errors"].sum(1), ctl["time"] / base["time"],
                ctl["errors"] / base["errors"])
    # the paper-like zones (one kerf each side), the feed cut to 10 % at most: 0.61-0.67
    error, time_, _ = best(wc.KERF, 0.1)
    assert np.all(time_ <= 1.10 + 1e-9)
    np.testing.assert_allclose(error, [0.618, 0.612, 0.667, 0.663], atol=3e-3)
    # the least zones the lag physics needs (3 relaxation lengths each side): 0.52-0.59
    error, time_, per_corner = best(3 * wc.RELAX, 0.1)
    assert np.all(time_ <= 1.10 + 1e-9)
    np.testing.assert_allclose(error, [0.528, 0.521, 0.588, 0.584], atol=3e-3)
    assert np.all(error > 0.5)
    # per corner the 90 and 60 deg corners do fall below half (0.31-0.34, 0.43-0.49), the
    # 30, 120 and 150 deg ones do not
    assert np.all(per_corner[:, [2, 11]] < 0.35) and np.all(per_corner[:, [3, 4, 9, 10]] < 0.5)
    assert np.all(per_corner[:, 5:9] > 0.55) and np.all(per_corner[:, [0, 1, 12, 13]] > 0.5)
    # within Table 2's measured range (feed >= a quarter of the rough one): 0.57-0.64
    error, _, _ = best(3 * wc.RELAX, 0.25)
    np.testing.assert_allclose(error, [0.580, 0.573, 0.636, 0.632], atol=3e-3)


def test_what_the_headline_would_take():
    """An idealised corner: the lag relaxes within 10 um (a third of our RELAX), zones of 3 of
    those before and 50 um after the vertex, the feed cut to 10 %, below Table 2's range. Then
    the thick rough cuts (50, 43 mm) just pass half; the thin ones (30, 21 mm), whose error is
    more edge than lag, stay at 0.56."""
    feed = np.array([f for _, f in ROUGH])
    thickness = np.array([h for h, _ in ROUGH])
    params = wc.CornerParams(feed=feed, thickness=thickness, zone_before=0.03, zone_after=0.05,
                             relax=0.01)
    reduction = wc.best_reductions(params, 1.10, 0.1)
    ctl = wc.evaluate_path(params, reduction)
    base = wc.evaluate_path(params, np.zeros_like(reduction))
    error = ctl["errors"].sum(1) / base["errors"].sum(1)
    assert np.all(ctl["time"] / base["time"] <= 1.10 + 1e-9)
    np.testing.assert_allclose(error, [0.494, 0.485, 0.562, 0.557], atol=3e-3)


def test_scenario_runs_in_the_runtime_and_matches_the_closed_form():
    corner = scenario.load("corner_path", {"period": "2.0"})     # exact stepping: coarse is fine
    fuzzy = simulate(corner)
    base = simulate(corner, baseline=True)
    t_fuzzy = summarize(corner, fuzzy)["machining time"]["mean"]
    t_base = summarize(corner, base)["machining time"]["mean"]
    y = corner_reductions()[0]
    exact = wc.evaluate_path(wc.CornerParams(), np.stack([np.zeros(14), y]))
    assert t_base == pytest.approx(exact["time"][0], abs=2 * corner.period)
    assert t_fuzzy == pytest.approx(exact["time"][1], abs=2 * corner.period)
    assert fuzzy["error_sum"][-1, 0] == pytest.approx(exact["errors"][1].sum(), rel=1e-9)
    assert base["error_sum"][-1, 0] == pytest.approx(exact["errors"][0].sum(), rel=1e-9)


def test_table2_is_fitted_better_with_a_floor_than_by_power_laws_through_zero():
    # The floor E0 is what keeps the path above half (README, "What is not done yet"). A power
    # law through zero in the same force variable, E = a (f (H/2 + h/8))^n per angle (fitted in
    # logs, H searched over the same guide gaps), leaves rms 4.50 um at best (H = 10.5 mm);
    # the linear model with a floor leaves 3.30 um.
    best = min(fit[0] for fit in _power_law_fits())
    assert best == pytest.approx(4.50, abs=0.01)
    assert wc.fit_table2().rms == pytest.approx(3.30, abs=0.01)


def test_the_headline_under_the_power_law_reading_of_table2():
    """The answer rests on the floor. Read Table 2 instead as power laws through zero (the
    worse fit above, rms 4.50 um), E = a(angle) x^n(angle), with x the force variable and the
    force at keep of normal in the zones (the lag relaxed, as in our zones), and ask the same
    question: the least summed path error within +10 % time, feed down to 10 % (extrapolated
    below Table 2's lowest feed). With kerf-wide zones: 0.65 of normal machining; with the
    least zones the lag needs (3 relaxation lengths each side): 0.48 -- under half. So whether
    the paper's headline is reachable depends on how the corner error behaves below 40
    mm^2/min, which Table 2 does not show; the held-out Table 4 would tell."""
    rms, gap, log_a, n = min(_power_law_fits(), key=lambda fit: fit[0])
    assert rms == pytest.approx(4.50, abs=0.01)
    # exponents per angle 30 ... 150 deg: the sharp and the wide corners flatten most
    np.testing.assert_allclose(n, [0.283, 0.502, 0.744, 0.433, 0.273], atol=2e-3)
    feed = np.array([f for _, f in ROUGH])
    thickness = np.array([h for h, _ in ROUGH])
    angle = wc.test_path().corner_angle
    x = wc.lag_factor(feed, thickness, gap)[:, None, None]                 # (N, 1, 1)
    normal = np.exp(np.interp(angle, wc.TABLE2_ANGLES, log_a)
                    + np.interp(angle, wc.TABLE2_ANGLES, n) * np.log(x))[:, 0]   # (N, C)

    def power_law(keep):                                                   # (G, N, C)
        return normal * keep ** np.interp(angle, wc.TABLE2_ANGLES, n)

    def best(zone):
        params = wc.CornerParams(feed=feed, thickness=thickness, zone_before=zone,
                                 zone_after=zone)
        reduction = wc.best_reductions(params, 1.10, 0.1, grid=901, error_model=power_law)
        keep = 1.0 - reduction / 100.0
        base = wc.machining_time(params, np.ones_like(keep))
        time_ratio = wc.machining_time(params, keep) / base
        assert np.all(time_ratio <= 1.10 + 1e-9)
        return power_law(keep[None])[0].sum(axis=1) / normal.sum(axis=1)
    np.testing.assert_allclose(best(wc.KERF), 0.651, atol=3e-3)
    np.testing.assert_allclose(best(3 * wc.RELAX), 0.482, atol=4e-3)


def _power_law_fits():
    """(rms, H, log a per angle, n per angle) of E = a x^n fitted in logs, for each guide gap."""
    for gap in wc.GUIDE_GAPS:
        x = wc.lag_factor(wc.TABLE2_CONDITIONS[:, 1], wc.TABLE2_CONDITIONS[:, 0], gap)
        design = np.column_stack([np.ones_like(x), np.log(x)])
        coef, *_ = np.linalg.lstsq(design, np.log(wc.TABLE2_ERRORS), rcond=None)
        rms = np.sqrt(np.mean((np.exp(design @ coef) - wc.TABLE2_ERRORS) ** 2))
        yield rms, gap, coef[0], coef[1]
