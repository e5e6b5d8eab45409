"""Under --semantics fuzzylite|pyfuzzylite the file's own settings apply (issue 28, causes 1-3
of the differential fuzzer; tool_semantics.FileSettings): an input's lock-range clamps it, a
numeric default replaces NaN (a `nan` default does not), the FLL resolution is the file's.
Hand-computed; the kept cases under tests/differential/cases/ replay the tools' own numbers."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fuzzyc.formats import load_any
from fuzzyc.formats.tool_semantics import Chain, file_settings

SUGENO = """Engine: settings
InputVariable: x
  enabled: true
  range: 0 10
  lock-range: {lock}
  term: mid Triangle 5 10 15
  term: lowish Ramp 20 0
OutputVariable: y
  enabled: true
  range: 0 10
  lock-range: false
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: {default}
  lock-previous: false
  term: a Constant 2
  term: b Constant 8
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: none
  activation: General
  rule: if x is mid then y is a
  rule: if x is lowish then y is b
"""


def _chain(tmp_path, text: str, suffix: str = ".fll") -> Chain:
    path = tmp_path / f"model{suffix}"
    path.write_text(text)
    return Chain(load_any(path))


@pytest.mark.parametrize("semantics", ["fuzzylite", "pyfuzzylite"])
def test_lock_range_clamps_the_input(tmp_path, semantics):
    # x = 15 clamped to 10: mid(10) = 1, lowish(10) = 1 - 10/20 = 0.5,
    # y = (1 * 2 + 0.5 * 8) / 1.5 = 4; unclamped: mid(15) = 0, lowish(15) = 0.25 -> y = 8
    locked = _chain(tmp_path, SUGENO.format(lock="true", default="nan"))
    free = _chain(tmp_path, SUGENO.format(lock="false", default="nan"))
    assert locked.evaluate([[15.0]], semantics)[0, 0] == pytest.approx(4.0, abs=1e-12)
    assert free.evaluate([[15.0]], semantics)[0, 0] == pytest.approx(8.0, abs=1e-12)


def test_numeric_default_where_nothing_fires(tmp_path):
    # x = 20 is outside both terms' supports (lowish is 0 from 20 on, mid from 15 on):
    # no rule fires; the tools give the default 7, or NaN for `default: nan`
    numeric = _chain(tmp_path, SUGENO.format(lock="false", default="7"))
    nan = _chain(tmp_path, SUGENO.format(lock="false", default="nan"))
    for semantics in ("fuzzylite", "pyfuzzylite"):
        assert numeric.evaluate([[20.0]], semantics)[0, 0] == 7.0
        assert math.isnan(nan.evaluate([[20.0]], semantics)[0, 0])


MAMDANI = """Engine: resolution
InputVariable: x
  enabled: true
  range: 0 1
  lock-range: false
  term: all Rectangle -1 2
OutputVariable: y
  enabled: true
  range: 0 3
  lock-range: false
  aggregation: Maximum
  defuzzifier: Centroid {points}
  default: nan
  lock-previous: false
  term: down Triangle 0 0 3
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  activation: General
  rule: if x is all then y is down
"""


@pytest.mark.parametrize("semantics", ["fuzzylite", "pyfuzzylite"])
def test_the_files_resolution(tmp_path, semantics):
    # Centroid 3 on [0, 3]: midpoints 0.5, 1.5, 2.5 where down = (3 - u)/3 = 5/6, 1/2, 1/6:
    # (0.5 * 5/6 + 1.5 * 1/2 + 2.5 * 1/6) / (5/6 + 1/2 + 1/6) = (19/12) / (3/2) = 19/18
    chain = _chain(tmp_path, MAMDANI.format(points=3))
    assert chain.evaluate([[0.5]], semantics)[0, 0] == pytest.approx(19 / 18, abs=1e-12)
    # a resolution given by the caller wins over the file's (the conformance suites' way)
    again = chain.evaluate([[0.5]], semantics, {"y": 100})[0, 0]
    assert again == pytest.approx(1.0, abs=1e-3) and abs(again - 19 / 18) > 0.05


def test_fcl_settings(tmp_path):
    text = """FUNCTION_BLOCK f
VAR_INPUT x: REAL; END_VAR
VAR_OUTPUT y: REAL; z: REAL; END_VAR
FUZZIFY x
  RANGE := (0 .. 1);
  TERM all := Rectangle -1 2;
END_FUZZIFY
DEFUZZIFY y
  RANGE := (0 .. 3);
  TERM a := 2;
  METHOD : COGS;
  DEFAULT := nan;
END_DEFUZZIFY
DEFUZZIFY z
  RANGE := (0 .. 3);
  TERM b := 1;
  METHOD : COGS;
  DEFAULT := 1.5;
END_DEFUZZIFY
RULEBLOCK r
  RULE 1 : if x is all then y is a and z is b;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""
    path = tmp_path / "f.fcl"
    path.write_text(text)
    settings = file_settings(load_any(path))
    # (fuzzylite's `LOCK : RANGE` is refused by fuzzyc's FCL grammar so far: not tested here)
    assert settings.known and settings.nan_default == {"y"}
    assert np.allclose(Chain(load_any(path)).evaluate([[0.5]], "fuzzylite"), [[2.0, 1.0]])


TWO_RESOLUTIONS = """Engine: two
InputVariable: x
  enabled: true
  range: 0 1
  lock-range: false
  term: all Rectangle -1 2
OutputVariable: y
  enabled: true
  range: 0 4
  lock-range: false
  aggregation: Maximum
  defuzzifier: Centroid 2
  default: nan
  lock-previous: false
  term: up Ramp 0 4
OutputVariable: z
  enabled: true
  range: 0 4
  lock-range: false
  aggregation: Maximum
  defuzzifier: Centroid 4
  default: nan
  lock-previous: false
  term: up Ramp 0 4
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  activation: General
  rule: if x is all then y is up and z is up
"""


@pytest.mark.parametrize("semantics", ["fuzzylite", "pyfuzzylite"])
def test_each_output_samples_at_its_own_resolution(tmp_path, semantics):
    # up = u/4, activation 1.  y, Centroid 2: midpoints 1, 3 (mu 1/4, 3/4):
    # (1/4 + 9/4) / 1 = 2.5.  z, Centroid 4: midpoints 0.5 .. 3.5 (mu 1/8, 3/8, 5/8, 7/8):
    # (1/16 + 9/16 + 25/16 + 49/16) / 2 = 2.625 (was 2.5: the block's first output's 2)
    # (differential case pyfuzzylite-fll/the-file-s-defuzzifier-resolution)
    y = _chain(tmp_path, TWO_RESOLUTIONS).evaluate([[0.5]], semantics)[0]
    np.testing.assert_allclose(y, [2.5, 2.625], rtol=0, atol=1e-12)


LINEAR = """Engine: linear
InputVariable: x
  enabled: true
  range: 0 10
  lock-range: {lock}
  term: all Rectangle -100 100
OutputVariable: y
  enabled: true
  range: 0 10
  lock-range: false
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: false
  term: line Linear 2 1
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: none
  activation: General
  rule: if x is all then y is line
"""


@pytest.mark.parametrize("semantics", ["fuzzylite", "pyfuzzylite"])
def test_a_linear_term_reads_the_input_unclamped(tmp_path, semantics):
    # x = -5 outside [0, 10]: the tools' Linear reads the value as it is, 2 * -5 + 1 = -9
    # (differential cases */a-linear-term); lock-range clamps it to 0 first: 1; fuzzyc's
    # exact semantics clamp a Linear term's inputs to their range: 1
    free = _chain(tmp_path, LINEAR.format(lock="false"))
    locked = _chain(tmp_path, LINEAR.format(lock="true"))
    assert free.evaluate([[-5.0], [12.0]], semantics)[:, 0].tolist() == [-9.0, 25.0]
    assert locked.evaluate([[-5.0], [12.0]], semantics)[:, 0].tolist() == [1.0, 21.0]
    assert free.evaluate([[-5.0], [12.0]], "exact")[:, 0].tolist() == [1.0, 21.0]
