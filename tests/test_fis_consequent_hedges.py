"""Hedges on FIS consequents (`2.2` on an output: issue 14, sugeno_tip_calculator.fis).

The model keeps them as CondOp.CONCLUDED steps.  Exact semantics: the Octave toolkit's
(eval_rules_sugeno.m: height = strength^(1/p) for that output alone); `--semantics fuzzylite`
and pyfuzzylite: the hedge acts on the activation and carries on to the later conclusions of
the row (fuzzylite's Consequent::modify; its `extremely` is the S-curve).  Known answers by
hand, then both tools run live on the same file (skipped with the reason when missing).
"""
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.backends.c.header import check_supported
from fuzzyc.conformance import oracles
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fis, write_fcl, write_fis, write_fll, write_fz
from fuzzyc.language.parser import parse
from fuzzyc.formats.tool_semantics import evaluate_as, exact_equivalent
from fuzzyc.verifier.proof import beyond_proofs

# x in [0, 1]: low = 1 - x, high = x.  y, z: zero = 0, ten = 10.  Sum aggregation: the
# Octave toolkit's merging of equal Sugeno values is then the plain weighted average.
OUTPUT = "[Output{n}]\nName='{name}'\nRange=[0 10]\nNumMFs=2\n" \
         "MF1='zero':'constant',[0]\nMF2='ten':'constant',[10]\n\n"
HEDGED_FIS = """[System]
Name='hedged'
Type='sugeno'
Version=2.0
NumInputs=1
NumOutputs=2
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='prod'
AggMethod='sum'
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 1]
NumMFs=2
MF1='low':'trimf',[-1 0 1]
MF2='high':'trimf',[0 1 2]

""" + OUTPUT.format(n=1, name="y") + OUTPUT.format(n=2, name="z") + """[Rules]
1, 2.2 2 (1) : 1
2, 1 1 (1) : 1
"""


def _model(rows: str = "1, 2.2 2 (1) : 1"):
    return read_fis(HEDGED_FIS.replace("1, 2.2 2 (1) : 1", rows), "hedged.fis")


def test_very_on_a_consequent_in_both_readings_by_hand():
    rb = _model().rulebase
    # x = 0.36: low = 0.64 (rule 1), high = 0.36 (rule 2, -> zero for both outputs).
    # Octave toolkit (exact): y's height 0.64^(1/2) = 0.8: y = 0.8*10 / (0.8 + 0.36) = 8/1.16;
    # z (no hedge of its own; y's is not carried): z = 0.64*10 / (0.64 + 0.36) = 6.4.
    expected = [8 / 1.16, 6.4]
    for semantics in ("exact", "octave", "matlab"):
        assert evaluate_as(rb, [[0.36]], semantics)[0] == pytest.approx(expected, abs=1e-12)
    # fuzzylite: very(0.64) = 0.4096, carried on to z: both 4.096 / (0.4096 + 0.36)
    for semantics in ("fuzzylite", "pyfuzzylite"):
        assert evaluate_as(rb, [[0.36]], semantics)[0] == pytest.approx([4.096 / 0.7696] * 2,
                                                                       abs=1e-12)


def test_extremely_on_a_consequent_in_both_readings_by_hand():
    rb = _model("1, 2.3 2 (1) : 1").rulebase
    # x = 0.488: low = 0.512.  Octave: y's height 0.512^(1/3) = 0.8: 8 / (0.8 + 0.488) = 8/1.288;
    # z = 5.12 / (0.512 + 0.488) = 5.12.
    assert evaluate(rb, [[0.488]])[0] == pytest.approx([8 / 1.288, 5.12], abs=1e-12)
    # fuzzylite's extremely (S-curve) of 0.512 > 1/2: 1 - 2 (1 - 0.512)^2 = 0.523712, for y and
    # (carried) z: 5.23712 / (0.523712 + 0.488) = 5.23712 / 1.011712
    assert evaluate_as(rb, [[0.488]], "fuzzylite")[0] == pytest.approx([5.23712 / 1.011712] * 2,
                                                                       abs=1e-12)


def test_very_very_on_an_input_is_the_fourth_power_in_both():
    rb = _model("1.4, 2 2 (1) : 1").rulebase
    # x = 0.5: (very very low) = 0.5^4 = 0.0625, high = 0.5: 0.625 / 0.5625 = 10/9 (each output)
    for semantics in ("exact", "fuzzylite"):
        assert evaluate_as(rb, [[0.5]], semantics)[0] == pytest.approx([10 / 9] * 2, abs=1e-12)


def test_the_rules_say_where_the_hedge_was_and_what_cannot_follow_refuses():
    model = _model()
    rb = model.rulebase
    assert "very on this conclusion" in rb.describe_rule(0)
    assert "very on an earlier conclusion" in rb.describe_rule(1)
    assert "nested condition" in beyond_proofs(rb)
    with pytest.raises(FuzzycError, match="nested condition"):
        check_supported(rb)
    for writer in (write_fll, write_fcl):
        with pytest.raises(FuzzycError, match="hedge on a consequent"):
            writer(model, [])
    # compile/verify --semantics fuzzylite get fuzzylite's reading as plain hedge steps
    same, why = exact_equivalent(rb, "fuzzylite")
    assert why is None
    assert evaluate(same, [[0.36]])[0] == pytest.approx([4.096 / 0.7696] * 2, abs=1e-12)


def test_fz_says_the_row_as_concluded_and_carried_steps_and_reads_it_back():
    # the row `1, 2.2 2` becomes y's rule (its own hedge) and z's (y's hedge before it)
    text = write_fz(_model())
    assert "  rule if concluded very (x is low) then y is ten\n" in text
    assert "  rule if carried very (x is low) then z is ten\n" in text
    back = parse(text, "hedged.fz").rulebase
    # x = 0.36, as by hand above: 8/1.16 and 6.4 (exact), 4.096/0.7696 twice (fuzzylite)
    assert evaluate(back, [[0.36]])[0] == pytest.approx([8 / 1.16, 6.4], abs=1e-12)
    assert evaluate_as(back, [[0.36]], "fuzzylite")[0] == pytest.approx([4.096 / 0.7696] * 2,
                                                                        abs=1e-12)
    # written by hand: `concluded (...)` without a hedge is the identity under exact semantics
    # (p = 1), `not concluded very (...)` the negated Sugeno consequent's 1 - s^(1/2)
    hand = text.replace("concluded very (x is low) then y", "not concluded very (x is low) "
                        "then y").replace("carried very (x is low)", "concluded (x is low)")
    # x = 0.36: y's height 1 - 0.8 = 0.2: y = 0.2*10 / (0.2 + 0.36) = 2/0.56; z = 6.4
    assert evaluate(parse(hand, "hand.fz").rulebase, [[0.36]])[0] == \
        pytest.approx([2 / 0.56, 6.4], abs=1e-12)


def test_the_fis_writer_writes_the_row_back():
    # rule 2 gets `.3` on its input and z; rule 3 `.4` (very very) and `-` (not) on its input
    model = _model("1, 2.2 2 (1) : 1\n2.3, 1 1.3 (1) : 1\n-1.4, 2 0 (0.5) : 2")
    warnings: list[str] = []
    text = write_fis(model, warnings)
    # a row whose first conclusion is plain comes back as two rows (the same in both readings)
    assert text.split("[Rules]\n")[1].splitlines() == [
        "1, 2.2 2 (1) : 1", "2.3, 1 0 (1) : 1", "2.3, 0 1.3 (1) : 1", "-1.4, 2 0 (0.5) : 1",
        "2, 1 1 (1) : 1"]
    assert any("fuzzylite as its S-curve" in w for w in warnings)
    back = read_fis(text, "back.fis").rulebase
    x = np.linspace(0.0, 1.0, 11)[:, None]
    for semantics in ("exact", "fuzzylite"):
        assert np.array_equal(evaluate_as(back, x, semantics),
                              evaluate_as(model.rulebase, x, semantics))


def test_a_weight_on_a_hedged_row_weighs_the_strength_first():
    """Refused until issue 28's Octave campaign: both tools hedge the weighted strength (the
    toolkit's eval_firing_strength.m weighs, eval_rules_sugeno.m then takes ^(1/p))."""
    rb = _model("1, 2.2 2 (0.5) : 1").rulebase
    # x = 0.36: rule 1's strength 0.5 * 0.64 = 0.32; y's height 0.32^(1/2) = 0.5656854:
    # y = 5.656854 / (0.5656854 + 0.36) = 6.1112; z (no hedge of its own) 3.2 / 0.68 = 4.70588.
    y = evaluate(rb, np.array([[0.36]]))[0]
    assert y.tolist() == pytest.approx([10 * 0.32 ** 0.5 / (0.32 ** 0.5 + 0.36), 3.2 / 0.68])


X = np.linspace(0.0, 1.0, 11)[:, None]


def _written(tmp_path: Path):
    """The file with `.3` on rule 2's input and z (so both readings differ from plain rules)."""
    path = tmp_path / "hedged.fis"
    path.write_text(HEDGED_FIS.replace("2, 1 1", "2.3, 1 1.3"))
    return path, read_fis(path.read_text(), str(path)).rulebase


def test_octave_evalfis_agrees(tmp_path: Path):
    if not oracles.have_octave():
        pytest.skip("octave with fuzzy-logic-toolkit not installed")
    path, rb = _written(tmp_path)
    assert np.max(np.abs(oracles.octave_outputs(path, X) - evaluate(rb, X))) < 1e-12


def test_fuzzylite_cli_agrees(tmp_path: Path):
    if not oracles.have_fuzzylite():
        pytest.skip("fuzzylite not installed")
    path, rb = _written(tmp_path)
    names, got = oracles.fuzzylite_outputs(path, X)
    assert names == ["x", "y", "z"]
    ours = evaluate_as(rb, X, "fuzzylite")
    assert np.max(np.abs(got[:, 1:] - ours)) < 1e-9
    assert np.max(np.abs(got[:, 1:] - evaluate(rb, X))) > 0.1    # the readings differ here
