"""Butterworth filters: magnitude response against the analytic formula, and the time domain."""
import numpy as np
import pytest

from fuzzyc.plants import filters

FS = 1000.0


def warp(f):
    return 2 * FS * np.tan(np.pi * f / FS)


@pytest.mark.parametrize("order", [1, 2, 4])
def test_lowpass_magnitude_is_butterworth(order):
    sos = filters.butter_lowpass_sos(order, 200.0, FS)
    f = np.linspace(1.0, 490.0, 200)
    expected = 1 / np.sqrt(1 + (warp(f) / warp(200.0)) ** (2 * order))
    np.testing.assert_allclose(abs(filters.sos_response(sos, f, FS)), expected, atol=1e-9)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_bandstop_magnitude_is_butterworth(order):
    sos = filters.butter_bandstop_sos(order, 40.0, 60.0, FS)
    f = np.linspace(1.0, 490.0, 300)
    w1, w2 = warp(40.0), warp(60.0)
    w = warp(f)
    expected = 1 / np.sqrt(1 + ((w2 - w1) * w / (w1 * w2 - w ** 2)) ** (2 * order))
    np.testing.assert_allclose(abs(filters.sos_response(sos, f, FS)), expected, atol=1e-9)


def test_cutoff_is_minus_3_db():
    # |H(fc)| = 1/sqrt(2) for every order: (Wc/Wc)^(2n) = 1
    sos = filters.butter_lowpass_sos(4, 200.0, FS)
    assert abs(filters.sos_response(sos, [200.0], FS)[0]) == pytest.approx(2 ** -0.5, abs=1e-12)


def test_block_attenuates_sine_as_predicted():
    """A 50 Hz and a 10 Hz tone through the band-stop block: 50 Hz gone, 10 Hz kept."""
    sos = filters.butter_bandstop_sos(2, 40.0, 60.0, FS)
    block = filters.SOSFilter(sos, "v", "vf")
    t = np.arange(4000) / FS
    freqs = np.array([50.0, 10.0])
    block.reset(2)
    out = np.array([block.step({"v": np.sin(2 * np.pi * freqs * ti)})["vf"] for ti in t])
    tail = out[2000:]
    amplitude = (tail.max(axis=0) - tail.min(axis=0)) / 2
    predicted = abs(filters.sos_response(sos, freqs, FS))
    np.testing.assert_allclose(amplitude, predicted, atol=2e-3)
    # the notch centre is sqrt(40*60) ~ 49 Hz (pre-warped), so 50 Hz is down by > 30 dB, not to 0
    assert amplitude[0] < 0.02 and amplitude[1] > 0.99


def test_block_starts_at_steady_state_and_holds_through_nan():
    block = filters.lowpass("v", "vf", 4, 200.0, FS)
    block.reset(3)
    x = np.array([50.0, -3.0, 0.0])
    for _ in range(5):
        np.testing.assert_allclose(block.step({"v": x})["vf"], x, atol=1e-9)
    held = block.step({"v": np.array([np.nan, -3.0, 0.0])})["vf"]
    np.testing.assert_allclose(held, x, atol=1e-9)


def test_before_its_first_finite_sample_a_loop_reads_nan_not_zero():
    # a sensor that fails from the start must not look like a 0-V short to the servo; the
    # first finite sample then starts that loop at its steady state (no ringing)
    block = filters.lowpass("v", "vf", 4, 200.0, FS)
    block.reset(2)
    first = block.step({"v": np.array([np.nan, 40.0])})["vf"]
    assert np.isnan(first[0]) and first[1] == pytest.approx(40.0)
    for _ in range(3):
        np.testing.assert_allclose(block.step({"v": np.array([45.0, 40.0])})["vf"],
                                   [45.0, 40.0], atol=1e-9)


def test_a_long_outage_reads_nan_and_restarts_at_steady_state():
    # 5 missing samples are bridged with the last output, the 6th reads NaN (a failed sensor
    # must not look like a frozen voltage); the next finite sample restarts that loop
    block = filters.lowpass("v", "vf", 4, 200.0, FS)
    block.reset(1)
    block.step({"v": np.array([50.0])})
    outputs = [block.step({"v": np.array([np.nan])})["vf"][0] for _ in range(6)]
    assert outputs[:5] == pytest.approx([50.0] * 5) and np.isnan(outputs[5])
    assert block.step({"v": np.array([30.0])})["vf"][0] == pytest.approx(30.0)


def test_bad_edges_are_rejected():
    with pytest.raises(ValueError):
        filters.butter_lowpass_sos(2, 600.0, FS)
    with pytest.raises(ValueError):
        filters.butter_bandstop_sos(2, 60.0, 40.0, FS)
