"""Mean of maximum where a term has a vertical edge (found by tests/test_tiny_activations.py's
author): the engine stores the edge as two points a few ulps apart, and counted that pair as a
plateau, so one vertical-edged peak outweighed every other isolated peak (6 where 4 is right).
The C headers counted the peaks; now both do, and both give the hand-computed values."""
import numpy as np
import pytest

from fuzzyc.backends.c.load import CController
from fuzzyc.engine.inference import evaluate
from fuzzyc.language.parser import parse

SOURCE = """controller mom {
  input x in [0, 10]
  var y in [0, 10]
  terms x : lo = tri(0, 0, 10), hi = tri(0, 10, 10)
  terms y : a = tri(1, 2, 3), b = trap(6, 6, 6, 9)
  inference and = min, implication = min, aggregation = max, defuzzify = mean_of_maximum
  rule if x is lo then y is a
  rule if x is lo then y is b
}
"""

# x = 0: lo = 1, both rules fire at 1; the maxima are the peaks 2 (of a) and 6 (of b, its
#   vertical left edge): two isolated points, mean (2 + 6) / 2 = 4.
# x = 5: lo = 0.5; a clipped at 0.5 is flat on [1.5, 2.5] (length 1, middle 2); b clipped at
#   0.5 is flat from its edge 6 to 9 - 0.5 * 3 = 7.5 (length 1.5, middle 6.75); mean of the
#   plateaus weighted by length: (1 * 2 + 1.5 * 6.75) / 2.5 = 12.125 / 2.5 = 4.85.
# x = 2: lo = 0.8; a flat on [1.8, 2.2] (0.4, middle 2), b flat on [6, 9 - 2.4 = 6.6]
#   (0.6, middle 6.3): (0.4 * 2 + 0.6 * 6.3) / 1.0 = 4.58.
HAND = {0.0: 4.0, 5.0: 4.85, 2.0: 4.58}


def test_engine_counts_a_vertical_edge_as_one_point():
    model = parse(SOURCE, "mom.fz")
    x = np.array([[k] for k in HAND])
    np.testing.assert_allclose(evaluate(model.rulebase, x)[:, 0], list(HAND.values()),
                               rtol=0, atol=1e-9)


@pytest.mark.parametrize("numeric", ["double", "float"])
def test_c_header_agrees(numeric):
    model = parse(SOURCE, "mom.fz")
    x = np.array([[k] for k in HAND])
    got = CController(model, numeric=numeric).evaluate(x)[:, 0]
    np.testing.assert_allclose(got, list(HAND.values()), rtol=0,
                               atol=1e-9 if numeric == "double" else 1e-5)
