"""Properties of the engine for every input hypothesis can find."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from fuzzyc.engine.inference import evaluate
from fuzzyc.semantics.model import Aggregation, Defuzzifier, Implication, RuleBase, TNorm
from test_engine_core import SINGLE_OUT, TRI_OUT, wedm_like

finite = st.floats(-5, 5, allow_nan=False)
anything = st.floats(allow_nan=True, allow_infinity=True)
rows = st.lists(st.tuples(anything, anything, anything), min_size=1, max_size=20)

BOUNDED = [Defuzzifier.CENTROID, Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM,
           Defuzzifier.CENTER_OF_AREA, Defuzzifier.WEIGHTED_AVERAGE]
CHOICES = {0: (TNorm.MIN, Implication.MIN, Aggregation.MAX),
           1: (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.SUM),
           2: (TNorm.MIN, Implication.MIN, Aggregation.PROBSUM),
           3: (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.BOUNDED_SUM)}
RULEBASES = {(m, tri, agg): wedm_like(TRI_OUT if tri else SINGLE_OUT, seed=7, weights=True,
                                      and_=CHOICES[agg][0], implication=CHOICES[agg][1],
                                      aggregation=CHOICES[agg][2], defuzzifier=m)
             for m in BOUNDED for tri in (False, True) for agg in CHOICES}
KEYS = sorted(RULEBASES)


@settings(max_examples=40, deadline=None)
@given(key=st.sampled_from(KEYS), x=st.lists(st.tuples(finite, finite, finite), min_size=1,
                                              max_size=20))
def test_output_within_span_of_output_terms(key, x):
    y = evaluate(RULEBASES[key], np.array(x))
    assert np.all(np.isfinite(y))
    assert np.all((y >= -1 - 1e-12) & (y <= 1 + 1e-12))   # every output term lies in [-1, 1]


@settings(max_examples=40, deadline=None)
@given(key=st.sampled_from(KEYS), x=rows)
def test_never_nan_and_batch_equals_one_by_one(key, x):
    rb = RULEBASES[key]
    x = np.array(x, dtype=float)
    y = evaluate(rb, x)
    assert np.all(np.isfinite(y))
    single = np.vstack([evaluate(rb, row[None]) for row in x])
    np.testing.assert_allclose(y, single, rtol=0, atol=1e-12)


def permuted(rb: RuleBase, order: np.ndarray) -> RuleBase:
    return RuleBase(rb.inputs, rb.outputs, rb.antecedents[order], rb.consequents[order],
                    rb.weights[order], rb.negated[order], rb.hedges[order], rb.connective[order],
                    rb.inference)


@settings(max_examples=25, deadline=None)
@given(key=st.sampled_from(KEYS), x=rows, seed=st.integers(0, 2 ** 16))
def test_invariant_under_rule_permutation(key, x, seed):
    rb = RULEBASES[key]
    order = np.random.default_rng(seed).permutation(rb.n_rules)
    x = np.array(x, dtype=float)
    np.testing.assert_allclose(evaluate(permuted(rb, order), x), evaluate(rb, x),
                               rtol=0, atol=1e-12)
