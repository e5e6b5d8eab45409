"""Agreement with fuzzylite itself (pyfuzzylite, not a dependency: skipped without it) on the
same FLL text, on 2000 random inputs per engine.

Agreement reached (pyfuzzylite 8.0.6):
- weighted average / weighted sum / center of area (WeightedAverage by Maximum): exact engine
  and fuzzylite agree to 1e-12;
- Centroid, Bisector, MeanOfMaximum: `fuzzylite_compat.evaluate_sampled` at the file's resolution
  agrees to 1e-9 on tipper.fll (in practice 1e-13: same midpoints, same ties) and to 1e-12 on
  ramp.fll's 41 x 41 input grid (measured max 8.9e-16), every aggregation x implication;
- the exact centroid differs from fuzzylite's sampled one by at most 0.0087 (resolution 100) and
  0.00015 (resolution 1000) on tipper.fll's [0, 30] output, under aggregation Maximum,
  AlgebraicSum and BoundedSum alike (test_aggregation_snorms compares a case where they differ).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.formats import load_any, read_fll, write_fll
from fuzzyc.formats.fuzzylite_compat import evaluate_sampled

fl = pytest.importorskip("fuzzylite")

ROOT = Path(__file__).parent.parent
CORPUS = Path(__file__).parent / "format_corpus"
TIPPER = (CORPUS / "tipper.fll").read_text()
RAMP = (CORPUS / "ramp.fll").read_text()


def fuzzylite_outputs(text: str, x: np.ndarray) -> np.ndarray:
    engine = fl.FllImporter().from_string(text)
    rb = read_fll(text, "<fll>").rulebase
    for i, var in enumerate(rb.inputs):
        engine.input_variable(var.name).value = x[:, i]
    engine.process()
    return np.column_stack([np.atleast_1d(engine.output_variable(v.name).value)
                            for v in rb.outputs])


def random_inputs(rb, n: int = 2000, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(v.lo, v.hi, n) for v in rb.inputs])


def weighted_texts():
    yield from ((p.name, p.read_text()) for p in sorted(CORPUS.glob("*.fll"))
                if not p.name.startswith("bad_") and p.name not in ("tipper.fll", "ramp.fll"))
    for path in sorted((ROOT / "rulebases").glob("*.fz")):
        yield path.name, write_fll(load_any(path))


@pytest.mark.parametrize("name, text", list(weighted_texts()), ids=lambda v: str(v)[:20])
def test_weighted_defuzzifiers_agree_exactly(name, text):
    rb = read_fll(text, name).rulebase
    x = random_inputs(rb)
    np.testing.assert_allclose(evaluate(rb, x), fuzzylite_outputs(text, x), rtol=0, atol=1e-12)


@pytest.mark.parametrize("method", ["Centroid", "Bisector", "MeanOfMaximum"])
@pytest.mark.parametrize("resolution", [100, 1000])
@pytest.mark.parametrize("aggregation, implication", [("Maximum", "Minimum"),
                                                      ("UnboundedSum", "AlgebraicProduct"),
                                                      ("AlgebraicSum", "Minimum"),
                                                      ("BoundedSum", "AlgebraicProduct")])
def test_sampled_compat_reproduces_fuzzylite(method, resolution, aggregation, implication):
    text = (TIPPER.replace("Centroid 100", f"{method} {resolution}")
            .replace("aggregation: Maximum", f"aggregation: {aggregation}")
            .replace("implication: Minimum", f"implication: {implication}"))
    rb = read_fll(text, "tipper.fll").rulebase
    x = random_inputs(rb)
    theirs = fuzzylite_outputs(text, x)
    np.testing.assert_allclose(evaluate_sampled(rb, x, resolution), theirs, rtol=0, atol=1e-9)


@pytest.mark.parametrize("resolution, bound", [(100, 0.0087), (1000, 0.00015)])
@pytest.mark.parametrize("aggregation", ["Maximum", "AlgebraicSum", "BoundedSum"])
def test_exact_centroid_differs_by_the_sampling_error_only(resolution, bound, aggregation):
    text = TIPPER.replace("Centroid 100", f"Centroid {resolution}").replace(
        "aggregation: Maximum", f"aggregation: {aggregation}")
    rb = read_fll(text, "tipper.fll").rulebase
    x = random_inputs(rb)
    gap = np.max(np.abs(evaluate(rb, x) - fuzzylite_outputs(text, x)))
    assert 0 < gap <= bound


@pytest.mark.parametrize("method", ["Centroid", "Bisector", "MeanOfMaximum"])
@pytest.mark.parametrize("resolution", [100, 1000])
@pytest.mark.parametrize("aggregation", ["Maximum", "AlgebraicSum", "BoundedSum", "UnboundedSum"])
@pytest.mark.parametrize("implication", ["Minimum", "AlgebraicProduct"])
def test_sampled_compat_reproduces_fuzzylite_on_ramp(method, resolution, aggregation, implication):
    # A 1/40 input grid: rule levels repeat there, so the bisector's near-ties are exercised
    # (random inputs almost never hit them).
    text = (RAMP.replace("Bisector 1000", f"{method} {resolution}")
            .replace("aggregation: Maximum", f"aggregation: {aggregation}")
            .replace("implication: Minimum", f"implication: {implication}"))
    rb = read_fll(text, "ramp.fll").rulebase
    grid = np.linspace(0, 1, 41)
    x = np.array([(a, b) for a in grid for b in grid])
    np.testing.assert_allclose(evaluate_sampled(rb, x, resolution), fuzzylite_outputs(text, x),
                               rtol=0, atol=1e-12)
