"""Plant noise that belongs to a loop, not to its place in the batch.

A plant draws its noise for the whole batch at once (`rng.standard_normal((3, n))`), so what
loop i sees depends on how many loops run beside it. The verifier shrinks a failing loop by
re-running simpler variants of it in other batches; for the shrunk case to fail for the same
reason, each variant must see the noise its original loop saw. `KeyedNoise` draws every batch
as if it were the original one (`width` loops) and hands loop i the noise of loop `keys[i]`.
The plants draw through `standard_normal(size)` and `uniform(low, high, size)` only, with the
batch as the last axis of `size`.
"""
from __future__ import annotations

import numpy as np


class KeyedNoise:
    def __init__(self, seed: int | None, keys: np.ndarray, width: int) -> None:
        self.keys = np.asarray(keys, dtype=int)
        if self.keys.size and not (0 <= self.keys.min() and self.keys.max() < width):
            raise ValueError(f"noise keys must lie in [0, {width})")
        self.width = width
        self._generator = np.random.default_rng(seed)

    def _wide(self, size) -> tuple[int, ...]:
        shape = (size,) if np.isscalar(size) else tuple(size)
        if not shape or shape[-1] != len(self.keys):
            raise ValueError(f"a plant draws noise with the batch ({len(self.keys)}) as the "
                             f"last axis, not {shape}")
        return shape[:-1] + (self.width,)

    def standard_normal(self, size) -> np.ndarray:
        return self._generator.standard_normal(self._wide(size))[..., self.keys]

    def uniform(self, low=0.0, high=1.0, size=None) -> np.ndarray:
        return self._generator.uniform(low, high, self._wide(size))[..., self.keys]
