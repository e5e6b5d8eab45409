"""Random numbers that belong to a loop, not to its place in the batch.

A plant draws its noise for the whole batch at once (`rng.standard_normal((3, n))`). With an
ordinary generator what loop i sees depends on how many loops run beside it, so a campaign
split into chunks (runtime.campaign) would not give the numbers of the same campaign run as one
batch, and a failing loop the verifier re-runs among its simplified variants would not see the
noise it failed with. `KeyedNoise` gives loop i its own counter-based stream, a function of
(seed, keys[i]) alone: the j-th number loop i draws is SplitMix64 of (its stream's start + j
steps), whatever batch it runs in. The plants draw through `standard_normal(size)` and
`uniform(low, high, size)` only, with the batch as the last axis of `size`.
"""
from __future__ import annotations

import numpy as np

_MASK = (1 << 64) - 1
_GAMMA = 0x9E3779B97F4A7C15     # SplitMix64's step (the golden ratio in 64 bits)


def _mix(x: np.ndarray) -> np.ndarray:
    """SplitMix64's output function on a uint64 array (in place; uint64 arithmetic wraps)."""
    x ^= x >> np.uint64(30)
    x *= np.uint64(0xBF58476D1CE4E5B9)
    x ^= x >> np.uint64(27)
    x *= np.uint64(0x94D049BB133111EB)
    x ^= x >> np.uint64(31)
    return x


class KeyedNoise:
    """keys: one non-negative integer per loop of the batch (its place in the campaign, or the
    drawn case a verifier variant comes from); seed: the campaign's seed (None: fresh entropy);
    stream: separates independent uses under one seed (plant noise, randomized params)."""

    def __init__(self, seed: int | None, keys, stream: int = 0) -> None:
        self.keys = np.asarray(keys, dtype=np.int64)
        if self.keys.size and self.keys.min() < 0:
            raise ValueError("noise keys must be non-negative")
        if seed is None:
            seed = int(np.random.SeedSequence().entropy) & _MASK
        start = np.array([(int(seed) * _GAMMA + (stream + 1) * 0xD1B54A32D192ED03) & _MASK],
                         dtype=np.uint64)
        self._start = _mix(_mix(start) + self.keys.astype(np.uint64) * np.uint64(_GAMMA))
        self._drawn = 0          # numbers each loop has drawn so far

    def _uniform(self, size) -> np.ndarray:
        """(..., n) uniforms in (0, 1], the next ones of each loop's stream."""
        shape = (size,) if np.isscalar(size) else tuple(size)
        if not shape or shape[-1] != len(self.keys):
            raise ValueError(f"a plant draws noise with the batch ({len(self.keys)}) as the "
                             f"last axis, not {shape}")
        rows = int(np.prod(shape[:-1], dtype=np.int64))
        steps = (np.arange(self._drawn + 1, self._drawn + rows + 1, dtype=np.uint64)
                 * np.uint64(_GAMMA))
        self._drawn += rows
        bits = _mix(self._start[None, :] + steps[:, None])
        uniform = ((bits >> np.uint64(11)) + np.uint64(1)) * (1.0 / 2 ** 53)
        return uniform.reshape(shape)

    def standard_normal(self, size) -> np.ndarray:
        """Box-Muller: each pair of uniforms gives two independent numbers (cosine, sine)."""
        shape = (size,) if np.isscalar(size) else tuple(size)
        rows = int(np.prod(shape[:-1], dtype=np.int64))
        pairs = (rows + 1) // 2
        u = self._uniform((2, pairs) + shape[-1:])
        radius, angle = np.sqrt(-2.0 * np.log(u[0])), 2.0 * np.pi * u[1]
        both = np.concatenate([radius * np.cos(angle), radius * np.sin(angle)])
        return both[:rows].reshape(shape)

    def uniform(self, low=0.0, high=1.0, size=None) -> np.ndarray:
        return low + (high - low) * self._uniform(size)
