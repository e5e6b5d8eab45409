"""Bisector and mean of maximum, and area-based defuzzifiers over smooth output terms, in C
(fuzzyc/backends/c/area.py) against the numpy engine (fuzzyc/engine/defuzz.py).

Each case is compiled with the strict flags (`cload.STRICT_FLAGS`, -Werror) in float and in
double and run on 100,000 random inputs plus every edge (test_c_backend.inputs_for).
Tolerances, as a fraction of the output's range:
- double: 1e-10.  The C walks the same piecewise-linear M as the engine; what differs is the
  order of rounding (a compensated running sum against numpy's pairwise sum, the C polygon's
  points against the engine's point set), tens of ulps; seen: below 1e-13.
- float: 1e-5, as for the rest of the C back end (float has 6e-8 relative resolution; the
  running sums are compensated, so 2,000 grid pieces do not add up their roundings).
- float mean of maximum over smooth terms: no bound in u holds.  The maximum of a smooth M
  is flat to float resolution over several grid points (a bell's top over about 13), float
  cannot tell which of them is highest, and the mean moves by up to their spread (seen: 14 % of
  the product-sum samples beyond 1e-5, worst 1.7e-2 where the engine has two exactly tied
  maxima).  What holds: the float answer lies among the grid points that the engine's M makes
  maximal to 32 float ulps (check_float_mean_of_maximum).  The double C meets 1e-10 there too.
"""
from __future__ import annotations


import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.area import FLOAT_FLAT_TOLERANCE
from fuzzyc.backends.c.load import CController
from fuzzyc.engine.defuzz import GRID_POINTS, term_strengths
from fuzzyc.engine.inference import CompiledRuleBase, evaluate
from fuzzyc.semantics.model import Aggregation, Defuzzifier, Implication, TermKind
from fuzzyc.language.parser import parse

from test_c_backend import inputs_for, variant

BIS, MOM, CEN = Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM, Defuzzifier.CENTROID
MIN_MAX = dict(implication=Implication.MIN, aggregation=Aggregation.MAX)
PROD_SUM = dict(implication=Implication.PRODUCT, aggregation=Aggregation.SUM)
PROD_MAX = dict(implication=Implication.PRODUCT, aggregation=Aggregation.MAX)
TOLERANCE = {"float": 1e-5, "double": 1e-10}
FLOAT_EPS = float(np.finfo(np.float32).eps)
HULL_ULPS = 32


def smooth_outputs(model, outputs=slice(None)):
    """The WEDM outputs' five terms (peaks -1, -0.5, 0, 0.5, 1) as sigmoid, gaussian, bell,
    gaussian, sigmoid: the engine samples M on its grid."""
    for var in model.rulebase.outputs[outputs]:
        var.kinds = np.array([TermKind.SIGMOID, TermKind.GAUSSIAN, TermKind.BELL,
                              TermKind.GAUSSIAN, TermKind.SIGMOID])
        var.params = np.array([[-0.75, -20, 0, 0], [-0.5, 0.2, 0, 0], [0, 0.25, 2, 0],
                               [0.5, 0.2, 0, 0], [0.75, 20, 0, 0]])
    return model


def wedm(method, norms, smooth=False):
    model = variant("wedm_three_region", defuzzifier=method, **norms)
    return smooth_outputs(model) if smooth else model


CASES = {
    "bisector_min_max": lambda: wedm(BIS, MIN_MAX),
    "bisector_prod_sum": lambda: wedm(BIS, PROD_SUM),
    "mom_min_max": lambda: wedm(MOM, MIN_MAX),
    "mom_prod_sum": lambda: wedm(MOM, PROD_SUM),
    "bisector_prod_max": lambda: wedm(BIS, PROD_MAX),   # scaled lines crossing: candidates
    "mom_prod_max": lambda: wedm(MOM, PROD_MAX),
    "smooth_centroid_min_max": lambda: wedm(CEN, MIN_MAX, smooth=True),
    "smooth_centroid_prod_sum": lambda: wedm(CEN, PROD_SUM, smooth=True),
    "smooth_bisector_min_max": lambda: wedm(BIS, MIN_MAX, smooth=True),
    "smooth_bisector_prod_sum": lambda: wedm(BIS, PROD_SUM, smooth=True),
    "smooth_mom_min_max": lambda: wedm(MOM, MIN_MAX, smooth=True),
    "smooth_mom_prod_sum": lambda: wedm(MOM, PROD_SUM, smooth=True),
    # du1 sampled on the grid, du2 walked as its exact polygon, in one header
    "mixed_bisector_min_max": lambda: smooth_outputs(wedm(BIS, MIN_MAX), slice(0, 1)),
}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    model = CASES[request.param]()
    x = inputs_for(model.rulebase)
    return request.param, model, x, evaluate(model.rulebase, x)


def engine_grid_m(rb, x: np.ndarray, o: int) -> tuple[np.ndarray, np.ndarray]:
    """The engine's grid and its M there (N, GRID_POINTS) for output o of a sampled case."""
    engine = CompiledRuleBase(rb)
    act, rid = engine.candidates(x)
    J = rb.consequents[:, o] if rid is None else engine.consequents[rid, o]
    od = engine.defuzzifiers[o]
    if od.strength_aggregation() is None:     # SUM of MIN-clipped rules: every rule an item
        return od.grid, items_grid_m(od.grid_mu, np.where(J >= 0, act, 0.0),
                                     np.broadcast_to(J, act.shape))
    alpha = term_strengths(act, J, rb.outputs[o].n_terms, od.strength_aggregation())
    if rb.inference.implication == Implication.MIN:
        return od.grid, np.minimum(alpha[:, None, :], od.grid_mu[None]).max(axis=2)
    return od.grid, alpha @ od.grid_mu.T


def items_grid_m(grid_mu: np.ndarray, levels: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """sum_k min(levels[:, k], grid_mu[:, ids[:, k]]) (N, P), in chunks of rows so the
    (rows, P, K) temporary stays near 2**22 values."""
    rows = max(1, (1 << 22) // (grid_mu.size // grid_mu.shape[1] * ids.shape[1]))
    return np.concatenate([
        np.minimum(levels[s, None, :], grid_mu[:, ids[s]].transpose(1, 0, 2)).sum(axis=2)
        for s in (slice(i, i + rows) for i in range(0, len(levels), rows))])


def check_float_mean_of_maximum(rb, x, got, error, span) -> None:
    """Where float and double differ, the float answer lies among the engine's grid points
    that are maximal to float resolution: the mean of maximum of a smooth M is ill-conditioned
    (a bell's top is flat to 6e-8 over 8 grid points), so float can only say which points are
    maximal to its resolution.  HULL_ULPS = 32: the float C counts points within 4 ulps of its
    top, its M carries a few ulps of rounding per term; 32 covers both with margin."""
    for o in range(len(rb.outputs)):
        bad = np.flatnonzero(error[:, o] > TOLERANCE["float"])
        grid, m = engine_grid_m(rb, x[bad], o)
        top = m.max(axis=1, keepdims=True)
        near = m >= top - HULL_ULPS * FLOAT_EPS * np.maximum(top, 1.0)
        first = grid[near.argmax(axis=1)]
        last = grid[len(grid) - 1 - near[:, ::-1].argmax(axis=1)]
        margin = TOLERANCE["float"] * span[o]
        assert np.all((got[bad, o] >= first - margin) & (got[bad, o] <= last + margin))


@pytest.mark.parametrize("numeric", ["float", "double"])
def test_matches_engine(case, numeric):
    name, model, x, expected = case
    check_against_engine(name, model, x, expected, numeric,
                         ill_conditioned=numeric == "float" and name.startswith("smooth_mom"))


def check_against_engine(name, model, x, expected, numeric, ill_conditioned: bool) -> None:
    """The C in `numeric` within TOLERANCE of the engine's `expected` (ill_conditioned: the
    float mean of maximum over smooth terms, held by check_float_mean_of_maximum), and the
    outputs move over the sample."""
    rb = model.rulebase
    got = CController(model, numeric=numeric).evaluate(x)
    assert np.all(np.isfinite(got))
    span = np.array([v.hi - v.lo for v in rb.outputs])
    error = np.abs(got - expected) / span
    worst = np.unravel_index(error.argmax(), error.shape)
    print(f"{name} {numeric}: worst {error.max():.3g} of the range, "
          f"{np.mean(error.max(axis=1) > TOLERANCE[numeric]):.4f} of the samples beyond "
          f"{TOLERANCE[numeric]:g}")
    if ill_conditioned:
        check_float_mean_of_maximum(rb, x, got, error, span)
    else:
        assert error.max() <= TOLERANCE[numeric], (x[worst[0]], expected[worst[0]], got[worst[0]])
    # Not vacuous: the outputs move over the sample.
    assert np.all(expected.max(axis=0) - expected.min(axis=0) > 0.1 * span)


TWO_TERMS = """controller two {
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  var y in [0, 10]
  terms y : a = tri(0, 2, 4), b = trap(4, 8, 9, 10)
  inference implication = min, aggregation = max, defuzzify = DEFUZZ
  rule if x is lo then y is a
  rule if x is hi then y is b
  output u in [0, 10] = y
}
"""


def two_terms(method: str, numeric: str) -> CController:
    return CController(parse(TWO_TERMS.replace("DEFUZZ", method), "two.fz"), numeric=numeric)


@pytest.mark.parametrize("numeric, atol", [("float", 1e-5), ("double", 1e-12)])
def test_hand_computed_bisector(numeric, atol):
    # x = 0.5: lo = hi = 0.5.  a = tri(0, 2, 4) clipped at 0.5: area 0.5 * (4 + 2) / 2 = 1.5.
    # b = trap(4, 8, 9, 10) clipped at 0.5: rises (u - 4) / 4 to 0.5 at u = 6, flat to 9.5,
    # falls to 10: area 0.5 * (6 + 3.5) / 2 = 2.375.  Half of 3.875 is 1.9375; a gives 1.5, so
    # 0.4375 more inside b's rise, whose area from 4 to u is (u - 4)^2 / 8 (0.5 at u = 6):
    # (u - 4)^2 = 3.5, u = 4 + sqrt(3.5) = 5.8708287.
    got = two_terms("bisector", numeric).evaluate([[0.5]])
    np.testing.assert_allclose(got, [[4 + np.sqrt(3.5)]], atol=atol)


@pytest.mark.parametrize("numeric, atol", [("float", 1e-5), ("double", 1e-12)])
def test_hand_computed_mean_of_maximum(numeric, atol):
    # x = 0.5: top 0.5 on a's plateau [1, 3] (length 2, middle 2) and b's [6, 9.5] (length 3.5,
    # middle 7.75): (2 * 2 + 3.5 * 7.75) / 5.5 = 31.125 / 5.5 = 5.6590909.
    # x = 0: only a, unclipped: one isolated maximum, its peak 2.
    # x = 1: only b, unclipped: plateau [8, 9], middle 8.5.
    got = two_terms("mean_of_maximum", numeric).evaluate([[0.5], [0.0], [1.0]])
    np.testing.assert_allclose(got, [[31.125 / 5.5], [2.0], [8.5]], atol=atol)


@pytest.mark.parametrize("method", ["centroid", "bisector", "mean_of_maximum"])
def test_symmetric_gaussian_on_the_grid(method):
    # One gaussian at 5 on [0, 10]: the grid (step 0.005, 5 at index 1000) and M are symmetric
    # about 5, so centroid, bisector and mean of maximum are all 5.  Clipped at 0.5 (x = 0.5)
    # the maximal plateau is symmetric too.
    text = TWO_TERMS.replace("DEFUZZ", method).replace(
        "a = tri(0, 2, 4), b = trap(4, 8, 9, 10)", "a = gauss(5, 1), b = gauss(5, 1)")
    for numeric in ("float", "double"):
        got = CController(parse(text, "g.fz"), numeric=numeric).evaluate([[0.5], [1.0]])
        np.testing.assert_allclose(got, [[5.0], [5.0]], atol=1e-5 if numeric == "float"
                                   else 1e-12)


def test_grid_is_one_constant_table_and_walked_without_malloc():
    # Both WEDM outputs have the same five terms: one table of 2001 x 5 serves both.
    text = generate_header(wedm(BIS, MIN_MAX, smooth=True))
    assert text.count(f"static const float WEDM_THREE_REGION_GRID_0[{GRID_POINTS}][5] =") == 1
    assert "GRID_1" not in text and text.count("wedm_three_region_grid_0, alpha") == 2
    assert "malloc" not in text


def test_float_tolerance_is_a_few_ulps():
    assert FLOAT_FLAT_TOLERANCE == 4 * FLOAT_EPS < HULL_ULPS * FLOAT_EPS


VERTICAL = TWO_TERMS.replace("a = tri(0, 2, 4), b = trap(4, 8, 9, 10)",
                             "a = tri(0, 2, 5), b = trap(4, 4, 6, 8)")
# x = 1: only b = trap(4, 4, 6, 8), unclipped, with a vertical rise at 4 inside the range:
# rectangle [4, 6] (area 2, centre 5) and triangle [6, 8] (area 1, centre 20/3): centroid
# (10 + 20/3) / 3 = 50/9 = 5.5556; bisector: half the area 1.5 is reached at 4 + 1.5 = 5.5.
VERTICAL_EXACT = [("centroid", 50 / 9), ("bisector", 5.5)]


@pytest.mark.parametrize("method, exact", VERTICAL_EXACT)
def test_c_is_exact_at_an_interior_vertical_edge(method, exact):
    model = parse(VERTICAL.replace("DEFUZZ", method), "v.fz")
    got = CController(model, numeric="double").evaluate([[1.0]])
    np.testing.assert_allclose(got, [[exact]], atol=1e-12)


@pytest.mark.parametrize("inference", ["implication = min, aggregation = max",
                                       "implication = product, aggregation = sum"])
@pytest.mark.parametrize("method, exact", VERTICAL_EXACT)
def test_engine_is_exact_at_an_interior_vertical_edge(method, exact, inference):
    # without a point 1 ulp left of the edge the engine ramped M from the previous break
    # point (2) up to it: centroid 5.0 and bisector 5.0 (fuzzyc/engine/defuzz.py, vertical edges)
    text = VERTICAL.replace("DEFUZZ", method).replace(
        "implication = min, aggregation = max", inference)
    model = parse(text, "v.fz")
    np.testing.assert_allclose(evaluate(model.rulebase, np.array([[1.0]])), [[exact]],
                               atol=1e-12)
