"""The scalar path (fuzzyc.engine.scalar): one evaluation on Python floats gives the batch engine's
bits, and a sample's result does not depend on the batch it is evaluated in.

The batch-independence tests fail on the engine before the scalar path (2e7648d): the peak
ratios went through BLAS, whose kernels gave edm_sink_gap.fz (peaks +-0.08, +-0.3) a different
last bit for about 9 % of the samples evaluated one at a time, and the exact centroid summed
its pieces pairwise at batch 1 (row by row beyond), 11 % of WEDM's triangle-output samples."""
from __future__ import annotations

import copy
import pathlib

import numpy as np
import pytest

from fuzzyc.engine.inference import compiled, evaluate, evaluate_one, scalar_evaluator
from fuzzyc.language.parser import load
from fuzzyc.semantics.model import Aggregation, Defuzzifier, TNorm

ROOT = pathlib.Path(__file__).resolve().parents[1]


def wedm():
    return load(ROOT / "rulebases" / "wedm_three_region.fz").rulebase


def variant(edit):
    rb = wedm()
    edit(rb)
    return rb


CASES = {
    "wedm": wedm,
    "edm_sink_gap": lambda: load(ROOT / "rulebases" / "edm_sink_gap.fz").rulebase,
    "product t-norm": lambda: variant(lambda r: setattr(r.inference, "and_", TNorm.PRODUCT)),
    "sum": lambda: variant(lambda r: setattr(r.inference, "aggregation", Aggregation.SUM)),
    "bounded sum": lambda: variant(
        lambda r: setattr(r.inference, "aggregation", Aggregation.BOUNDED_SUM)),
    "weighted average": lambda: variant(
        lambda r: setattr(r.inference, "defuzzifier", Defuzzifier.WEIGHTED_AVERAGE)),
    "weights": lambda: variant(lambda r: setattr(r, "weights", np.linspace(0.2, 1, r.n_rules))),
}


def points(rb, n: int = 4000, seed: int = 0) -> np.ndarray:
    """In range, out of range, on each break point and one ulp either side, infinities."""
    rng = np.random.default_rng(seed)
    lo = np.array([v.lo for v in rb.inputs], dtype=float)
    hi = np.array([v.hi for v in rb.inputs], dtype=float)
    rows = [rng.uniform(lo, hi, (n, len(lo))), rng.uniform(2 * lo - hi, 2 * hi - lo, (n, len(lo)))]
    for i, part in enumerate(compiled(rb).grid.partitions):
        for b in part.breaks:
            for v in (b, np.nextafter(b, -np.inf), np.nextafter(b, np.inf)):
                row = rng.uniform(lo, hi, (1, len(lo)))
                row[0, i] = v
                rows.append(row)
    rows.append(np.full((1, len(lo)), np.inf))
    rows.append(np.full((1, len(lo)), -np.inf))
    return np.vstack(rows)


@pytest.mark.parametrize("case", CASES)
def test_the_scalar_path_gives_the_batch_engines_bits(case):
    rb = CASES[case]()
    engine = compiled(rb)
    assert engine.scalar is not None
    x = points(rb)
    batch = evaluate(rb, x)
    one_by_one = np.array([engine.scalar(row) for row in x.tolist()])
    np.testing.assert_array_equal(one_by_one, batch)


def triangle_centroid():
    """WEDM with uniform triangle output terms (same peaks) and the exact centroid."""
    rb = wedm()
    for v in rb.outputs:
        peaks = v.peaks()
        h = np.diff(peaks).min()
        v.params = np.stack([peaks - h, peaks, peaks, peaks + h], axis=1)
    rb.inference.defuzzifier = Defuzzifier.CENTROID
    return rb


@pytest.mark.parametrize("case", ["wedm", "edm_sink_gap", "centroid"])
def test_a_samples_result_does_not_depend_on_its_batch(case):
    rb = triangle_centroid() if case == "centroid" else CASES[case]()
    x = points(rb, n=1500, seed=1)
    batch = evaluate(rb, x)
    np.testing.assert_array_equal(evaluate(rb, x, chunk=97), batch)
    singles = np.vstack([evaluate(rb, x[k:k + 1]) for k in range(0, len(x), 7)])
    np.testing.assert_array_equal(singles, batch[::7])
    rows = compiled(rb).evaluate_rows(np.ascontiguousarray(x.T))      # the controller's call
    np.testing.assert_array_equal(rows.T, batch)


def test_nan_inputs_take_the_batch_engine():
    rb = wedm()
    f = scalar_evaluator(rb)
    x = np.array([[np.nan, 0.2, 0.3], [0.1, np.nan, np.nan], [0.1, 0.2, 0.3]])
    expected = evaluate(rb, x, chunk=3)
    assert compiled(rb).scalar(x[0].tolist()) is None
    np.testing.assert_array_equal(np.array([f(row) for row in x.tolist()]), expected)


def test_evaluate_one_and_scalar_evaluator_agree_with_the_batch():
    rb = wedm()
    x = points(rb, n=200, seed=2)
    batch = evaluate(rb, x)
    f = scalar_evaluator(rb)
    names = [v.name for v in rb.inputs]
    for row, expected in zip(x.tolist(), batch.tolist()):
        assert f(row) == expected
        assert list(evaluate_one(rb, dict(zip(names, row))).values()) == expected


def test_off_the_scalar_paths_reach_the_evaluator_is_the_batch_engine():
    rb = wedm()
    centroid = copy.deepcopy(rb)
    centroid.inference.defuzzifier = Defuzzifier.CENTROID     # needs the terms' areas
    assert compiled(centroid).scalar is None
    x = points(rb, n=100, seed=3)
    f = scalar_evaluator(centroid)
    np.testing.assert_array_equal(np.array([f(row) for row in x.tolist()]),
                                  evaluate(centroid, x))


def test_known_points_of_the_wedm_table():
    """e1 = e2 = ce2 = 0: rule (ZO, ZO, ZO) fires alone at 1 (the peaks of the triangles):
    du1 = ZO = 0, du2 = NS = -0.5 (block e1 ZO, row e2 ZO, column ce2 ZO of Table 2).
    e2 = 0.25 is half ZO (tri(-0.5, 0, 0.5)) and half PS (tri(0, 0.5, 1)), so rules (ZO, ZO, ZO)
    and (ZO, PS, ZO) fire at 0.5 each: du1 = (0.5 * 0 + 0.5 * 0.5) / 1 = 0.25 (ZO, PS),
    du2 = (0.5 * -0.5 + 0.5 * 0) / 1 = -0.25 (NS, ZO)."""
    f = scalar_evaluator(wedm())
    assert f([0.0, 0.0, 0.0]) == [0.0, -0.5]
    assert f([0.0, 0.25, 0.0]) == [0.25, -0.25]


@pytest.mark.parametrize("case", ["wedm", "centroid"])
def test_the_controllers_rows_give_evaluates_bits_over_several_chunks(case):
    rb = triangle_centroid() if case == "centroid" else wedm()
    engine = compiled(rb)
    x = np.random.default_rng(4).uniform(-1.2, 1.2, (3 * engine.chunk_limit + 5, 3))
    rows = engine.evaluate_rows(np.ascontiguousarray(x.T))
    np.testing.assert_array_equal(rows.T, evaluate(rb, x))
    # the pool kept no workspace larger than a chunk's
    assert max(engine.pool._free) <= engine.chunk_limit


def test_the_scalar_path_reads_any_real_number_as_a_double():
    """float32 and int inputs: the batch engine converts to float64 first, so does the scalar
    path (NumPy 2 would otherwise compute float32 - float in float32)."""
    rb = wedm()
    f = scalar_evaluator(rb)
    x32 = np.random.default_rng(6).uniform(-1.2, 1.2, (300, 3)).astype(np.float32)
    expected = evaluate(rb, x32.astype(float))
    for row, y in zip(x32, expected.tolist()):
        assert f([row[0], int(row[1] > 0), row[2]]) == evaluate(
            rb, np.array([[row[0], int(row[1] > 0), row[2]]], dtype=float))[0].tolist()
        assert f(list(row)) == y
