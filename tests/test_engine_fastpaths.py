"""The engine's fast paths (grid term strengths, closed-form centroid) against the general ones."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fuzzyc.engine.centroid import ClosedFormCentroid
from fuzzyc.engine.defuzz import OutputDefuzzifier
from fuzzyc.engine.inference import CompiledRuleBase
from fuzzyc.engine.membership import memberships
from fuzzyc.semantics.model import Aggregation, Defuzzifier, Implication, Inference, TNorm
from test_engine_core import (LABELS5, SINGLE_OUT, TRI_OUT, random_inputs, uniform, var,
                              wedm_like)

INF = math.inf
MAX_MIN = Inference(implication=Implication.MIN, aggregation=Aggregation.MAX)
SUM_PROD = Inference(implication=Implication.PRODUCT, aggregation=Aggregation.SUM)


def general(rb) -> CompiledRuleBase:
    """Every rule for every sample, areas from sorted break points: no fast path at all."""
    engine = CompiledRuleBase(rb, allow_sparse=False)
    for d in engine.defuzzifiers:
        d.closed_form = None
    return engine


def general_centroid(out, inference, alpha):
    d = OutputDefuzzifier(out, inference)
    d.closed_form = None
    return d.from_strengths(alpha)


# -- output variables for the closed form --------------------------------------------------

SHOULDERS = uniform("y", LABELS5)                            # end terms clipped by the range
ASYMMETRIC = var("y", {"A": ("trap", -INF, -INF, -0.7, -0.2), "B": ("trap", -0.6, -0.3, 0.1, 0.5),
                       "C": ("tri", 0.2, 0.6, 1.4)}, lo=-1.0, hi=1.0)   # C reaches past hi
GAPPED = var("y", {"A": ("tri", 0.0, 1.0, 2.0), "B": ("tri", 3.0, 3.5, 5.0)}, lo=0.0, hi=5.0)
PLATEAUS = var("y", {"A": ("trap", 0.0, 1.0, 3.0, 4.0), "B": ("tri", 0.5, 2.0, 3.5),
                     "C": ("tri", 1.0, 2.5, 5.0)}, lo=0.0, hi=5.0)      # three overlap at 2
ASYMMETRIC5 = var("y", dict(zip(LABELS5, [
    ("trap", -INF, -INF, -0.8, -0.3), ("tri", -0.8, -0.3, -0.1), ("trap", -0.3, -0.1, 0.05, 0.3),
    ("tri", 0.05, 0.3, 0.7), ("tri", 0.3, 0.7, 1.6)])))               # a plateau; PB past hi
CLOSED_FORM_OUTPUTS = {"triangles": TRI_OUT[0], "shoulders": SHOULDERS,
                       "asymmetric": ASYMMETRIC, "gapped": GAPPED, "asymmetric5": ASYMMETRIC5}


def strengths(n_terms, n, seed):
    """Random strengths with zeros, ones, ties and all-zero rows."""
    rng = np.random.default_rng(seed)
    alpha = rng.choice([0.0, 0.25, 1.0, -1.0], (n, n_terms))
    alpha = np.where(alpha < 0, rng.uniform(0, 1, (n, n_terms)), alpha)
    alpha[0] = 0.0
    return alpha


def test_hand_computed_clipped_asymmetric_triangle():
    # tri(0, 1, 3) cut at 0.5 on [0, 3]: rises to 0.5 on [0, 0.5], flat to u = 2, falls to 3.
    # area = 0.5*0.5/2 + 1.5*0.5 + 1*0.5/2 = 1.125
    # moment = int_0^.5 u^2 + 0.5 (2^2 - 0.5^2)/2 + int_2^3 u (3-u)/2 = 1/24 + 0.9375 + 7/12
    #        = 1.5625;  centroid = 1.5625 / 1.125 = 25/18
    out = var("y", {"T": ("tri", 0.0, 1.0, 3.0)}, lo=0.0, hi=3.0)
    closed = ClosedFormCentroid.build(out, MAX_MIN)
    assert closed is not None
    assert closed(np.array([[0.5]]))[0] == pytest.approx(25 / 18, abs=1e-14)
    # the whole triangle (level 1): centroid (0 + 1 + 3) / 3
    assert closed(np.array([[1.0]]))[0] == pytest.approx(4 / 3, abs=1e-14)


@pytest.mark.parametrize("name", sorted(CLOSED_FORM_OUTPUTS))
@pytest.mark.parametrize("inference", [MAX_MIN, SUM_PROD], ids=["max-min", "sum-product"])
def test_closed_form_equals_sorted_break_points(name, inference):
    out = CLOSED_FORM_OUTPUTS[name]
    closed = ClosedFormCentroid.build(out, inference)
    assert closed is not None
    alpha = strengths(out.n_terms, 3000, seed=len(name))
    np.testing.assert_allclose(closed(alpha), general_centroid(out, inference, alpha),
                               rtol=0, atol=1e-12)
    assert closed(alpha)[0] == out.default                 # nothing fired


@pytest.mark.parametrize("name", ["asymmetric", "shoulders"])
def test_closed_form_equals_a_fine_numerical_integral(name):
    out = CLOSED_FORM_OUTPUTS[name]
    alpha = np.array([[0.3, 0.8, 0.55, 0.1, 0.9][:out.n_terms]])
    u = np.linspace(out.lo, out.hi, 1_000_001)
    m = np.minimum(alpha, memberships(out, u)).max(axis=1)
    expected = np.trapezoid(u * m, u) / np.trapezoid(m, u)
    assert ClosedFormCentroid.build(out, MAX_MIN)(alpha)[0] == pytest.approx(expected, abs=1e-9)


# Levels from 1e-3 up: below, the general path's split points (level - q) / s lose digits
# (its error grows like 1e-16 / level; at level 1e-9 it is off by 1e-7, the closed form is not).
@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(sorted(CLOSED_FORM_OUTPUTS)),
       levels=st.lists(st.sampled_from([0.0, 1.0, 0.5, 0.3333333333333333, 2.0])
                       | st.floats(1e-3, 1), min_size=5, max_size=5))
def test_closed_form_equals_general_for_any_levels(name, levels):
    out = CLOSED_FORM_OUTPUTS[name]
    alpha = np.array([levels[:out.n_terms]])
    for inference in (MAX_MIN, SUM_PROD):
        got = ClosedFormCentroid.build(out, inference)(alpha)
        assert np.all(np.isfinite(got))
        np.testing.assert_allclose(got, general_centroid(out, inference, alpha),
                                   rtol=0, atol=1e-12)


def test_closed_form_declines_where_it_does_not_apply():
    assert ClosedFormCentroid.build(PLATEAUS, MAX_MIN) is None           # three terms overlap
    assert ClosedFormCentroid.build(PLATEAUS, SUM_PROD) is not None      # linear: any overlap
    max_prod = Inference(implication=Implication.PRODUCT, aggregation=Aggregation.MAX)
    assert ClosedFormCentroid.build(SHOULDERS, max_prod) is None
    assert ClosedFormCentroid.build(SINGLE_OUT[0], MAX_MIN) is None
    vertical = var("y", {"A": ("trap", 0.0, 0.0, 1.0, 2.0)}, lo=0.0, hi=2.0)
    assert ClosedFormCentroid.build(vertical, SUM_PROD) is None
    # and the engine still answers through the general path
    alpha = strengths(3, 500, seed=4)
    d = OutputDefuzzifier(PLATEAUS, Inference(defuzzifier=Defuzzifier.CENTROID))
    assert d.closed_form is None
    np.testing.assert_allclose(d.from_strengths(alpha),
                               general_centroid(PLATEAUS, MAX_MIN, alpha), rtol=0, atol=0)


# -- the grid path ---------------------------------------------------------------------------

@pytest.mark.parametrize("outputs", [TRI_OUT, SINGLE_OUT, [SHOULDERS, ASYMMETRIC5]],
                         ids=["triangles", "singletons", "mixed"])
@pytest.mark.parametrize("method", list(Defuzzifier))
@pytest.mark.parametrize("tnorm, imp, agg, depth, weights", [
    (TNorm.MIN, Implication.MIN, Aggregation.MAX, 1, False),
    (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.SUM, 2, True),
    (TNorm.MIN, Implication.MIN, Aggregation.SUM, 1, True),
    (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.MAX, 1, True),
    (TNorm.MIN, Implication.MIN, Aggregation.PROBSUM, 2, True),
    (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.BOUNDED_SUM, 2, False),
])
def test_fast_paths_equal_the_general_path(outputs, method, tnorm, imp, agg, depth, weights):
    rb = wedm_like(outputs, depth=depth, weights=weights, and_=tnorm, implication=imp,
                   aggregation=agg, defuzzifier=method)
    fast = CompiledRuleBase(rb)
    x = random_inputs(700)                       # NaN, +-inf and exact break points included
    expected = general(rb).evaluate_chunk(x)
    np.testing.assert_allclose(fast.evaluate_chunk(x), expected, rtol=0, atol=1e-12)
    assert np.all(np.isfinite(expected))


def test_grid_is_taken_for_the_usual_case_and_refused_otherwise():
    rb = wedm_like(TRI_OUT, defuzzifier=Defuzzifier.CENTROID)
    engine = CompiledRuleBase(rb)
    assert engine.grid is not None
    assert all(d.closed_form is not None for d in engine.defuzzifiers)
    # SUM of MIN-clipped areas needs every rule on its own: no grid (the sparse path remains)
    rb = wedm_like(TRI_OUT, implication=Implication.MIN, aggregation=Aggregation.SUM,
                   defuzzifier=Defuzzifier.CENTROID)
    engine = CompiledRuleBase(rb)
    assert engine.sparse and engine.grid is None


def test_grid_strengths_by_hand():
    # e1 = 0.3 -> ZO 0.7, P 0.3; e2 = -0.2 -> NS 0.4, ZO 0.6; ce2 = 0.6 -> PS 0.8, PB 0.2.
    # With min, the corner (ZO, ZO, PS) fires min(0.7, 0.6, 0.8) = 0.6, the strongest one.
    rb = wedm_like(SINGLE_OUT, defuzzifier=Defuzzifier.CENTER_OF_AREA)
    engine = CompiledRuleBase(rb)
    alpha = engine.grid(np.array([[0.3, -0.2, 0.6]]))[:, 0]
    term = rb.consequents[(rb.antecedents == [1, 2, 3]).all(axis=1), 0][0]
    assert alpha[engine.grid.slices[0]][term] == pytest.approx(0.6)
    assert alpha[engine.grid.slices[0]].max() == pytest.approx(0.6)
    # and nothing at all for a NaN input
    assert not engine.grid(np.array([[np.nan, 0.0, 0.0]])).any()


def test_chunked_fast_path_is_independent_of_the_chunk():
    rb = wedm_like(TRI_OUT, defuzzifier=Defuzzifier.CENTROID)
    engine = CompiledRuleBase(rb)
    x = random_inputs(301)
    whole = engine.evaluate_chunk(x)
    parts = np.vstack([engine.evaluate_chunk(x[s:s + 13]) for s in range(0, len(x), 13)])
    np.testing.assert_array_equal(parts, whole)


def test_uniform_partitions_share_their_knots_exactly():
    # `terms x : uniform ...` over [-1, 1] with 7 terms (the milling controller's e and ce):
    # the knots are -1 + 2k/6. Computed as peak +- step, the knot -1/3 came out as
    # -0.33333333333333343, -0.3333333333333337 and -0.3333333333333331 in three terms, and the
    # 1-ulp slivers between them (three positive terms) turned the two-terms path off.
    from pathlib import Path
    from fuzzyc.language.parser import load
    model = load(Path(__file__).parents[1] / "rulebases" / "milling_neurofuzzy.fz")
    for v in model.rulebase.inputs:
        p = np.asarray(v.params)
        for left, right in zip(p[:-1], p[1:]):
            assert left[2] == right[0] and left[3] == right[1]   # peak_i = a_{i+1}, d_i = peak_{i+1}
    assert CompiledRuleBase(model.rulebase).sparse
