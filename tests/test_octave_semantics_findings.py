"""What the differential fuzzer found of the Octave toolkit 0.4.6's evalfis that `--semantics
octave` did not reproduce (issue 28), each by hand, then against the live toolkit (skipped
without Octave).

- A hedge on a Mamdani consequent (`1, 1.2 (1) : 1`): eval_rules_mamdani.m raises the output
  term's membership to the power (evalmf_private.m: mu(u)^2 for `.2`) and applies the
  implication to the plain strength; fuzzyc's own reading (the Sugeno one, strength^(1/p))
  applied the hedge to the strength.
- An output no rule concludes (a FIS row's `0`, or a file converted from FLL): the toolkit
  defuzzifies its empty set as it is; fuzzyc's octave semantics crashed (an empty reduction).
- Vanishing activations: the toolkit skips a rule only where its strength is 0; fuzzyc's
  ACTIVATION_FLOOR (1e-12) made such a rule silent under --semantics octave too.
"""
from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.conformance import oracles
from fuzzyc.formats import load_any
from fuzzyc.formats.tool_semantics import Chain

FILES = Path(__file__).resolve().parent / "octave_findings"
X = [0.0, 4.0, 5.0, 10.0]

# mamdani_hedge.fis: x on [0, 10], lo = trimf [-10 0 10], hi = trimf [0 10 20]; y on [0, 10],
# a = trimf [-10 0 10] (1 - u/10); rules `lo -> a.2` (very), `hi -> a`.
#   x = 0: rule 1 at 1 concludes (1 - u/10)^2: centroid 10 * (1/12) / (1/3) = 2.5 (v = u/10:
#   int v (1 - v)^2 = 1/12, int (1 - v)^2 = 1/3); Octave's trapz on 101 samples 2.49963.
#   x = 10: rule 2 alone, 1 - u/10: 10/3 (3.333 sampled).  The strength reading gave 10/3 at
#   x = 0 too (sqrt(1) = 1, the set 1 - u/10).
MAMDANI_HEDGE = {0.0: 2.5, 10.0: 10 / 3}
# vanishing.fis: a = gaussmf [0.5 0] (sigma 0.5 at 0), b = trimf [5 10 15]; y: c1 = 3, c2 = 8.
#   x = 4: a = exp(-16 / 0.5) = 1.3e-14, b = 0: rule 1 alone fires: 3 (not the default 5).
#   x = 5: a = exp(-50) = 1.9e-22, b = 0: 3.  x = 0: a = 1: 3.  x = 10: b = 1, a = 1e-87: 8.
VANISHING = [3.0, 3.0, 3.0, 8.0]


def _y(name: str, semantics: str = "octave") -> list[float]:
    return Chain(load_any(FILES / name)).evaluate(np.array(X)[:, None], semantics)[:, 0].tolist()


def test_mamdani_consequent_hedge_by_hand():
    got = dict(zip(X, _y("mamdani_hedge.fis")))
    assert got[0.0] == pytest.approx(MAMDANI_HEDGE[0.0], abs=1e-3)
    assert got[10.0] == pytest.approx(MAMDANI_HEDGE[10.0], abs=1e-3)
    # the model's own (exact) reading stays the strength's: sqrt(1) = 1 at x = 0
    assert _y("mamdani_hedge.fis", "exact")[0] == pytest.approx(10 / 3, abs=1e-9)


def test_vanishing_activations_by_hand():
    assert _y("vanishing.fis") == pytest.approx(VANISHING, abs=1e-12)
    # the exact semantics keep the floor: nothing fires at 4 and 5, the default 5
    assert _y("vanishing.fis", "exact") == pytest.approx([3.0, 5.0, 5.0, 8.0], abs=1e-12)


def _octave(name: str) -> list[float]:
    script = (f"pkg load fuzzy-logic-toolkit; warning('off', 'all'); f = readfis('{name}');"
              f" printf('%.17g\\n', evalfis([{' '.join(map(str, X))}]', f));")
    done = subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval",
                           script], capture_output=True, text=True, timeout=120, cwd=FILES)
    return [float(v) for v in done.stdout.split()]


@pytest.mark.parametrize("name,tolerance", [("mamdani_hedge.fis", 1e-3 * 10),
                                            ("vanishing.fis", 1e-6 * 10)])
def test_octave_live(name, tolerance):
    if not oracles.have_octave():
        pytest.skip("no octave with the fuzzy-logic-toolkit")
    assert _y(name) == pytest.approx(_octave(name), abs=tolerance)


# unconcluded_output.fis: x on [0, 10]; y on [0, 10] and z on [-3, 1], each one term
# trimf [0 5 10]; one rule `1, 1 0 (1) : 1` concludes y only.  x = 4: a = 0.8, y's set is
# min(0.8, a(u)), its maximum 0.8 on [4, 6]: mean of maximum 5.  z's set is 0 everywhere:
# every sample is a maximum, their mean the range's middle (-3 + 1)/2 = -1; with centroid,
# 0/0 = NaN.  Both columns live: evalfis prints y then z.
def _both(defuzzify: str, tmp_path: Path) -> tuple[Path, np.ndarray]:
    path = tmp_path / "unconcluded_output.fis"
    path.write_text((FILES / "unconcluded_output.fis").read_text()
                    .replace("DefuzzMethod='mom'", f"DefuzzMethod='{defuzzify}'"))
    return path, Chain(load_any(path)).evaluate(np.array([[4.0], [6.0]]), "octave")


def test_an_output_no_rule_concludes_by_hand(tmp_path):
    _, got = _both("mom", tmp_path)
    assert got.ravel().tolist() == pytest.approx([5.0, -1.0, 5.0, -1.0], abs=1e-12)
    _, got = _both("centroid", tmp_path)
    assert got[:, 0] == pytest.approx([5.0, 5.0], abs=1e-3) and np.isnan(got[:, 1]).all()


@pytest.mark.parametrize("defuzzify", ["mom", "centroid"])
def test_an_output_no_rule_concludes_live(defuzzify, tmp_path):
    if not oracles.have_octave():
        pytest.skip("no octave with the fuzzy-logic-toolkit")
    path, got = _both(defuzzify, tmp_path)
    script = (f"pkg load fuzzy-logic-toolkit; warning('off', 'all'); f = readfis('{path.name}');"
              " printf('%.17g\\n', evalfis([4; 6], f));")
    done = subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval",
                           script], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    octave = np.array([float(v) for v in done.stdout.split()]).reshape(2, 2).T
    assert np.array_equal(np.isnan(octave), np.isnan(got))
    assert np.nan_to_num(got) == pytest.approx(np.nan_to_num(octave), abs=1e-3 * 10)
