"""Centroid, bisector and mean of maximum of SUM-aggregated MIN-implied rules in C
(fuzzyc/backends/c/rule_items.py) against the numpy engine (fuzzyc/engine/defuzz.py).

Every rule is its own item: M(u) = sum_k min(level_k, mu_{t_k}(u)).  Hand-computed cases
where two rules conclude the same term at different levels, then the C against the engine
on 100,000 random inputs plus every edge for each method x (piecewise-linear, smooth terms) x
(float, double), on the sparse path (WEDM three-region: 2**3 candidate slots) and the dense
one (WEDM with NOT, hedges, OR, wildcards and weights: all 75 rules), and on a small rule
base of edge shapes (shoulders, a term past the range, a singleton, vertical edges), compiled
with the strict flags.  Tolerances as in test_c_area: double 1e-10 of the range, float 1e-5; the
float mean of maximum over smooth terms only to the engine's float-resolution maxima
(test_c_area.check_float_mean_of_maximum says why).
"""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.rule_items import fixed_points
from fuzzyc.backends.c.load import CController
from fuzzyc.engine.inference import evaluate
from fuzzyc.semantics.model import Aggregation, Defuzzifier, Implication
from fuzzyc.language.parser import parse

from test_c_area import check_against_engine, smooth_outputs
from test_c_backend import general_dense, inputs_for, variant
from test_c_chain import sanitized_error

SUM_MIN = dict(implication=Implication.MIN, aggregation=Aggregation.SUM)
METHODS = {"centroid": Defuzzifier.CENTROID, "bisector": Defuzzifier.BISECTOR,
           "mom": Defuzzifier.MEAN_OF_MAXIMUM}

THREE = """controller three {
  input x1 in [0, 1]
  input x2 in [0, 1]
  input x3 in [0, 1]
  terms x1 : hi = rshoulder(0, 1)
  terms x2 : hi = rshoulder(0, 1)
  terms x3 : hi = rshoulder(0, 1)
  var y in [0, 5]
  terms y : a = tri(0, 1, 3), b = tri(3, 4, 5)
  inference implication = min, aggregation = AGG, defuzzify = DEFUZZ
  rule if x1 is hi then y is a
  rule if x2 is hi then y is a
  rule if x3 is hi then y is b
  output u in [0, 5] = y
}
"""
# Each rule's level is its input (hi = rshoulder(0, 1) is mu = x): rules 1 and 2 conclude
# the same term a at levels x1 and x2.


def three(method: str, aggregation: str = "sum") -> str:
    return THREE.replace("DEFUZZ", method).replace("AGG", aggregation)


def run_both(text: str, x) -> np.ndarray:
    """The C in double and float and the engine on x agree; returns the double C's answer."""
    model = parse(text, "three.fz")
    got = {n: CController(model, numeric=n).evaluate(x) for n in ("double", "float")}
    np.testing.assert_allclose(got["float"], got["double"], atol=1e-5 * 5)   # 1e-5 of [0, 5]
    np.testing.assert_allclose(evaluate(model.rulebase, np.asarray(x, float)), got["double"],
                               atol=1e-12)
    return got["double"]


def test_hand_computed_centroid():
    # x = (0.5, 1, 0.5).  a = tri(0, 1, 3) at 1: the triangle, area 3 / 2 = 1.5, centroid
    # (0 + 1 + 3) / 3 = 4/3, moment 2.  a clipped at 0.5: rise [0, 0.5] (area 0.125, centre
    # 1/3), plateau [0.5, 2] (0.75, centre 1.25), fall [2, 3] (0.25, centre 7/3): area 1.125,
    # moment 1/24 + 15/16 + 7/12 = 75/48.  b = tri(3, 4, 5) clipped at 0.5: area 0.75,
    # centre 4, moment 3.  Sum: (2 + 75/48 + 3) / (1.5 + 1.125 + 0.75) = (105/16) / (27/8)
    # = 35/18 = 1.9444.  (max aggregation keeps only a at 1: (2 + 3) / 2.25 = 2.2222.)
    x = [[0.5, 1.0, 0.5]]
    np.testing.assert_allclose(run_both(three("centroid"), x), [[35 / 18]], atol=1e-12)
    np.testing.assert_allclose(run_both(three("centroid", "max"), x), [[5 / 2.25]], atol=1e-12)


def test_hand_computed_bisector():
    # x = (0.5, 1, 0.5): total area 3.375 (above), half 1.6875.  M = 2u on [0, 0.5] (area
    # 0.25), 0.5 + u on [0.5, 1] (0.625: 0.875 so far), 0.5 + (3 - u) / 2 on [1, 2] (1.5 down
    # to 1: area 1.25, past half).  In [1, 2], M(1 + t) = 1.5 - t / 2:
    # 1.5 t - t^2 / 4 = 1.6875 - 0.875 = 0.8125, t^2 - 6 t + 3.25 = 0, t = (6 - sqrt 23) / 2,
    # u = (8 - sqrt 23) / 2 = 1.6021.
    got = run_both(three("bisector"), [[0.5, 1.0, 0.5]])
    np.testing.assert_allclose(got, [[(8 - np.sqrt(23)) / 2]], atol=1e-12)


def test_hand_computed_mean_of_maximum():
    # x = (0.5, 0.5, 0.8): a twice at 0.5 sums to 1.0 where tri(0, 1, 3) >= 0.5, [0.5, 2],
    # above b's top 0.8: the middle 1.25.  (max aggregation: a's top 0.5 loses to b's plateau
    # [3.8, 4.2], middle 4; the sum of the levels per term, min(1.0, a), peaks at 1 only.)
    # x = (0.5, 1, 0.5): M = 0.5 + u on [0.5, 1] and falls after: one maximum 1.5 at u = 1.
    x = [[0.5, 0.5, 0.8], [0.5, 1.0, 0.5]]
    np.testing.assert_allclose(run_both(three("mean_of_maximum"), x), [[1.25], [1.0]],
                               atol=1e-12)
    np.testing.assert_allclose(run_both(three("mean_of_maximum", "max"), x[:1]), [[4.0]],
                               atol=1e-12)


@pytest.mark.parametrize("method", ["centroid", "bisector", "mean_of_maximum"])
def test_symmetric_gaussian_summed_on_the_grid(method):
    # a = b = gauss(2.5, 0.5) on [0, 5]: the grid (step 0.0025, 2.5 at index 1000) and every
    # item's clipped gaussian are symmetric about 2.5, so is their sum (levels 0.5, 1, 0.3):
    # centroid, bisector and mean of maximum are all 2.5.
    text = three(method).replace("a = tri(0, 1, 3), b = tri(3, 4, 5)",
                                 "a = gauss(2.5, 0.5), b = gauss(2.5, 0.5)")
    np.testing.assert_allclose(run_both(text, [[0.5, 1.0, 0.3]]), [[2.5]], atol=1e-12)


def test_vertical_edge_in_float_has_its_own_points():
    # b = trap(4, 4, 5, 5) jumps at 4 inside [0, 5]: the float polygon has the float just
    # below 4 and just above it, so the piece before 4 does not ramp up over the jump.
    text = three("bisector").replace("b = tri(3, 4, 5)", "b = trap(4, 4, 5, 5)")
    var = parse(text, "v.fz").rulebase.outputs[0]
    points = fixed_points(var, "float")
    below, above = np.nextafter(np.float32(4), np.float32(0)), np.nextafter(np.float32(4),
                                                                            np.float32(5))
    assert points.dtype == np.float32 and below in points and above in points
    # x = (0, 0, 1): only b, the rectangle [4, 5]: bisector 4.5 (mean of maximum 4.5 too).
    np.testing.assert_allclose(run_both(text, [[0.0, 0.0, 1.0]]), [[4.5]], atol=1e-12)


SHAPES = """controller shapes {
  input x1 in [0, 1]
  input x2 in [0, 1]
  terms x1 : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  terms x2 : lo = lshoulder(0, 0.6), mid = tri(0.2, 0.5, 0.8), hi = rshoulder(0.4, 1)
  var y in [0, 5]
  terms y : a = lshoulder(0.5, 2), b = trap(1, 2, 2, 6), c = singleton(3),
            d = rshoulder(4, 4.8), e = trap(3, 3, 4, 4)
  inference implication = min, aggregation = sum, defuzzify = DEFUZZ
  rule if x1 is lo and x2 is lo then y is a
  rule if x1 is lo and x2 is mid then y is b
  rule if x1 is lo and x2 is hi then y is c
  rule if x1 is hi and x2 is lo then y is b
  rule if x1 is hi and x2 is mid then y is d
  rule if x1 is hi and x2 is hi then y is e
  rule if x1 is hi then y is a
  output u in [0, 5] = y
}
"""
# A shoulder reaching to -inf, a term running past hi (b falls to 6), a singleton among
# trapezoids (no area: its rule adds nothing), vertical edges inside the range (e is the
# rectangle [3, 4]), and a rule with a wildcard (dense path), where a and b are each
# concluded by two rules.


@pytest.mark.parametrize("numeric", ["float", "double"])
@pytest.mark.parametrize("method", ["centroid", "bisector", "mean_of_maximum"])
def test_edge_shapes_match_engine(method, numeric):
    model = parse(SHAPES.replace("DEFUZZ", method), "shapes.fz")
    x = inputs_for(model.rulebase, n_random=20_000)
    check_against_engine(f"shapes_{method}", model, x, evaluate(model.rulebase, x), numeric,
                         ill_conditioned=False)


def wedm(method, smooth=False):
    model = variant("wedm_three_region", defuzzifier=method, **SUM_MIN)
    return smooth_outputs(model) if smooth else model


def dense(method, smooth=False):
    model = general_dense()
    for key, value in dict(defuzzifier=method, **SUM_MIN).items():
        setattr(model.rulebase.inference, key, value)
    return smooth_outputs(model) if smooth else model


def test_no_malloc_and_the_items_are_the_candidates():
    text = generate_header(dense(Defuzzifier.BISECTOR))
    assert "malloc" not in text and "float lv[75]" in text   # dense: every rule
    text = generate_header(wedm(Defuzzifier.BISECTOR))
    assert "malloc" not in text and "float lv[8]" in text    # sparse: 2**3 slots of depth 1


CASES = {f"{path}_{name}_{shape}": (builder, method, shape == "smooth")
         for path, builder in (("sparse", wedm), ("dense", dense))
         for name, method in METHODS.items() for shape in ("linear", "smooth")}
# Random inputs besides the edges.  assumption: fewer where the engine is slow, since it keeps
# every item: smooth terms form M as (N, 2001 grid points, K items), 33 s for 100,000 samples
# of the sparse path (K = 8); the dense path (K = 75) took 50-65 s for 100,000 samples over
# linear terms.  These counts keep each case to seconds and still move the outputs over their
# range (asserted below).
N_RANDOM = {("sparse", False): 100_000, ("dense", False): 20_000,
            ("sparse", True): 20_000, ("dense", True): 2_000}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    builder, method, smooth = CASES[request.param]
    model = builder(method, smooth)
    x = inputs_for(model.rulebase, n_random=N_RANDOM[request.param.split("_")[0], smooth])
    return request.param, model, x, evaluate(model.rulebase, x)


@pytest.mark.parametrize("numeric", ["float", "double"])
def test_matches_engine(case, numeric):
    name, model, x, expected = case
    check_against_engine(name, model, x, expected, numeric,
                         ill_conditioned=numeric == "float" and name.endswith("mom_smooth"))


@pytest.mark.parametrize("method", sorted(METHODS))
@pytest.mark.parametrize("builder, smooth", [(wedm, False), (dense, False), (wedm, True)],
                         ids=["sparse", "dense", "sparse_smooth"])
def test_under_sanitizers(tmp_path, builder, smooth, method):
    """The items, the in-place merge of the polygon and the grid sums under ASan + UBSan,
    float, against the engine within 1e-5 of the range (the float mean of maximum over
    smooth terms is left to test_matches_engine)."""
    error = sanitized_error(tmp_path, builder(METHODS[method], smooth), n_random=500)
    assert smooth and method == "mom" or error.max() <= 1e-5
