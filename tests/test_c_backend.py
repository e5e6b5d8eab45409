"""The generated C against the numpy engine: every shipped rule base, several inference choices,
>= 100,000 random inputs plus the edges (range bounds, break points, just outside, NaN, +-inf).

The C is compiled with -std=c99 -O2 -Wall -Wextra -Wpedantic -Wconversion -Wshadow -Werror
(`cload.STRICT_FLAGS`), so a warning fails the build and the test.  Float results must be
within 1e-5 of each output's range of the engine's (double) results.
"""
from __future__ import annotations

import copy
import itertools
import pathlib

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.load import STRICT_FLAGS, CController
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.semantics.model import (Aggregation, Defuzzifier, Implication, SNorm, TermKind, TNorm,
                          set_entries)
from fuzzyc.language.parser import load

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHIPPED = ["wedm_three_region", "wedm_corner", "milling_neurofuzzy", "edm_sink_gap"]
N_RANDOM = 100_000
FLOAT_TOLERANCE = 1e-5


def shipped(name: str):
    model = load(ROOT / "rulebases" / f"{name}.fz")
    if name == "milling_neurofuzzy":   # ships untrained (all 0): give it values to check
        out = model.rulebase.outputs[0]
        set_entries(out, "params", np.s_[:, 0],
                    np.random.default_rng(7).uniform(-40, 40, out.n_terms))
    return model


def variant(name: str, **inference):
    model = copy.deepcopy(shipped(name))
    for key, value in inference.items():
        setattr(model.rulebase.inference, key, value)
    return model


def general_dense():
    """WEDM with every dense-path feature: NOT, hedges, OR, wildcards, weights, product/probsum."""
    model = variant("wedm_three_region", and_=TNorm.PRODUCT, or_=SNorm.PROBSUM)
    rb = model.rulebase
    set_entries(rb, "negated", np.s_[::7, 1], True)
    hedges = rb.hedges.copy()
    hedges[::5, 0] = 1
    hedges[::11, 2] = 2
    hedges[::9, 1] = 3
    rb.hedges = hedges
    set_entries(rb, "connective", np.s_[::3], 1)
    antecedents = rb.antecedents.copy()
    antecedents[::13, 2] = -1
    antecedents[74] = -1                 # a rule of wildcards only: fires 1
    rb.antecedents = antecedents
    set_entries(rb, "weights", np.s_[::4], 0.5)
    return model


def smooth_terms():
    """Gaussian, bell and sigmoid input terms (libm shapes) on the corner rule base."""
    model = copy.deepcopy(shipped("wedm_corner"))
    var = model.rulebase.inputs[0]
    var.kinds = np.array([TermKind.SIGMOID, TermKind.GAUSSIAN, TermKind.BELL,
                          TermKind.GAUSSIAN, TermKind.SIGMOID])
    var.params = np.array([[40, -0.1, 0, 0], [80, 20, 0, 0], [125, 30, 2, 0],
                           [170, 25, 0, 0], [210, 0.1, 0, 0]])
    return model


CASES = {
    **{name: (lambda n=name: shipped(n)) for name in SHIPPED},
    "wedm_centroid_min_max": lambda: variant("wedm_three_region",
                                             defuzzifier=Defuzzifier.CENTROID),
    "wedm_centroid_prod_max": lambda: variant("wedm_three_region",
                                              defuzzifier=Defuzzifier.CENTROID,
                                              implication=Implication.PRODUCT),
    "wedm_centroid_prod_sum": lambda: variant("wedm_three_region",
                                              defuzzifier=Defuzzifier.CENTROID,
                                              implication=Implication.PRODUCT,
                                              aggregation=Aggregation.SUM),
    "wedm_weighted_average": lambda: variant("wedm_three_region",
                                             defuzzifier=Defuzzifier.WEIGHTED_AVERAGE),
    "general_dense_coa": general_dense,
    "general_dense_centroid": lambda: _with(general_dense(), defuzzifier=Defuzzifier.CENTROID),
    "smooth_terms": smooth_terms,
}


def _with(model, **inference):
    for key, value in inference.items():
        setattr(model.rulebase.inference, key, value)
    return model


def edge_values(var) -> np.ndarray:
    """Per input: its bounds, every finite break point, just outside the range, NaN, +-inf."""
    params = np.asarray(var.params, dtype=float)
    locations = np.where((var.kinds == TermKind.TRAPEZOID)[:, None], params, params[:, :1])
    breaks = locations[np.isfinite(locations)]
    span = var.hi - var.lo
    return np.unique(np.concatenate([breaks, [var.lo, var.hi, var.lo - 1e-3 * span,
                                              var.hi + 1e-3 * span, np.inf, -np.inf, np.nan]]))


def inputs_for(rb, seed: int = 0, n_random: int = N_RANDOM) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo = np.array([v.lo for v in rb.inputs])
    hi = np.array([v.hi for v in rb.inputs])
    random = lo + (hi - lo) * rng.uniform(-0.1, 1.1, (n_random, len(lo)))
    edges = np.array(list(itertools.product(*[edge_values(v) for v in rb.inputs])))
    return np.concatenate([random, edges])


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    model = CASES[request.param]()
    return model, CController(model)


def test_rule_base_matches_engine(case):
    model, controller = case
    rb = model.rulebase
    x = inputs_for(rb)
    expected, got = evaluate(rb, x), controller.evaluate(x)
    assert np.all(np.isfinite(got))
    span = np.array([v.hi - v.lo for v in rb.outputs])
    error = np.abs(got - expected) / span
    worst = np.unravel_index(error.argmax(), error.shape)
    assert error.max() <= FLOAT_TOLERANCE, (x[worst[0]], expected[worst[0]], got[worst[0]])
    # The check is not vacuous: the outputs move over the sample.
    assert np.all(expected.max(axis=0) - expected.min(axis=0) > 0.1 * span)


def test_nan_input_gives_declared_defaults():
    # Every rule of the WEDM base needs all three inputs, so one NaN input fires nothing and
    # both outputs take their declared default 0.
    model = shipped("wedm_three_region")
    got = CController(model).evaluate([[np.nan, 0.2, 0.3], [0.5, np.nan, 0.1]])
    np.testing.assert_array_equal(got, np.zeros((2, 2)))


def test_hand_computed_center_of_area():
    # e1 = 1 (P only), e2 = 0.25 (ZO 0.5, PS 0.5), ce2 = 0 (ZO 1): two rules fire with 0.5.
    # Table 2, e1 = P: du1(e2=ZO, ce2=ZO) = ZO (peak 0), du1(e2=PS, ce2=ZO) = PS (peak 0.5):
    # (0.5*0 + 0.5*0.5) / (0.5 + 0.5) = 0.25; du2 has the same two terms there: 0.25.
    got = CController(shipped("wedm_three_region")).evaluate([[1.0, 0.25, 0.0]])
    np.testing.assert_allclose(got, [[0.25, 0.25]], atol=1e-6)


def test_unsupported_numeric_is_a_diagnostic():
    # (The centroid of sum-aggregated min-implied rules, refused here before, is emitted now:
    # tests/test_c_sum_min.py.)
    with pytest.raises(FuzzycError, match="numeric `long double` is not emitted"):
        generate_header(shipped("wedm_three_region"), numeric="long double")


def test_header_names_source_hash_and_choices():
    model = shipped("wedm_three_region")
    text = generate_header(model)
    assert model.source_hash in text
    assert model.rulebase.inference.describe() in text
    assert "malloc" not in text and "static inline" in text
    assert STRICT_FLAGS[-1] == "-Werror"
