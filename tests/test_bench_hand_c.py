"""The hand-written WEDM C baselines of the benchmarks (benchmarks/hand_wedm_active_rules.c and its
q15 counterpart) compute the rule base the engine computes, so `make bench`'s ratios compare like
with like: float to float rounding, q15 within 2 LSB of the engine at the inputs the q15 code
sees (its inputs rounded down to 0..32767 over [-1, 1]).  Inputs in [-1, 1]: the hand versions
clamp there (the controller's chain does), the rule base alone does not (e1's P is tri(0, 1, 2))."""
from __future__ import annotations

import ctypes
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.language.parser import load

ROOT = pathlib.Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")


@pytest.fixture(scope="module")
def hand(tmp_path_factory):
    lib = tmp_path_factory.mktemp("hand") / "hand.so"
    subprocess.run(["gcc", "-std=c99", "-O2", "-shared", "-fPIC", "-o", str(lib),
                    str(BENCH / "hand_wedm_active_rules.c"),
                    str(BENCH / "hand_wedm_active_rules_q15.c")], check=True)
    return ctypes.CDLL(str(lib))


@pytest.fixture(scope="module")
def points():
    x = np.random.default_rng(3).uniform(-1, 1, (3000, 3))
    x[:5] = [[-1, -1, -1], [1, 1, 1], [0, 0, 0], [0.5, -0.5, 0.25], [1, -1, 0.5]]  # on breaks
    return x


def test_hand_float_is_the_engine_in_float(hand, points):
    rb = load(ROOT / "rulebases" / "wedm_three_region.fz").rulebase
    x32 = points.astype(np.float32)
    expected = evaluate(rb, x32.astype(float))
    got = np.empty_like(expected)
    y = (ctypes.c_float * 2)()
    for k, row in enumerate(x32):
        hand.hand_wedm_active_rules((ctypes.c_float * 3)(*row), y)
        got[k] = list(y)
    np.testing.assert_allclose(got, expected, atol=2e-6)


def test_hand_q15_is_the_engine_within_two_lsb(hand, points):
    rb = load(ROOT / "rulebases" / "wedm_three_region.fz").rulebase
    xq = np.floor((points + 1) * 32767 / 2).astype(np.int16)
    expected = evaluate(rb, xq.astype(float) * 2 / 32767 - 1)
    got = np.empty_like(expected)
    y = (ctypes.c_int16 * 2)()
    for k, row in enumerate(xq):
        hand.hand_wedm_active_rules_q15((ctypes.c_int16 * 3)(*(int(v) for v in row)), y)
        got[k] = [y[0] / 32767, y[1] / 32767]
    assert np.abs(got - expected).max() * 32767 <= 2.0
