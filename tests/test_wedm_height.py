"""The workpiece-height estimator (Liao & Yu): eq. 13, the correction factor, and the plant."""
import numpy as np
import pytest

from fuzzyc.plants import height_estimator as HE
from fuzzyc.plants.scenario import load
from fuzzyc.runtime.simulate import simulate


def test_correction_factor_reproduces_table_1():
    # Table 1: estimated 20.7 -> CF 0.965 (20/20.7 = 0.966); 55.3 -> 0.904; 10 -> 1.0
    # regression at 20.7: 3.84e-5*428.49 - 0.0047*20.7 + 1.04438 = 0.01645 - 0.09729 + 1.04438
    assert HE.correction_factor(20.7) == pytest.approx(0.96354, abs=1e-5)
    read = np.array([10.0, 20.7, 32.1, 44.1, 55.3])
    true = np.array([10.0, 20.0, 30.0, 40.0, 50.0])
    assert HE.correction_factor(read) * read == pytest.approx(true, abs=0.5)


def test_eq13_with_lambda_zero_jumps_to_the_sample_ratio():
    # lam = 0: beta = b + (dN + 0.4)/(1e-7 + dN^2) (dS - dN b); dN = 1000, dS = 0.02, b = 0:
    # 1000.4/1e6 * 0.02 = 2.0008e-5
    assert HE.beta_update(np.array([0.0]), np.array([1000.0]), np.array([0.02]),
                          np.array([0.0]))[0] == pytest.approx(2.0008e-5)


def test_forgetting_sees_the_sample_error_and_its_running_mean_in_noise_units():
    # first sample sets beta = dS/dN = 1e-5; the second reads 2.5 % more with 1000 counts:
    # err = 0.025, z = 0.025 sqrt(1000) = 0.7906, m = 0.1 z = 0.07906;
    # lam = 0.999 - 0.399 ((0.025/0.15)^2 + (0.07906/2)^2) = 0.999 - 0.399 x 0.029340 = 0.98729
    est = HE.HeightEstimator(gamma=1e-4, correct=False)
    est.reset(1)
    dt = 0.04
    for d_s in (0.01, 0.01025):                 # mm of travel per 1000 counts
        out = est.step({"spark_freq": np.array([1000 / dt / 1000.0]),
                        "feed_actual": np.array([d_s / dt * 60.0]), "dt": dt})
    assert out["forgetting"][0] == pytest.approx(0.98729, abs=1e-5)


def synthetic_cut(heights, gamma=1e-5, seconds=5.0, dt=0.04, feed=0.6, seed=1):
    """dN from H F = gamma Fq with 3 % counting noise; each height held `seconds`."""
    rng = np.random.default_rng(seed)
    est = HE.HeightEstimator(gamma=gamma, correct=False)
    est.reset(1)
    out = []
    for h in heights:
        for _ in range(int(seconds / dt)):
            fq = h * feed / 60.0 / gamma                          # discharges per second
            counted = fq * dt + np.sqrt(fq * dt) * rng.standard_normal()
            sig = {"spark_freq": np.array([counted / dt / 1000.0]),
                   "feed_actual": np.array([feed]), "dt": dt}
            out.append(est.step(sig)["height_raw"][0])
    return np.array(out)


def test_estimator_follows_height_steps_within_1_mm_in_1_s():
    # Liao & Yu: "error within 1 mm, response under 1 s" on a 10-50 mm stepped workpiece.
    # 125 samples per height; 1 s = 25 samples after each step.
    raw = synthetic_cut([10, 20, 30, 40, 50, 40, 30, 20, 10])
    heights = np.repeat([10, 20, 30, 40, 50, 40, 30, 20, 10], 125)
    for k in range(1, 9):
        after = slice(125 * k + 25, 125 * (k + 1))
        assert np.max(np.abs(raw[after] - heights[after])) < 1.0


def test_gamma_in_the_step_scenarios_is_a_10_mm_calibration():
    # the paper's procedure: cut a known 10 mm, invert eq. 14 over the steady part
    scenario = load("wedm_finish", {"plant.height": "10", "duration": "300"})
    trace = simulate(scenario)
    keep = trace.time > 240
    gamma, ratio_ref = HE.calibrate_gamma(trace["spark_freq"][keep, 0],
                                          trace["feed_actual"][keep, 0], 10,
                                          ratio=trace["abnormal_ratio"][keep, 0])
    for name in ("wedm_step_up", "wedm_step_down"):
        shipped = load(name).data["observers"][0]["params"]
        assert gamma == pytest.approx(shipped["gamma"], rel=0.03)
        assert ratio_ref == pytest.approx(shipped["ratio_ref"], abs=0.02)


@pytest.fixture(scope="module")
def step_down():
    return simulate(load("wedm_step_down"))


def test_step_down_no_wire_rupture_with_the_controller(step_down):
    assert step_down["ruptures"][-1, 0] == 0


def section_means(trace):
    """10-s means of the estimate before each next step (the 40-ms value is noisy)."""
    t = trace.time
    return np.array([np.mean(trace["height_est"][(t > t0) & (t <= t0 + 10), 0])
                     for t0 in (50, 110, 170, 230, 290)])


def test_step_down_estimate_within_2_mm_at_20_to_50_mm(step_down):
    means = section_means(step_down)
    assert means[:4] == pytest.approx([50, 40, 30, 20], abs=2.0)


@pytest.fixture(scope="module")
def step_up():
    return simulate(load("wedm_step_up"))


def test_step_down_estimate_within_1_mm_of_every_height(step_down):
    # with the eq. 3 pulse-mix weighting (ratio_ref in the scenario); the paper's fixed gamma
    # reads 51.2 / 41.5 / 30.5 / 19.9 / 8.7 mm here, because the loop moves the abnormal ratio
    # and with it gamma (eq. 7)
    assert section_means(step_down) == pytest.approx([50, 40, 30, 20, 10], abs=1.0)


def test_step_up_estimate_within_1_mm_of_every_height(step_up):
    # the same on the way up (fixed gamma: 7.2 / 19.7 / 31.4 / 41.9 / 51.8 mm)
    assert section_means(step_up) == pytest.approx([10, 20, 30, 40, 50], abs=1.0)


def one_second_errors(trace, steps):
    """Mean estimate over the 25 samples 1-2 s after each step, minus the new true height."""
    t = trace.time
    errors = []
    for t_step, h in steps:
        k = np.searchsorted(t, t_step + 1.0)
        errors.append(np.mean(trace["height_est"][k:k + 25, 0]) - h)
    return np.array(errors)


def test_step_down_estimate_within_1_mm_1_s_after_each_step(step_down):
    # Liao & Yu: "error within 1 mm, response under 1 s". Here +0.67 / -0.35 / -0.46 / -0.35
    # mm (20 noise seeds: all within 1 mm, worst 0.88). Two things make it (round 5): the
    # ignition delay scales with the wire area facing the work (t_d ~ 1/H, plant docstring), so
    # after a step down at constant feed the count falls at once instead of after the gap has
    # opened (round 4 read 43.5 / 31.0 / 20.3 / 9.9 here); and the estimator's forgetting sees a
    # persistent error in units of counting noise and weights with a filtered abnormal ratio.
    assert np.all(np.abs(one_second_errors(step_down, ((60, 40), (120, 30), (180, 20),
                                                       (240, 10)))) < 1.0)


def test_step_up_estimate_within_1_mm_1_s_after_each_step(step_up):
    # the same on the way up: +0.29 / -0.06 / -0.07 / -0.67 mm (19 of 20 noise seeds within
    # 1 mm; the worst, 1.11 mm, at the 40 -> 50 step)
    assert np.all(np.abs(one_second_errors(step_up, ((60, 20), (120, 30), (180, 40),
                                                     (240, 50)))) < 1.0)
