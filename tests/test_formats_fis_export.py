"""MATLAB .fis export: the text pinned line by line for a small rule base, what is refused and
what is warned about, the atomic write and `fuzzyc convert ... x.fis`.  Values are fuzzyc's
engine on the re-imported file (MATLAB samples Mamdani outputs on 101 points; we integrate)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any, read_fis, save, write_fis
from fuzzyc.semantics.model import Defuzzifier, TNorm
from fuzzyc.language.parser import parse

ROOT = Path(__file__).parent.parent
CORPUS = Path(__file__).parent / "format_corpus"

# 2 inputs, 1 output, 3 rules: one NOT (rule 1), one input left out (= 0, rule 2), an or-rule
# with a weight (rule 3); a shoulder, a gaussian and a bell to pin MATLAB's parameter orders.
SMALL_FZ = """controller small "pinned: shoulder, gaussmf, gbellmf, NOT, any, or, weight" {
  input x in [0, 10]
  input e in [-1, 1]
  terms x : low = lshoulder(2, 5), mid = tri(2, 5, 8), high = gauss(10, 2)
  terms e : neg = trap(-1, -1, -0.5, 0), pos = bell(1, 0.5, 2)
  var y in [0, 1] default 0.5
  terms y : small = tri(0, 0.25, 0.5), big = trap(0.5, 0.75, 0.9, 1)
  inference and = min, or = max, implication = min, aggregation = max, defuzzify = centroid
  rule if x is low and e is not neg then y is small
  rule if x is high then y is big
  rule if x is mid or e is pos then y is big with 0.5
  output y_out in [0, 1] = y
}
"""


def fis(text: str, warnings: list[str] | None = None) -> str:
    return write_fis(parse(text, "t.fz"), warnings)


def test_small_rule_base_is_written_as_the_hand_written_file():
    # tests/format_corpus/small_export.fis was written by hand from MATLAB's format:
    # lshoulder(2, 5) -> trapmf [-10 0 2 5] (flat over the range, its edge leaned out), gauss(mean 10, sigma 2)
    # -> gaussmf [sigma c] = [2 10], bell(centre 1, width 0.5, slope 2) -> gbellmf [a b c] =
    # [0.5 2 1]; rules: `1 -1` = low and not neg, `3 0` = high, e any; `: 2` = or.
    warnings: list[str] = []
    expected = (CORPUS / "small_export.fis").read_text().splitlines()
    got = fis(SMALL_FZ, warnings).splitlines()
    for number, (want, line) in enumerate(zip(expected, got), start=1):
        assert line == want, f"line {number}"
    assert len(got) == len(expected)
    assert warnings == [
        "MATLAB evaluates Mamdani outputs on 101 points of the range (centroid of the sampled "
        "aggregate); fuzzyc integrates exactly: MATLAB's numbers differ by that sampling error",
        # the shoulder's vertical edge leans out by the range's width: 0 - 10 = -10
        "`low` of `x` is written as trapmf [-10 0 2 5] (FIS has no infinite break points, the "
        "Octave toolkit no vertical edges): the same on [0, 10], not beyond it",
        # a vertical edge at the range's low end -1 leans out by the width 2: -1 - 2 = -3
        "`neg` of `e` is written as trapmf [-3 -1 -0.5 0] (FIS has no infinite break points, "
        "the Octave toolkit no vertical edges): the same on [-1, 1], not beyond it"]


def test_small_rule_base_read_back_gives_the_hand_computed_value():
    rb = load_any(CORPUS / "small_export.fis").rulebase
    # x = 5, e = 0: low 0, mid 1, high exp(-25/8) = 0.044, neg 0, pos 1/(1 + 2^4) = 1/17.
    # r1 = min(0, 1 - 0) = 0; r2 = 0.044 -> big; r3 = 0.5 * max(1, 1/17) = 0.5 -> big.
    # big clipped at 0.5: rises 0.5 -> 0.625, flat to 0.95, falls to 1.  Pieces (area, centroid):
    # (0.5*0.125*0.5, 0.5 + 0.125*2/3), (0.325*0.5, 0.7875), (0.5*0.05*0.5, 0.95 + 0.05/3).
    pieces = [(0.03125, 0.5 + 0.125 * 2 / 3), (0.1625, 0.7875), (0.0125, 0.95 + 0.05 / 3)]
    centroid = sum(a * c for a, c in pieces) / sum(a for a, _ in pieces)   # 0.76742...
    assert evaluate(rb, np.array([[5.0, 0.0]]))[0, 0] == pytest.approx(centroid, abs=1e-12)
    # The default is MATLAB's: the middle of the range when no rule fires.
    assert rb.outputs[0].default == 0.5
    # Inside the range the re-imported file is the .fz rule base.
    model = parse(SMALL_FZ, "t.fz")
    x = np.column_stack([np.linspace(0, 10, 41).repeat(21), np.tile(np.linspace(-1, 1, 21), 41)])
    np.testing.assert_allclose(evaluate(rb, x), evaluate(model.rulebase, x), rtol=0, atol=1e-12)


def test_fis_import_defaults_to_the_middle_of_the_range():
    # MATLAB's evalfis: "No rules fired for Output 1. Defuzzified output value set to its mean
    # range value"; tipper's tip is in [0, 30] -> 15.
    rb = load_any(CORPUS / "tipper.fis").rulebase
    assert rb.outputs[0].default == 15


COA = """controller coa {{
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  var y in [0, 10] default {default}
  terms y : a = tri(0, 2, 4), b = tri(6, 8, 10)
  inference and = min, aggregation = {aggregation}, defuzzify = center_of_area
  rule if x is lo then y is a
  rule if x is hi then y is b
  {extra}
  output y_out in [0, 10] = y
}}
"""


def test_center_of_area_is_wtaver_when_no_two_rules_share_a_term():
    model = parse(COA.format(default=5, aggregation="max", extra=""), "t.fz")
    warnings: list[str] = []
    text = write_fis(model, warnings)
    assert "Type='sugeno'" in text and "DefuzzMethod='wtaver'" in text
    assert "MF1='a':'constant',[2]" in text and "MF2='b':'constant',[8]" in text
    assert any("no two rules conclude the same term" in w for w in warnings)
    assert any("singletons at their peaks (2, 8)" in w for w in warnings)
    back = read_fis(text, "x.fis").rulebase
    assert back.inference.defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
    # x = 0.25: lo 0.75, hi 0.25 -> (0.75 * 2 + 0.25 * 8) / 1 = 3.5, both ways
    x = np.array([[0.25]])
    assert evaluate(back, x)[0, 0] == pytest.approx(3.5, abs=1e-12)
    assert evaluate(model.rulebase, x)[0, 0] == pytest.approx(3.5, abs=1e-12)


def test_center_of_area_with_sum_aggregation_is_wtaver_even_when_terms_are_shared():
    model = parse(COA.format(default=5, aggregation="sum",
                             extra="rule if x is hi then y is a with 0.5"), "t.fz")
    warnings: list[str] = []
    back = read_fis(write_fis(model, warnings), "x.fis").rulebase
    assert any("sum aggregation is written as Sugeno wtaver" in w for w in warnings)
    # x = 0.25: a 0.75 + 0.5 * 0.25 = 0.875, b 0.25 -> (0.875 * 2 + 0.25 * 8) / 1.125 = 10/3
    x = np.array([[0.25]])
    assert evaluate(back, x)[0, 0] == pytest.approx(3.75 / 1.125, abs=1e-12)
    assert evaluate(model.rulebase, x)[0, 0] == pytest.approx(3.75 / 1.125, abs=1e-12)


def test_refusals_name_why():
    shared = COA.format(default=5, aggregation="max", extra="rule if x is hi then y is a with 0.5")
    with pytest.raises(FuzzycError, match=r"strongest of the rules that conclude the same term "
                                          r"\(`a` of `y` \(2 rules\)\)"):
        fis(shared)
    hedged = COA.format(default=5, aggregation="sum", extra="rule if x is sharply hi then y is a")
    with pytest.raises(FuzzycError, match="hedge `sharply` has no equivalent in FIS"):
        fis(hedged)
    spike = SMALL_FZ.replace("gauss(10, 2)", "spike(10, 2)")
    with pytest.raises(FuzzycError, match=r"term `high` of `x` \(spike\) has no FIS membership"):
        fis(spike)
    einstein = SMALL_FZ.replace("and = min", "and = einstein_product")
    with pytest.raises(FuzzycError, match="AndMethod einstein_product \\(used by rule 1\\)"):
        fis(einstein)
    mixed = SMALL_FZ.replace("small = tri(0, 0.25, 0.5)", "small = singleton(0.25)")
    with pytest.raises(FuzzycError, match="singleton term `small` of `y` under centroid"):
        fis(mixed)


def test_warnings_for_what_is_replaced():
    # An or-operator MATLAB lacks, used by no or-rule with two clauses: written as max.
    text_in = SMALL_FZ.replace("or = max", "or = einstein_sum").replace(
        "rule if x is mid or e is pos", "rule if x is mid")
    warnings: list[str] = []
    text = fis(text_in, warnings)
    assert "OrMethod='max'" in text
    assert "OrMethod: the model's einstein_sum is used by no rule with two clauses; written as " \
           "max" in warnings
    # A default other than the middle of the range is said to be lost.
    warnings = []
    fis(COA.format(default=0, aggregation="max", extra=""), warnings)
    assert "`y`'s default 0 (when no rule fires): FIS has none; MATLAB gives the middle of the " \
           "range, 5" in warnings


def test_save_fis_is_atomic_and_convert_writes_it(tmp_path, capsys):
    model = load_any(CORPUS / "sugeno.fis")
    assert save(model, tmp_path / "x.fis") == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.fis"]   # no temporary left over
    assert (tmp_path / "x.fis").read_text() == write_fis(model)

    out = tmp_path / "milling.fis"
    assert main(["convert", str(ROOT / "rulebases/milling_neurofuzzy.fz"), str(out)]) == 0
    err = capsys.readouterr().err
    assert "warning: the input signal chain (e, cf)" in err
    assert "warning: the learnable flags of `du`'s terms" in err
    back = load_any(out).rulebase
    assert back.n_rules == load_any(ROOT / "rulebases/milling_neurofuzzy.fz").rulebase.n_rules
    assert back.inference.and_ == TNorm.PRODUCT
    assert back.inference.defuzzifier == Defuzzifier.WEIGHTED_SUM

    refused = tmp_path / "three_region.fis"
    assert main(["convert", str(ROOT / "rulebases/wedm_three_region.fz"), str(refused)]) == 2
    assert "FIS cannot say it" in capsys.readouterr().err and not refused.exists()
