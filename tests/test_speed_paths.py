"""The closed loop's fast paths give the very same numbers as the paths they shortcut.

- the grid's fused input location (all inputs in a few numpy calls) against the per-input
  `LocalPartition.locate` it replaces, bit for bit;
- `evaluate_rows` (signals as rows, the controller's layout) against `evaluate_chunk`;
- the controller's unmasked steps and outputs (once every memory is finite) against traces
  computed by hand, with a NaN arriving after the memories are primed;
- clamp compiled to one clip against the Min/Max it stands for.
"""
import math

import numpy as np
import pytest
import sympy

from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import CompiledRuleBase
from fuzzyc.engine.expressions import compile_expr
from fuzzyc.semantics.model import Aggregation, Defuzzifier, Implication, TNorm
from test_controller import model
from test_engine_core import (LABELS5, SINGLE_OUT, TRI_OUT, random_inputs, rulebase,
                              uniform, wedm_like)


def per_input_strengths(grid, x: np.ndarray) -> np.ndarray:
    """The grid's strengths located one input at a time (the path before the fused one)."""
    n = x.shape[0]
    cell = np.zeros(n, dtype=np.intp)
    act = np.ones((1, n))
    for i, part in enumerate(grid.partitions):
        seg, mu = part.locate(x[:, i])
        cell += seg * grid.stride[i]
        act = (act[:, None] * mu[None]).reshape(2 * len(act), n) if grid.product else \
            np.minimum(act[:, None], mu[None]).reshape(2 * len(act), n)
    if grid.depth > 1:
        act = np.repeat(act, grid.depth, axis=0)
    if not grid.unit_weights:
        act = act * grid.weights.take(cell, axis=1)
    index = grid.columns.take(cell, axis=1) * n + np.arange(n)
    alpha = np.full(grid.width * n, grid.accumulate.start)
    for rows in index.reshape(len(grid.slices), -1):
        grid.accumulate.ufunc.at(alpha, rows, grid.accumulate.values(act.reshape(-1)))
    return grid.accumulate.finish(alpha.reshape(grid.width, n))


# the new aggregations take the grid for the peak-based methods only (area-based ones need
# every rule's own shape: see test_aggregation_snorms)
CASES = [(TNorm.MIN, Implication.MIN, Aggregation.MAX, 1, False, Defuzzifier.CENTROID),
         (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.SUM, 2, True, Defuzzifier.CENTROID),
         (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.MAX, 1, True, Defuzzifier.CENTROID),
         (TNorm.MIN, Implication.MIN, Aggregation.PROBSUM, 2, True, Defuzzifier.CENTER_OF_AREA),
         (TNorm.PRODUCT, Implication.MIN, Aggregation.BOUNDED_SUM, 2, False,
          Defuzzifier.CENTER_OF_AREA)]


@pytest.mark.parametrize("tnorm, imp, agg, depth, weights, method", CASES)
def test_fused_location_equals_the_per_input_one(tnorm, imp, agg, depth, weights, method):
    rb = wedm_like(TRI_OUT, depth=depth, weights=weights, and_=tnorm, implication=imp,
                   aggregation=agg, defuzzifier=method)
    grid = CompiledRuleBase(rb).grid
    assert grid.padded_breaks is not None       # every input counted in one comparison
    x = random_inputs(700)                      # NaN, +-inf and exact break points included
    x[7] = np.nan                               # a sample with every input NaN
    for batch in (x, x[:1], x[:0], x[10:11]):   # the batch-size tables follow n
        np.testing.assert_array_equal(grid(batch), per_input_strengths(grid, batch))
    assert not grid(x[7:8]).any()


def test_many_breaks_keep_their_binary_search():
    # 17 terms 0.125 apart (exact in binary): 17 breaks, more than LINEAR_SEARCH_BREAKS, so
    # the fused count is not taken
    fine = uniform("x", [f"T{k}" for k in range(17)])
    coarse = uniform("y", LABELS5)
    rng = np.random.default_rng(3)
    rules = [([a, b], [LABELS5[rng.integers(0, 5)]]) for a in fine.names for b in coarse.names]
    rb = rulebase([fine, coarse], [TRI_OUT[0]], rules, defuzzifier=Defuzzifier.CENTROID)
    grid = CompiledRuleBase(rb).grid
    assert grid is not None and grid.padded_breaks is None
    x = random_inputs(500)[:, :2]
    x[::7, 0] = np.linspace(-1, 1, 17)[np.arange(0, 500, 7) % 17]      # on the breaks
    np.testing.assert_array_equal(grid(x), per_input_strengths(grid, x))


@pytest.mark.parametrize("outputs", [TRI_OUT, SINGLE_OUT], ids=["triangles", "singletons"])
# Tsukamoto needs each rule's own activation (no term strengths, so no grid path); its terms are
# monotonic, which these outputs are not
@pytest.mark.parametrize("method", [d for d in Defuzzifier
                                    if d not in (Defuzzifier.TSUKAMOTO, Defuzzifier.TSUKAMOTO_SUM)])
@pytest.mark.parametrize("sparse", [True, False], ids=["grid", "dense"])
def test_evaluate_rows_is_evaluate_chunk_transposed(outputs, method, sparse):
    rb = wedm_like(outputs, defuzzifier=method)
    engine = CompiledRuleBase(rb, allow_sparse=sparse)
    assert (engine.grid is not None) == sparse
    x = random_inputs(300)
    x[:40] = 5.0            # beyond every term's support on the e1 side: nothing fires
    x[:40, 0] = np.nan
    np.testing.assert_array_equal(engine.evaluate_rows(np.ascontiguousarray(x.T)),
                                  engine.evaluate_chunk(x).T)
    np.testing.assert_array_equal(engine.evaluate_rows(np.ascontiguousarray(x[:1].T)),
                                  engine.evaluate_chunk(x[:1]).T)


def test_peak_ratio_path_is_taken_for_center_of_area_only_where_it_applies():
    assert CompiledRuleBase(wedm_like(SINGLE_OUT, defuzzifier=Defuzzifier.CENTER_OF_AREA)
                            ).peak_ratio
    assert not CompiledRuleBase(wedm_like(SINGLE_OUT, defuzzifier=Defuzzifier.WEIGHTED_SUM)
                                ).peak_ratio
    assert not CompiledRuleBase(wedm_like(TRI_OUT, defuzzifier=Defuzzifier.CENTROID)).peak_ratio


def test_nan_after_the_memories_are_primed_holds_them():
    # x = [0.2, 0.4], [nan, 0.6], [0.5, 0.1]; d = delta(x), p = prev(x), l = 0.75 l + 0.25 x
    c = Controller(model(), batch=2)
    sig = []
    for xs in ([0.2, 0.4], [np.nan, 0.6], [0.5, 0.1]):
        c.step({"x": np.array(xs)})
        sig.append(dict(c.signals))
    np.testing.assert_allclose([s["d"] for s in sig], [[0, 0], [np.nan, 0.2], [0.3, -0.5]],
                               rtol=0, atol=1e-15)
    # prev holds 0.2 through the NaN: 0.2 is still the last finite sample of loop 0
    np.testing.assert_array_equal([s["p"] for s in sig], [[0.2, 0.4], [0.2, 0.4], [0.2, 0.6]])
    # l: [0.2, 0.4]; [nan, 0.75*0.4 + 0.25*0.6 = 0.45]; [0.75*0.2 + 0.25*0.5 = 0.275,
    #    0.75*0.45 + 0.25*0.1 = 0.3625]
    np.testing.assert_allclose([s["l"] for s in sig],
                               [[0.2, 0.4], [np.nan, 0.45], [0.275, 0.3625]], rtol=1e-15)
    # u holds on the NaN sample (du = 0 there); both loops stay finite
    assert np.all(np.isfinite(sig[1]["u"])) and np.all(np.isfinite(sig[1]["t"]))


def test_a_memory_is_not_the_callers_array():
    # prev(x) and delta(x) of an input: the caller may reuse its array for the next sample
    c = Controller(model())
    x = np.array([0.2])
    c.step({"x": x})
    x[0] = 0.6
    c.step({"x": x})
    assert c.signals["p"][0] == 0.2 and c.signals["d"][0] == pytest.approx(0.4)


def test_clamp_runs_as_clip_with_the_same_values():
    x = sympy.Symbol("x")
    values = np.array([np.nan, -np.inf, np.inf, -3.0, -1.0, -0.0, 0.0, 0.3, 1.0, 5.0])
    for lo, hi in ((-1, 1), (-0.5, 2), (0, 1), (-1, 0)):
        expr = sympy.Min(sympy.Max(2 * x, lo), hi)
        got = compile_expr(expr)({"x": values})
        want = np.minimum(float(hi), np.maximum(float(lo), 2 * values))
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(np.signbit(got), np.signbit(want))
    assert math.isclose(compile_expr(sympy.Min(sympy.Max(2 * x, -1), 1))({"x": 0.3}), 0.6)


def test_differences_run_as_subtract_with_the_same_values():
    # sympy holds a - b as a + (-1) b; a + (-b) and a - b are the same IEEE operation
    a, b = sympy.symbols("a b")
    va = np.array([1.0, -0.0, 0.0, -0.0, np.inf, -np.inf, np.nan, 3.5, 0.1])
    vb = np.array([1.0, 0.0, -0.0, -0.0, np.inf, 2.0, 1.0, -1e-300, 0.3])
    env = {"a": va, "b": vb}
    with np.errstate(invalid="ignore"):
        cases = {a - b: va + (-1.0 * vb), b - a: (-1.0 * va) + vb, -a: -1.0 * va,
                 2 - a: 2.0 + (-1.0 * va), -a - b: (-1.0 * va) + (-1.0 * vb),
                 a - 2 * b: va + (-2.0 * vb)}
        for expr, want in cases.items():
            got = compile_expr(expr)(env)
            np.testing.assert_array_equal(got, want, err_msg=str(expr))
            real = ~np.isnan(want)              # a NaN's sign bit carries no value
            np.testing.assert_array_equal(np.signbit(got)[real], np.signbit(want)[real],
                                          err_msg=str(expr))


def test_schedule_holds_between_points_and_switches_at_them():
    from fuzzyc.runtime.blocks import ScheduleBlock
    block = ScheduleBlock("sp", [(0.0, 1.0), (0.12, 2.0), (0.2, 2.0), (0.3, -1.0)])
    block.reset(3)
    times = [k * 0.04 for k in range(12)]        # 0.12 = 3 * 0.04 only up to rounding
    got = [block.step({"t": t})["sp"] for t in times]
    assert [float(v[0]) for v in got] == [block.value_at(t) for t in times]
    assert [float(v[0]) for v in got] == [1, 1, 1, 2, 2, 2, 2, 2, -1, -1, -1, -1]
    assert got[3] is got[7]                       # one array while the value holds
    block.reset(3)                                # and from the start again after a reset
    assert float(block.step({"t": 0.0})["sp"][0]) == 1.0
