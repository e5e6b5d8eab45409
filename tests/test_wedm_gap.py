"""The WEDM gap plant on its own: the physics relations and the papers' process facts."""
import numpy as np
import pytest

from fuzzyc.plants import wedm_gap as W

DT = 0.04


def hold(params, feed, t_off, seconds, height=None, rng=None):
    """Constant inputs for `seconds` over a batch (one loop per feed); the last outputs."""
    feed = np.asarray(feed, float)
    state = W.initial_state(params, feed.size)
    inputs = {"feed": feed, "t_off": np.full(feed.size, t_off)}
    if height is not None:
        inputs["height"] = np.full(feed.size, height)
    history = []
    for k in range(int(seconds / DT)):
        state, out = W.step(params, state, inputs, k * DT, DT, rng)
        history.append(out)
    return state, out, history


def test_discharge_energy_of_an_isosceles_pulse():
    # Liao & Yu eq. 1: V_D K t_on^2 (current up at K for t_on, down as fast: peak K t_on,
    # 2 t_on long) = 80 V * 380 A/us * (0.5 us)^2 = 80 * 190 A * 0.5e-6 s = 7.6 mJ
    assert W.discharge_energy(W.WedmGapParams(), 0.5) == pytest.approx(7.6e-3)


def test_liao_yu_eq16_and_the_efficiency_it_gives():
    # eq. 16 at T_on = 5, A_on = 2 (0.1 us): X1 = ln 5 / ln 9 = 0.73249, X2 = ln 2 / ln 5 =
    # 0.43068: 4.592 X1^2 + 2.016 X2^2 - 0.274 X1 X2 - 2.692 X1 - 1.28 X2 + 1.095
    # = 2.46381 + 0.37394 - 0.08644 - 1.97186 - 0.55128 + 1.095 = 1.32317 mm^2/min per kHz
    assert W.liao_yu_gamma(0.5, 0.2) == pytest.approx(1.3232, abs=1e-4)
    # the plant's efficiency is eq. 16 (x 380/450 for the slope) at a calibration ratio of
    # 0.47: 1.3232 x 0.8444 / 60e3 mm^2 x 0.29 mm x 10 J/mm^3 / (80 V x 380e6 A/s x
    # (0.25 x 0.53 + 0.04 x 0.235) 1e-12 s^2) = 5.400e-5 / 4.3138e-3 = 0.01252
    p = W.WedmGapParams()
    assert W.eq16_efficiency(p, 0.47) == pytest.approx(p.efficiency, rel=0.005)


def test_mean_gap_voltage_over_the_whole_cycle():
    # gap 10 um, no debris, t_off 10 us, t_on 0.5 us, 30 mm: t_d = 4 us, p_s = 1/(1+e^2.5)
    # = 0.075858, re-strike p_a = e^-5 = 0.006738; normal pulses (1-p_s)(1-p_a) = 0.917913,
    # abnormal r = 0.082087, half of them arcs. Cycle: 10 + 0.917913 x (4 + 2 x 0.5)
    # + 0.082087 x 2 x 0.2 = 14.62241 us. Volt-us: 110 x 0.917913 x 4 = 403.882 (waiting)
    # + 80 x (0.917913 x 1 + 0.041044 x 0.4) = 74.747 (discharging): 478.629 / 14.62241
    # = 32.733 V
    p = W.WedmGapParams()
    r = W.rates(p, 10.0, 0.0, 0.5, 10.0, 0.5, 30.0)
    assert r["voltage"] == pytest.approx(32.733, abs=1e-3)
    assert r["pulses"] == pytest.approx(1e6 / 14.62241, rel=1e-6)


def test_height_times_feed_is_gamma_times_spark_frequency():
    # Liao & Yu eq. 8 holds in the plant's steady state: H F / Fq is the same at every feed
    # of a fixed operating point up to the arc share (gamma depends on it, eq. 7).
    p = W.WedmGapParams(noise=0)
    _, out, _ = hold(p, [0.4, 0.5, 0.6], 32.0, 120)
    gamma = 30.0 * out["feed_actual"] / 60.0 / (out["spark_freq"] * 1000)
    assert gamma == pytest.approx(np.full(3, gamma[0]), rel=0.05)


def test_fig3_removal_rate_peaks_then_falls_with_feed():
    # Yan & Liao Fig. 3/4 conditions: t_on 0.5 us, t_off 11.2 us, 30 mm, 7 m/min, 600 gf,
    # 2 bar. Published: MRR peaks at an abnormal ratio of 54 % and falls beyond 1.2 mm/min.
    # These facts were used to choose the plant's constants (see its docstring).
    p = W.WedmGapParams(tension=600, noise=0)
    feeds = np.linspace(0.2, 2.0, 19)
    _, out, _ = hold(p, feeds, 11.2, 120)
    k = int(np.argmax(out["removal_rate"]))
    assert 0.9 <= feeds[k] <= 1.5
    assert 0.45 <= out["abnormal_ratio"][k] <= 0.75
    assert out["removal_rate"][-1] < 0.7 * out["removal_rate"][k]
    assert np.all(np.diff(out["abnormal_ratio"]) > 0)     # abnormal ratio rises with feed


def fig3_map(feeds):
    """The static map at Yan & Liao's Fig. 3/4 conditions (t_on 0.5 us, t_off 11.2 us, 30 mm,
    7 m/min, 600 gf, 2 bar), each feed held 120 s: the last outputs."""
    _, out, _ = hold(W.WedmGapParams(tension=600, noise=0), feeds, 11.2, 120)
    return out


@pytest.mark.xfail(strict=True, reason="finding: the map reaches 40 % at 0.90 mm/min and 23.3 "
                   "kHz. Removal per pulse is Liao & Yu's eq. 16 at a calibration ratio of 0.47; "
                   "at 0.40 (efficiency 0.0112) the point moves to 25.2 kHz, but test 2's loop "
                   "then drives the off-time to 45 us onto the short-circuit branch (mean gap "
                   "voltage 2.9 V, first window error 0.0296 against 0.03); docs/plants.md")
def test_fig3_spark_frequency_at_40_percent_is_yr1_less_three_std():
    # Yan & Liao took Yr1 = 30 kHz as the mean + 3 std of the spark frequency at the 40 %
    # operating point of this cut. The 40-ms count alone has std sqrt(m x 0.04 s)/0.04 s:
    # m + 3 sqrt(m / 0.04 s) = 30 kHz gives m = 27.5 kHz (std 0.83 kHz); process spread on
    # top only lowers the mean: 24 kHz for a 2 kHz std. So 24 <= mean at 40 % <= 27.5 kHz.
    feeds = np.linspace(0.2, 2.0, 91)
    out = fig3_map(feeds)
    below = out["abnormal_ratio"] < 0.7          # the branch before the cliff
    f40 = np.interp(0.40, out["abnormal_ratio"][below], out["spark_freq"][below])
    assert 24.0 <= f40 <= 27.5


def test_fig3_abnormal_ratio_is_54_percent_at_1_2_mm_min():
    # "it reaches the maximum value when the abnormal ratio is 54 %. Once the feedrate is
    # increased to more than 1.2 mm/min, the MRR starts to decrease": 54 % +- 5 % at 1.2.
    # The plant's arc sensitivity at 0.5 us (k_arc 0.5^n = 4.60: 10 x 0.5^1.12 in round 4,
    # 13 x 0.5^1.5 since round 5) was chosen from this fact (plant docstring), so this test
    # holds that choice; the map reads 0.540 here.
    out = fig3_map(np.array([1.2]))
    assert out["abnormal_ratio"][0] == pytest.approx(0.54, abs=0.05)


def test_spark_frequency_counts_every_pulse_shorts_included():
    # Yan & Liao's card counts N_t = N_n + N_a, N_a "composed of arc discharge and short
    # circuit", and the ratio is N_a / N_t: so the counted frequency is 1/T, all pulses.
    # Gap 0 um: p_s = 1 / (1 + exp((0 - 5) / 2)) = 0.9241; discharges are (1 - p_s) / T.
    p = W.WedmGapParams(noise=0)
    state = {**W.initial_state(p, 1), "gap": np.array([0.0]), "debris": np.array([0.0])}
    _, out = W.step(p, state, {"feed": np.array([0.5]), "t_off": np.array([10.0])}, 0.0, DT)
    p_s, _, _, cycle = W.pulse_statistics(p, 0.0, 0.0, 10.0, 0.5)
    assert p_s == pytest.approx(0.9241, abs=1e-4)
    assert out["spark_freq"][0] == pytest.approx(1e3 / cycle)        # kHz, cycle in us
    assert out["abnormal_ratio"][0] >= p_s


def test_a_short_off_time_restrikes_without_debris():
    # the re-strike term alone (debris 0, wide gap): p_a = exp(-t_off / 2 us);
    # 1.6 us (the machine's minimum, Table 1): exp(-0.8) = 0.4493; 20 us: exp(-10) = 4.5e-5
    p = W.WedmGapParams()
    _, p_a, _, _ = W.pulse_statistics(p, np.array([30.0, 30.0]), np.array([0.0, 0.0]),
                                      np.array([1.6, 20.0]), 0.5)
    assert p_a == pytest.approx([0.4493, 4.54e-5], rel=1e-3)


def test_ignition_delay_scales_with_the_wire_area_facing_the_work():
    # the statistical time lag of breakdown is 1 / (rate per unit area x area): t_d ~ 30 mm / H
    # at a given gap; at g_ref = 10 um: 4 us at 30 mm (td_ref), 8 us at 15 mm, 2.4 us at 50 mm
    p = W.WedmGapParams()
    _, _, t_d, _ = W.pulse_statistics(p, np.full(3, 10.0), np.zeros(3), np.full(3, 10.0), 0.5,
                                      np.array([30.0, 15.0, 50.0]))
    assert t_d == pytest.approx([4.0, 8.0, 2.4])


def test_a_height_step_down_lowers_the_count_at_once():
    # open loop, noise-free: feed 0.5 mm/min, t_off 8 us, 50 mm for 60 s, then 40 mm. The
    # first 40-ms count after the step falls 17 % (21.7 -> 18.0 kHz; the new steady state is
    # 15.9 kHz), because t_d grows by 50/40 at the same gap; without the area law it fell 1 %
    # (22.7 -> 22.5) and waited for the gap to open (~1 s time constant).
    p = W.WedmGapParams(noise=0)
    state = W.initial_state(p, 1)
    counts = []
    for k in range(int(61 / DT)):
        height = 50.0 if k * DT < 60 - DT / 2 else 40.0
        state, out = W.step(p, state, {"feed": np.array([0.5]), "t_off": np.array([8.0]),
                                       "height": np.array([height])}, k * DT, DT)
        counts.append(out["spark_freq"][0])
    before, after = counts[int(60 / DT) - 1], counts[int(60 / DT)]
    assert after / before == pytest.approx(0.83, abs=0.02)


def test_arcing_above_50_percent_breaks_the_wire_after_60_s():
    # feed 1.5 at t_off 11.2 holds the ratio above 50 %: the second mechanism fires once per
    # 60 s of it (the first ~10 s are the gap closing in)
    p = W.WedmGapParams(noise=0, q_rupture_per_speed=1e9)     # thermal mechanism off
    _, out, history = hold(p, [1.5], 11.2, 130)
    times = [k * DT for k, o in enumerate(history) if o["rupture"][0] > 0]
    assert len(times) == 2 and 60.0 <= times[0] <= 75.0
    assert times[1] - times[0] == pytest.approx(60.0, abs=DT)


def test_off_time_cut_makes_a_spark_surge_that_breaks_the_wire():
    # Yan & Liao's first mechanism, "often when the pulse on-time or off-time is changed":
    # steady at t_off 20 us, then cut to the machine's 1.6 us (the re-strike term's
    # plasma_time = 2 us was set against this test in round 4; since round 6 1.5 us breaks
    # too, 1 us does not). The discharge power per mm of wire (Fq E / H) passes the limit
    # (1.25 W/mm per m/min x 7 m/min = 8.75 W/mm) within the 50 ms - 2 s the paper reports
    # (here after 0.28 s).
    p = W.WedmGapParams(noise=0, arc_rupture_time=1e9)
    state = W.initial_state(p, 1)
    times = []
    for k in range(int(40 / DT)):
        t_off = 20.0 if k * DT < 30 else 1.6
        state, out = W.step(p, state, {"feed": np.array([0.8]), "t_off": np.array([t_off])},
                            k * DT, DT, None)
        if out["rupture"][0]:
            times.append(k * DT)
    assert times and 30.0 + 0.05 <= times[0] <= 30.0 + 2.0


def test_randomized_batch_params_broadcast():
    rng = np.random.default_rng(0)
    p = W.WedmGapParams()
    p.td_ref = 4.0 * (1 + 0.1 * rng.standard_normal(500))
    _, out, _ = hold(p, np.full(500, 0.5), 20.0, 2.0, rng=rng)
    assert out["spark_freq"].shape == (500,) and np.all(np.isfinite(out["spark_freq"]))
    assert np.std(out["spark_freq"]) > 0


def test_voltage_p_baseline_law():
    base = W.VoltageP(servo_voltage=40, gain=0.05)
    base.reset(3)
    out = base.step({"gap_voltage": np.array([30.0, 50.0, 200.0])})
    # 0.05 * (V - 40) clipped to [0, 3]: 0, 0.5, 3
    assert out["feed"] == pytest.approx([0.0, 0.5, 3.0])
    assert out["t_off"] == pytest.approx([32.0] * 3)


def test_outputs_stay_finite_for_any_command():
    # hypothesis drives feed and off-time with anything, NaN and infinities included
    from hypothesis import given, settings, strategies as st
    anything = st.floats(allow_nan=True, allow_infinity=True)

    @settings(max_examples=60, deadline=None)
    @given(st.lists(st.tuples(anything, anything), min_size=1, max_size=20))
    def check(commands):
        p = W.WedmGapParams()
        rng = np.random.default_rng(0)
        state = W.initial_state(p, 1)
        for k, (feed, t_off) in enumerate(commands):
            state, out = W.step(p, state, {"feed": np.array([feed]), "t_off": np.array([t_off])},
                                k * DT, DT, rng)
            assert all(np.all(np.isfinite(v)) for v in out.values())
            assert all(np.all(np.isfinite(v)) for v in state.values())
    check()
