"""`fuzzyc.compiled_evaluator`: one point at a time through the generated header (issue 29's
"one evaluation from Python" in a microsecond or two; the figure is `make bench`'s, not here).

Its numbers are the header's, whose agreement with the engine tests/test_c_backend.py checks in
float over 100,000 points per case; here the double header, one point per call, against the
engine at 1e-12 of each output's range on the same cases (random points in and 10 % beyond
the range, the edges, NaN and infinities), against the batch C entry bit for bit, and by hand.
"""
from __future__ import annotations

import numpy as np
import pytest

import fuzzyc
from fuzzyc.backends.c.load import CController
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError

from test_c_backend import CASES, inputs_for

DOUBLE_TOLERANCE = 1e-12     # of each output's range


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    model = CASES[request.param]()
    return model, fuzzyc.compiled_evaluator(model)


def test_one_point_at_a_time_is_the_engine(case):
    model, one = case
    rb = model.rulebase
    x = inputs_for(rb, seed=3, n_random=3000)
    got = np.array([one(row) for row in x.tolist()])
    expected = evaluate(rb, x)
    span = np.array([v.hi - v.lo for v in rb.outputs])
    error = np.abs(got - expected) / span
    assert np.all(np.isfinite(got))
    assert error.max() <= DOUBLE_TOLERANCE, x[np.unravel_index(error.argmax(), error.shape)[0]]
    # the batch entry of the same library: the same C, so the same bits
    np.testing.assert_array_equal(got, CController(model, 1, "double").evaluate(x))
    # not vacuous: the outputs move over the points
    assert np.all(expected.max(axis=0) - expected.min(axis=0) > 0.1 * span)


def test_wedm_by_hand():
    """docs/api.md's point: e1 = 1 (P), e2 = 0.25 (ZO = PS = 0.5), ce2 = 0 (ZO): two rules at
    min(1, 0.5, 1) = 0.5 conclude ZO (peak 0) and PS (peak 0.5) for both outputs; the centre of
    area over the peaks is (0.5 * 0 + 0.5 * 0.5) / (0.5 + 0.5) = 0.25.  At e2 = 0 only ZO-ZO-P
    fires: 0.  Nothing fires at a NaN e1 (memberships 0): the declared default 0."""
    model = fuzzyc.load(fuzzyc.example("wedm_three_region.fz"))
    one = fuzzyc.compiled_evaluator(model)
    assert one([1.0, 0.25, 0.0]) == [0.25, 0.25]
    assert one((1, 0, 0)) == [0.0, 0.0]
    assert one(np.array([np.nan, 0.25, 0.0])) == [0.0, 0.0]
    assert one.input_names == ["e1", "e2", "ce2"] and one.output_names == ["du1", "du2"]


def test_float_header_within_float_rounding():
    model = CASES["wedm_three_region"]()
    x = inputs_for(model.rulebase, seed=4, n_random=500)
    one = fuzzyc.compiled_evaluator(model, "float")
    got = np.array([one(row) for row in x.tolist()])
    assert np.abs(got - evaluate(model.rulebase, x)).max() <= 1e-5 * 2   # outputs span 2


def test_bad_calls_say_what_is_wrong():
    model = CASES["wedm_three_region"]()
    one = fuzzyc.compiled_evaluator(model)
    with pytest.raises(ValueError, match=r"expected 3 input values \(e1, e2, ce2\), got 2"):
        one([1.0, 0.0])
    with pytest.raises(TypeError, match=r"input values \(e1, e2, ce2\) must be real numbers"):
        one([1.0, 0.0, "x"])
    with pytest.raises(ValueError, match="numeric is one of float, double, not `q15`"):
        fuzzyc.compiled_evaluator(model, "q15")


def test_no_compiler_is_a_diagnostic(monkeypatch, tmp_path):
    """Nothing cached (a fresh cache folder) and no gcc on the PATH: a FuzzycError, no
    traceback of FileNotFoundError."""
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    monkeypatch.setenv("FUZZYC_CACHE", str(cache))
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(FuzzycError, match="needs a C compiler: `gcc` is not on the PATH"):
        fuzzyc.compiled_evaluator(CASES["wedm_three_region"]())
