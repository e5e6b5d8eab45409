"""Keyed plant noise: a loop's noise depends on its key, not on the loops beside it."""
import numpy as np
import pytest

from fuzzyc.runtime.noise import KeyedNoise


def test_a_loop_sees_the_noise_of_its_key_in_any_batch():
    # the original batch: 5 loops, keys 0..4; a later batch runs variants of loop 3 twice and
    # loop 1 once: each gets exactly the column its key had, draw after draw
    whole = KeyedNoise(7, np.arange(5))
    again = KeyedNoise(7, np.array([3, 3, 1]))
    for _ in range(3):
        a, b = whole.standard_normal((3, 5)), again.standard_normal((3, 3))
        np.testing.assert_array_equal(b, a[:, [3, 3, 1]])
        u, v = whole.uniform(0, 2, 5), again.uniform(0, 2, 3)
        np.testing.assert_array_equal(v, u[[3, 3, 1]])


def test_keys_and_shapes_are_checked():
    with pytest.raises(ValueError, match="noise keys must be non-negative"):
        KeyedNoise(0, np.array([-1]))
    with pytest.raises(ValueError, match="the batch \\(2\\) as the last axis"):
        KeyedNoise(0, np.array([0, 1])).standard_normal((2, 3))


def test_the_streams_are_standard_normal_and_uniform():
    # 200,000 draws: the sample mean of N(0, 1) has a standard deviation of 1/sqrt(2e5) =
    # 0.0022, so |mean| < 0.011 is 5 sigma; the sample std's is 1/sqrt(2 * 2e5) = 0.0016;
    # U(0, 2) has mean 1 and variance 4/12 = 1/3; neighbouring loops and successive draws of one
    # loop are uncorrelated (the correlation's standard deviation is 1/sqrt(1e5) = 0.0032)
    noise = KeyedNoise(11, np.arange(100_000))
    z = noise.standard_normal((2, 100_000))
    assert abs(z.mean()) < 0.011 and abs(z.std() - 1) < 0.008
    assert abs(np.corrcoef(z[0], z[1])[0, 1]) < 0.016
    assert abs(np.corrcoef(z[0, :-1], z[0, 1:])[0, 1]) < 0.016
    u = noise.uniform(0, 2, 100_000)
    assert 0 < u.min() and u.max() <= 2
    assert abs(u.mean() - 1) < 5 * np.sqrt(1 / 3 / 1e5) and abs(u.var() - 1 / 3) < 0.01
