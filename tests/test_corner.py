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
    # each zone (2 x 0.31 mm) is cut at half speed: 0.62 mm extra per corner
    assert half["time"][0] == pytest.approx((params.path.length + n * 2 * wc.KERF) / v)
    # halving the feed halves the wire-lag part of the error and keeps the edge part
    x = wc.lag_factor(160.0, 50.0, wc.FIT.guide_gap)
    e0 = np.interp(90.0, wc.FIT.angles, wc.FIT.edge)
    s = np.interp(90.0, wc.FIT.angles, wc.FIT.slope)
    assert half["errors"][0, 2] == pytest.approx(e0 + 0.5 * s * x)


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
    error_ratio, time_ratio = path_ratios(y)
    assert np.all(time_ratio <= 1.10)
    assert np.all(error_ratio < 0.8)          # the errors fall by more than a fifth


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="physics + Table 2: the feed-independent edge error (about 110 um "
                   "at 30 deg even at 40 mm^2/min) keeps the path's corner error near 67-75 % of normal machining at <= 10 % more time "
                   "(see plants/wedm_corner.py)")
def test_paper_headline_50_percent_error_at_10_percent_time():
    error_ratio, time_ratio = path_ratios(corner_reductions())
    assert np.all(error_ratio <= 0.5) and np.all(time_ratio <= 1.10)


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
