"""Milling force plant (eqs. 6.1-6.12) against hand-computed forces and servo facts."""
import numpy as np
import pytest

from pathlib import Path

from fuzzyc.formats import load_any
from fuzzyc.learning import untrained_note
from fuzzyc.plants import milling, scenario
from fuzzyc.runtime.simulate import simulate, summarize

SQRT_1_KR2 = np.sqrt(1 + 0.6 ** 2)    # |F_t + F_r| per tooth = F_t * sqrt(1 + kr^2)


def params(radial_depth, runout=0.0, b=6.0):
    work = milling.Workpiece([100.0], [b], [radial_depth], start=-50.0)
    return milling.MillingParams(workpiece=work, runout=runout)


def test_half_immersion_peak_is_one_tooth_at_90_degrees():
    # ft = 0.05 mm, b = 6 mm: h = ft at theta = 90 deg, F_t = 1500*6*0.05 = 450 N,
    # resultant 450 * sqrt(1.36) = 524.79 N; the other teeth are out of the cut then
    force = milling.peak_force(params(6.0), np.array([0.0]), np.array([0.05]))
    assert force[0] == pytest.approx(450 * SQRT_1_KR2, rel=1e-9)


def test_slot_with_four_teeth_has_constant_resultant():
    # two engaged teeth at theta and theta+90: chips ft*sin, ft*cos along perpendicular
    # directions, so |F| = 450*sqrt(1.36)*sqrt(sin^2 + cos^2) = 524.79 N at every angle
    force = milling.peak_force(params(12.0), np.array([0.0]), np.array([0.05]))
    assert force[0] == pytest.approx(450 * SQRT_1_KR2, rel=1e-9)


def test_runout_thickens_the_longest_tooth_chip():
    # r = R + 0.005*cos(2 pi i/4): tooth 0 is 5 um longer than tooth 3 before it, so its chip
    # at 90 deg is ft + 0.005 = 0.025 mm: 1500*6*0.025*sqrt(1.36) = 262.39 N
    force = milling.peak_force(params(6.0, runout=0.005), np.array([0.0]), np.array([0.02]))
    assert force[0] == pytest.approx(1500 * 6 * 0.025 * SQRT_1_KR2, rel=1e-9)


def test_small_radial_depth_limits_the_engagement_angle():
    # a_r = 3 mm, R = 6: theta_exit = arccos(1 - 3/6) = 60 deg, the chip peaks at ft*sin 60
    force = milling.peak_force(params(3.0), np.array([0.0]), np.array([0.05]))
    assert force[0] == pytest.approx(450 * np.sin(np.pi / 3) * SQRT_1_KR2, rel=1e-9)


def test_params_per_loop_match_scalar_runs():
    # a batch with (N,) ks, kr, runout gives each loop the force of its own scalar run
    ks, kr, runout = np.array([1200.0, 1800.0]), np.array([0.5, 0.7]), np.array([0.0, 0.008])
    batch = milling.MillingParams(ks=ks, kr=kr, runout=runout)
    x, ft = np.array([10.0, 10.0]), np.array([0.03, 0.03])
    each = [milling.peak_force(milling.MillingParams(ks=ks[i], kr=kr[i], runout=runout[i]),
                               x[i:i + 1], ft[i:i + 1])[0] for i in range(2)]
    np.testing.assert_allclose(milling.peak_force(batch, x, ft), each, rtol=1e-12)


def test_no_force_in_air_and_depth_follows_the_tool_tip():
    p = milling.MillingParams(runout=0.0)          # step cut: air until 2 mm, b=6, then b=12
    x = np.array([-5.0, 10.0, 30.0, 60.0])         # tool centres
    f = milling.peak_force(p, x, np.full(4, 0.05))
    np.testing.assert_allclose(f, [0.0, 450 * SQRT_1_KR2, 900 * SQRT_1_KR2, 0.0], rtol=1e-9)


def test_servo_is_the_second_order_drive():
    # step response of Kn/((s/wn)^2 + 2 zeta s/wn + 1), sampled every revolution:
    # y(t) = 1 - exp(-zeta wn t) / sqrt(1 - zeta^2) * sin(wd t + arccos zeta),
    # wd = wn sqrt(1 - zeta^2)
    p = milling.MillingParams(workpiece=milling.Workpiece([1.0], [0.0], [0.0], start=1e6))
    state = milling.initial_state(p, 1)
    speeds = []
    for i in range(40):
        state, out = milling.step(p, state, {"feed": np.array([30.0])}, i * 0.15, 0.15)
        speeds.append(out["feed_actual"][0])
    t = 0.15 * np.arange(1, 41)
    wn, zeta = p.wn, p.zeta
    wd = wn * np.sqrt(1 - zeta ** 2)
    y = 1 - np.exp(-zeta * wn * t) / np.sqrt(1 - zeta ** 2) * np.sin(wd * t + np.arccos(zeta))
    np.testing.assert_allclose(speeds, 30.0 * y, atol=1e-9)


def test_max_constant_feed_inverts_the_linear_force_law():
    # slot, no run-out: F = ks*b*ft*sqrt(1+kr^2) with ft = U/(400*4), so the feed for 330 N is
    # 330 / (1500*6*1.16619) * 1600 = 50.31 mm/min
    feed = milling.max_constant_feed(params(12.0), 330.0)
    assert feed == pytest.approx(330 / (1500 * 6 * SQRT_1_KR2) * 1600, abs=0.02)


def test_workpiece_spec_is_checked():
    with pytest.raises(ValueError):
        milling.workpiece_from_spec({"pieces": [[10.0, 6.0]]})
    with pytest.raises(ValueError):
        milling.Workpiece([-1.0], [6.0], [6.0])


@pytest.mark.parametrize("name", ["milling_step", "milling_pocket"])
def test_scenario_baseline_is_the_largest_feed_within_330_N(name):
    sc = scenario.load(name)
    feed = milling.max_constant_feed(sc.plant_params(), 330.0)
    assert sc.baseline["params"]["feed"] == pytest.approx(feed, abs=0.1)


ROOT = Path(__file__).parents[1]


@pytest.mark.parametrize("name", ["milling_step", "milling_pocket"])
def test_learned_controller_against_constant_feed_as_the_scenario_note_says(name):
    """The scenario's note: the learned controller overshoots the 330 N limit on entry, then
    holds Fr closer than the constant feed and finishes sooner."""
    sc = scenario.load(name)
    assert sc.rulebase_ref().endswith("milling_neurofuzzy_learned.fz")
    fuzzy = summarize(sc, simulate(sc))
    base = summarize(sc, simulate(sc, baseline=True))
    peak, error, time = "peak force (limit 330)", "mean force error while cutting (Fr = 300)", \
        "machining time"
    assert base[peak]["mean"] <= 331.0 < fuzzy[peak]["mean"]
    assert fuzzy[error]["mean"] < 0.5 * base[error]["mean"]
    assert fuzzy[time]["mean"] < base[time]["mean"]


def test_untrained_rule_base_is_said_untrained():
    untrained = load_any(ROOT / "rulebases" / "milling_neurofuzzy.fz")
    learned = load_any(ROOT / "rulebases" / "milling_neurofuzzy_learned.fz")
    assert "UNTRAINED: the 49 learnable weights of `du` are all 0" in untrained_note(untrained)
    assert untrained_note(learned) is None
