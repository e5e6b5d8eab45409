"""Keyed plant noise: a loop's noise depends on its key, not on the loops beside it."""
import numpy as np
import pytest

from fuzzyc.runtime.noise import KeyedNoise


def test_a_loop_sees_the_noise_of_its_key_in_any_batch():
    # the original batch: 5 loops, keys 0..4; a later batch runs variants of loop 3 twice and
    # loop 1 once: each gets exactly the column its key had, draw after draw
    whole = KeyedNoise(7, np.arange(5), 5)
    again = KeyedNoise(7, np.array([3, 3, 1]), 5)
    for _ in range(3):
        a, b = whole.standard_normal((3, 5)), again.standard_normal((3, 3))
        np.testing.assert_array_equal(b, a[:, [3, 3, 1]])
        u, v = whole.uniform(0, 2, 5), again.uniform(0, 2, 3)
        np.testing.assert_array_equal(v, u[[3, 3, 1]])


def test_keys_and_shapes_are_checked():
    with pytest.raises(ValueError, match=r"noise keys must lie in \[0, 4\)"):
        KeyedNoise(0, np.array([4]), 4)
    with pytest.raises(ValueError, match="the batch \\(2\\) as the last axis"):
        KeyedNoise(0, np.array([0, 1]), 4).standard_normal((2, 3))
