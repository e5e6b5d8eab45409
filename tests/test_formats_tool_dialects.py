"""What the other tools' files say that fuzzyc reads since issue 14, each with hand-computed
values: fuzzylite's further term shapes, fuzzylite's FCL dialect, the Octave toolkit's FIS (rule
hedges, comment lines, norm names), and the tools' arithmetic (`tool_semantics`)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fuzzyc.backends.c.header import check_supported
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fis, read_fll
from fuzzyc.formats.fcl import write_fcl
from fuzzyc.formats.fll import write_fll
from fuzzyc.formats.fuzzylite_compat import Sampling, evaluate_sampled
from fuzzyc.formats.fz import write_fz
from fuzzyc.formats.tool_semantics import Chain, evaluate_as
from fuzzyc.engine.membership import term_values
from fuzzyc.semantics.model import Defuzzifier, Hedge, TermKind, TNorm
from fuzzyc.language.parser import parse

S1 = 1.0 / (1.0 + math.exp(-1.0))     # the logistic at 1: 0.7310585786...


def mu(kind: TermKind, params, x) -> np.ndarray:
    p = np.array([tuple(params) + (0.0,) * (4 - len(params))])
    return term_values(np.array([int(kind)]), p, np.asarray(x, dtype=float))[:, 0]


@pytest.mark.parametrize("kind, params, x, expected", [
    # |sig(0, 1)(1) - sig(2, 1)(1)| = |1/(1+e^-1) - 1/(1+e^1)| = S1 - (1 - S1) = 2 S1 - 1
    (TermKind.SIGMOID_DIFFERENCE, (0, 1, 1, 2), [1], [2 * S1 - 1]),
    # sig(0, 1)(1) * sig(2, -1)(1) = 1/(1+e^-1) * 1/(1+e^(1*(1-2))) = S1^2
    (TermKind.SIGMOID_PRODUCT, (0, 1, -1, 2), [1], [S1 * S1]),
    # x = 0 < 1: exp(-(0-1)^2 / (2 * 0.25)) = e^-2; x = 2 between the means: 1;
    # x = 5 > 3: exp(-(5-3)^2 / 2) = e^-2
    (TermKind.GAUSSIAN_PRODUCT, (1, 0.5, 3, 1), [0, 2, 5], [math.exp(-2), 1, math.exp(-2)]),
    # binary(0.5, 1): 1 from 0.5 on; binary(0.5, -1): 1 up to 0.5
    (TermKind.BINARY, (0.5, 1), [0.4, 0.5, 0.6], [0, 1, 1]),
    (TermKind.BINARY, (0.5, -1), [0.4, 0.5, 0.6], [1, 1, 0]),
    # semi_ellipse(0, 2): centre 1, radius 1: sqrt(1 - 0.5^2) = sqrt(0.75) at 0.5 and 1.5
    (TermKind.SEMI_ELLIPSE, (0, 2), [-1, 0.5, 1, 1.5, 3], [0, math.sqrt(0.75), 1,
                                                           math.sqrt(0.75), 0]),
    # arc(0, 2): circle of radius 2 about (2, 0): sqrt(4 - (1-2)^2) / 2 = sqrt(3)/2 at 1, 0 at 0
    (TermKind.ARC, (0, 2), [-1, 0, 1, 2, 3], [0, 0, math.sqrt(3) / 2, 1, 1]),
    # arc(2, 0): the mirror, 1 below 0
    (TermKind.ARC, (2, 0), [-1, 0, 1, 2, 3], [1, 1, math.sqrt(3) / 2, 0, 0]),
])
def test_fuzzylite_shapes_by_hand(kind, params, x, expected):
    np.testing.assert_allclose(mu(kind, params, x), expected, rtol=0, atol=1e-15)


def test_nan_input_gives_zero_for_the_fuzzylite_shapes():
    for kind, params in [(TermKind.SIGMOID_DIFFERENCE, (0, 1, 1, 2)),
                         (TermKind.SIGMOID_PRODUCT, (0, 1, -1, 2)),
                         (TermKind.GAUSSIAN_PRODUCT, (1, 0.5, 3, 1)), (TermKind.BINARY, (0.5, 1)),
                         (TermKind.SEMI_ELLIPSE, (0, 2)), (TermKind.ARC, (0, 2))]:
        assert mu(kind, params, [np.nan])[0] == 0.0


SHAPES_FLL = """Engine: shapes
InputVariable: x
  range: 0 2
  term: sd SigmoidDifference 0 1 1 2
  term: sp SigmoidProduct 0 1 -1 2
  term: gp GaussianProduct 1 0.5 3 1
  term: bi Binary 0.5 inf
  term: se SemiEllipse 0 2
  term: ar Arc 0 2
OutputVariable: y
  range: 0 1
  default: nan
  defuzzifier: WeightedAverage
  term: one Constant 1
  term: zero Constant 0
RuleBlock: r
  implication: Minimum
  rule: if x is ar then y is one
  rule: if x is se then y is zero
"""


def test_fll_shapes_import_and_carry_through_fz_and_fll():
    model = read_fll(SHAPES_FLL, "shapes.fll")
    x = model.rulebase.inputs[0]
    assert [TermKind(int(k)).name for k in x.kinds] == [
        "SIGMOID_DIFFERENCE", "SIGMOID_PRODUCT", "GAUSSIAN_PRODUCT", "BINARY", "SEMI_ELLIPSE",
        "ARC"]
    assert x.params[3, :2].tolist() == [0.5, 1.5]   # Binary's `inf` direction: start + 1
    # at x = 1: arc 0 2 gives sqrt(3)/2, semi ellipse 0 2 gives 1:
    # (sqrt(3)/2 * 1 + 1 * 0) / (sqrt(3)/2 + 1) = 0.4641016151...
    expected = (math.sqrt(3) / 2) / (math.sqrt(3) / 2 + 1)
    assert evaluate(model.rulebase, [[1.0]])[0, 0] == pytest.approx(expected, abs=1e-15)
    for back in (parse(write_fz(model), "back.fz"), read_fll(write_fll(model), "back.fll")):
        np.testing.assert_array_equal(back.rulebase.inputs[0].params, x.params)
        assert evaluate(back.rulebase, [[1.0]])[0, 0] == pytest.approx(expected, abs=1e-15)
    with pytest.raises(FuzzycError) as err:     # the C back ends say what they do not emit
        check_supported(model.rulebase)
    assert "sigmoid_difference" in str(err.value)


# fuzzylite 6 writes FCL so: a BOM, `//` and `/* */` comments, shapes by name, `nan` defaults,
# rules without `;`, COGS without ACCU (its WeightedAverage).
FUZZYLITE_FCL = """\ufeff//Code automatically generated with fuzzylite 6.0.
/* a block
   comment */
FUNCTION_BLOCK SimpleDimmer
VAR_INPUT
  Ambient: REAL;
END_VAR
VAR_OUTPUT
  Power: REAL;
END_VAR
FUZZIFY Ambient
  RANGE := (0.000 .. 1.000);
  TERM DARK := Triangle 0.000 0.250 0.500;
  TERM MEDIUM := Triangle 0.250 0.500 0.750;
  TERM BRIGHT := Ramp 0.500 0.750;
END_FUZZIFY
DEFUZZIFY Power
  RANGE := (0.000 .. 1.000);
  TERM LOW := 0.250;
  TERM MEDIUM := 0.500;
  TERM HIGH := Linear 0.000 0.750;
  METHOD : COGS;
  DEFAULT := nan;
END_DEFUZZIFY
RULEBLOCK
  AND : EPROD;
  ACT : MIN;
  RULE 1 : if Ambient is DARK then Power is HIGH
  RULE 2 : if Ambient is very MEDIUM then Power is MEDIUM
  RULE 3 : if Ambient is BRIGHT then Power is LOW
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_fuzzylite_fcl_dialect_by_hand():
    model = read_fcl(FUZZYLITE_FCL, "dimmer.fcl")
    rb = model.rulebase
    assert rb.inference.defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
    assert rb.inference.and_ == TNorm.EINSTEIN_PRODUCT
    assert rb.hedges[1, 0] == Hedge.VERY
    assert any("default nan" in note for note in model.notes)
    # Ambient = 0.3: DARK (0.5-0.3)/0.25 = 0.8, MEDIUM (0.3-0.25)/0.25 = 0.2, very: 0.04;
    # HIGH = Linear 0 * Ambient + 0.75 = 0.75: (0.8*0.75 + 0.04*0.5) / (0.8 + 0.04) = 0.62/0.84
    assert evaluate(rb, [[0.3]])[0, 0] == pytest.approx(0.62 / 0.84, abs=1e-15)


def test_fcl_tsukamoto_is_refused_with_its_place_and_nc_is_lock_previous():
    tsukamoto = FUZZYLITE_FCL.replace("TERM LOW := 0.250;", "TERM LOW := Ramp 0.6 0.4;")
    with pytest.raises(FuzzycError) as err:
        read_fcl(tsukamoto, "t.fcl")
    assert "t.fcl:19:8" in str(err.value) and "Tsukamoto" in str(err.value)
    # `nan | NC`: fuzzylite's lock-previous (the output holds its value; fuzzyc.engine.held_outputs)
    locked = read_fcl(FUZZYLITE_FCL.replace("DEFAULT := nan;", "DEFAULT := nan | NC;"), "l.fcl")
    assert [v.lock_previous for v in locked.rulebase.outputs] == [True]
    assert not any(v.lock_previous for v in read_fcl(FUZZYLITE_FCL, "f.fcl").rulebase.outputs)


def test_fcl_export_is_the_dialect_fuzzylite_reads():
    plain = FUZZYLITE_FCL.replace("is very MEDIUM", "is MEDIUM").replace("Linear 0.000 0.750",
                                                                           "0.750")
    text = write_fcl(read_fcl(plain, "dimmer.fcl"), [])
    assert "(*" not in text and "// " in text
    assert "RULE 1 : if Ambient is DARK then Power is HIGH;" in text
    assert "ACCU" not in text          # COGS without ACCU: the weighted average, read back so
    assert read_fcl(text, "back.fcl").rulebase.inference.defuzzifier == \
        Defuzzifier.WEIGHTED_AVERAGE


OCTAVE_FIS = """## Octave's header comment
# fuzzylite's
[System]
Name='hedged'
Type='sugeno'
NumInputs=1
NumOutputs=1
NumRules=3
AndMethod='einstein_product'
OrMethod='algebraic_sum'
ImpMethod='prod'
AggMethod='max'
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 1]
NumMFs=2
MF1='low':'trimf',[-1 0 1]
MF2='high':'rampmf',[0 1]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='a':'constant',[0]
MF2='b':'constant',[10]

[Rules]
1.200 , 1.000 (1.000) : 1
2.05, 2 (1) : 1
1, 2 (0.4) : 1
"""


def test_octave_fis_hedges_comments_and_norms_by_hand():
    rb = read_fis(OCTAVE_FIS, "hedged.fis").rulebase
    assert rb.hedges[:, 0].tolist() == [Hedge.VERY, Hedge.SOMEWHAT, Hedge.NONE]
    assert rb.inference.and_ == TNorm.EINSTEIN_PRODUCT
    # x = 0.25: low = 0.75, high (rampmf 0 1) = 0.25.  Rules: very low -> a: 0.75^2 = 0.5625;
    # somewhat high -> b: sqrt(0.25) = 0.5; low -> b with weight 0.4: 0.3.
    # MATLAB (and fuzzyc): the sum over rules, (0.5625*0 + 0.5*10 + 0.3*10) / 1.3625
    assert evaluate(rb, [[0.25]])[0, 0] == pytest.approx(8 / 1.3625, abs=1e-14)
    # the Octave toolkit merges rules of equal value with AggMethod max: b gets max(0.5, 0.3):
    # (0.5625*0 + 0.5*10) / (0.5625 + 0.5) = 5 / 1.0625
    assert evaluate_as(rb, [[0.25]], "octave")[0, 0] == pytest.approx(5 / 1.0625, abs=1e-14)
    assert evaluate_as(rb, [[0.25]], "matlab")[0, 0] == pytest.approx(8 / 1.3625, abs=1e-14)


def test_fis_refuses_hedges_it_cannot_carry_with_the_row():
    with pytest.raises(FuzzycError) as err:
        read_fis(OCTAVE_FIS.replace("2.05, 2 (1) : 1", "2.07, 2 (1) : 1"), "h.fis")
    assert "h.fis:31:1" in str(err.value) and "exponent of 0.7" in str(err.value)
    # a weight on a hedged consequent is read since issue 28's Octave campaign (the strength
    # weighed before the hedge, tests/test_fis_consequent_hedges.py); a hedge without a
    # fraction of the toolkit's is still refused above
    read_fis(OCTAVE_FIS.replace("2.05, 2 (1) : 1", "2, 2.2 (0.5) : 1"), "c.fis")


RAMP_FLL = """Engine: ramp
InputVariable: x
  range: 0 1
  term: on Ramp 0 1
OutputVariable: y
  range: 0 1
  default: nan
  aggregation: Maximum
  defuzzifier: Centroid 3
  term: up Triangle 0 1 1
RuleBlock: r
  implication: Minimum
  rule: if x is on then y is up
"""


def test_sampled_centroids_by_hand():
    rb = read_fll(RAMP_FLL, "ramp.fll").rulebase
    # x = 1 fires `up` fully: M(u) = u on [0, 1].  Exact: int u^2 / int u = (1/3)/(1/2) = 2/3.
    assert evaluate(rb, [[1.0]])[0, 0] == pytest.approx(2 / 3, abs=1e-15)
    # fuzzylite, 3 midpoints 1/6, 1/2, 5/6: sum u^2 / sum u = (35/36) / (3/2) = 35/54
    assert evaluate_as(rb, [[1.0]], "fuzzylite", 3)[0, 0] == pytest.approx(35 / 54, abs=1e-15)
    # Octave, trapz on 0, 1/2, 1 (weights 1/4, 1/2, 1/4): (0 + 1/8 + 1/4) / (0 + 1/4 + 1/4)
    # = 0.75
    got = evaluate_sampled(rb, [[1.0]], 3, Sampling.TRAPEZOID)[0, 0]
    assert got == pytest.approx(0.75, abs=1e-15)
    # x = 0: no rule fires: fuzzylite's default nan, fuzzyc's number (0, said in a note)
    assert math.isnan(evaluate_as(rb, [[0.0]], "fuzzylite")[0, 0])
    assert evaluate(rb, [[0.0]])[0, 0] == 0.0


def test_empty_sugeno_range_and_terms_less_variables_import():
    text = ("Engine: e\nInputVariable: a\n  range: 0 1\nInputVariable: b\n  range: 0 1\n"
            "  term: t Triangle 0 0.5 1\nOutputVariable: y\n  range: 0 0\n"
            "  defuzzifier: WeightedAverage\n  term: l Linear 2 3 1\n"
            "RuleBlock: r\n  rule: if b is t then y is l\n")
    model = read_fll(text, "e.fll")
    # a = 0.5, b = 0.5: t = 1, y = 2*0.5 + 3*0.5 + 1 = 3.5 (a has no terms yet is read)
    assert evaluate(model.rulebase, [[0.5, 0.5]])[0, 0] == pytest.approx(3.5, abs=1e-15)
    assert any("no terms" in note for note in model.notes)
    assert any("empty range" in note for note in model.notes)


@pytest.mark.parametrize("aggregation", ["max", "sum", "probor"])
def test_an_output_without_terms_gives_its_no_rule_default(aggregation):
    # found by `make fuzz`: a FIS output with NumMFs=0 under max aggregation raised ValueError.
    # No rule can conclude it, so every sample takes MATLAB's no-rule value, the middle of
    # the range: (0 + 30) / 2 = 15.
    text = ("[System]\nName='t'\nType='mamdani'\nNumInputs=1\nNumOutputs=1\nNumRules=0\n"
            f"AndMethod='min'\nOrMethod='max'\nImpMethod='min'\nAggMethod='{aggregation}'\n"
            "DefuzzMethod='centroid'\n\n[Input1]\nName='a'\nRange=[0 10]\nNumMFs=1\n"
            "MF1='lo':'trimf',[0 0 10]\n\n[Output1]\nName='y'\nRange=[0 30]\nNumMFs=0\n\n"
            "[Rules]\n")
    got = evaluate(read_fis(text, "t.fis").rulebase, [[0.0], [5.0], [10.0]])
    assert got[:, 0].tolist() == [15.0, 15.0, 15.0]
    # the C back end has no empty arrays: it refuses by name instead of writing invalid C
    with pytest.raises(FuzzycError, match="at least one rule"):
        check_supported(read_fis(text, "t.fis").rulebase)


def test_fz_written_from_an_import_reads_back_terms_less_inputs_and_peaks_past_the_range():
    # MATLAB's slcp1 (inputs read only by linear consequents) and invkine1 (a term peaking
    # past its input's range): convert used to write a .fz that eval refused, then refused
    text = ("Engine: e\nInputVariable: a\n  range: 0 1\nInputVariable: b\n  range: 0 1\n"
            "  term: t Triangle 0 0.5 1\n  term: past Triangle 1 1.5 2\n"
            "OutputVariable: y\n  range: 0 10\n  defuzzifier: WeightedAverage\n"
            "  term: l Linear 2 3 1\nRuleBlock: r\n  rule: if b is past then y is l\n")
    # the .fz keeps b's range [0, 1] (the Linear term reads b clamped to it) and the term
    # peaking at 1.5, which reads back with a located warning, not an error
    fz = write_fz(read_fll(text, "e.fll"))
    assert "  input b in [0, 1]\n" in fz and "past = tri(1, 1.5, 2)" in fz
    back = parse(fz, "e.fz")
    [warning] = back.warnings
    assert warning.format().startswith("e.fz:6:33: warning: ") and "term `past` of `b` peaks at 1.5, " \
        "outside the range [0, 1]" in warning.message
    # a = 0.5, b = 1.2: past = (1.2 - 1)/0.5 = 0.4, one rule (the weight cancels); the Linear
    # term reads b clamped to 1: y = 2*0.5 + 3*1 + 1 = 5, before and after the round trip
    for model in (read_fll(text, "e.fll"), back):
        assert evaluate(model.rulebase, [[0.5, 1.2]])[0, 0] == pytest.approx(5.0, abs=1e-15)
    model = read_fll(text.replace("  term: past Triangle 1 1.5 2\n", "")
                     .replace("b is past", "b is t"), "e.fll")
    fz = write_fz(model)
    assert "  terms a :\n" in fz
    back = parse(fz, "e.fz").rulebase
    assert [v.n_terms for v in back.inputs] == [0, 1]
    # a = 0.5, b = 0.25: t = 0.5, y = 2*0.5 + 3*0.25 + 1 = 2.75 (one rule: the weight cancels)
    assert evaluate(back, [[0.5, 0.25]])[0, 0] == pytest.approx(2.75, abs=1e-15)


TSUKAMOTO_FLL = """Engine: tsukamoto
InputVariable: x
  range: 0 1
  term: on Ramp 0 1
  term: off Ramp 1 0
OutputVariable: y
  range: 0 1
  default: nan
  aggregation: none
  defuzzifier: WeightedAverage Tsukamoto
  term: up Ramp 0.2 0.6
  term: lo Sigmoid 0.5 -10
RuleBlock: r
  implication: none
  activation: General
  rule: if x is on then y is up
  rule: if x is off then y is lo
"""


def test_tsukamoto_by_hand_in_each_tool():
    model = read_fll(TSUKAMOTO_FLL, "t.fll")
    rb = model.rulebase
    assert rb.inference.defuzzifier == Defuzzifier.TSUKAMOTO
    # x = 0.75: on = 0.75, off = 0.25.  up^-1(0.75) = 0.2 + 0.4 * 0.75 = 0.5;
    # lo^-1(0.25): 1 / (1 + e^(10 (z - 0.5))) = 0.25 -> z = 0.5 + ln(3)/10;
    # y = (0.75 * 0.5 + 0.25 * (0.5 + ln(3)/10)) / 1 = 0.5 + 0.025 ln 3
    expected = 0.5 + 0.025 * math.log(3)
    for semantics in ("exact", "fuzzylite", "pyfuzzylite"):
        assert evaluate_as(rb, [[0.75]], semantics)[0, 0] == pytest.approx(expected, abs=1e-15)
    # x = 0: off = 1, where the sigmoid is 1 only at -infinity: fuzzyc clips to the range's
    # end (0), fuzzylite 6 takes the range's end too, pyfuzzylite 8 gives -inf
    assert evaluate(rb, [[0.0]])[0, 0] == 0.0
    assert evaluate_as(rb, [[0.0]], "fuzzylite")[0, 0] == 0.0
    assert evaluate_as(rb, [[0.0]], "pyfuzzylite")[0, 0] == -math.inf
    back = parse(write_fz(model), "t.fz").rulebase            # `defuzzify = tsukamoto`
    assert evaluate(back, [[0.75]])[0, 0] == pytest.approx(expected, abs=1e-15)
    assert "WeightedAverage Tsukamoto" in write_fll(model)
    with pytest.raises(FuzzycError) as err:
        check_supported(rb)
    assert "tsukamoto" in str(err.value)
    with pytest.raises(FuzzycError) as err:
        write_fcl(model, [])
    assert "Tsukamoto" in str(err.value)


def test_tsukamoto_refuses_a_term_with_no_inverse_at_its_place():
    text = TSUKAMOTO_FLL.replace("term: up Ramp 0.2 0.6", "term: up Triangle 0.2 0.4 0.6")
    with pytest.raises(FuzzycError) as err:
        read_fll(text, "t.fll")
    assert "t.fll:11:9" in str(err.value) and "monotonic" in str(err.value)
    fz = write_fz(read_fll(TSUKAMOTO_FLL, "t.fll")).replace("rshoulder(0.2, 0.6)",
                                                             "tri(0.2, 0.4, 0.6)")
    with pytest.raises(FuzzycError) as err:
        parse(fz, "t.fz")
    assert "tsukamoto needs monotonic output terms" in str(err.value)


EINSTEIN_FLL = """Engine: einstein
InputVariable: x
  range: 0 1
  term: on Ramp 0 1
OutputVariable: y
  range: 0 1
  default: nan
  aggregation: EinsteinSum
  defuzzifier: Centroid 1000
  term: up Triangle 0 1 1
RuleBlock: r
  implication: EinsteinProduct
  rule: if x is on then y is up
  rule: if x is on then y is up with 0.5
"""


def test_einstein_implication_and_aggregation_by_hand():
    rb = read_fll(EINSTEIN_FLL.replace("  rule: if x is on then y is up with 0.5\n", ""),
                  "e.fll").rulebase
    # x = 0.5: one rule, level 0.5; E(0.5, u) = 0.5u / (2 - (0.5 + u - 0.5u)) = u / (3 - u).
    # int_0^1 u/(3-u) = 3 ln 1.5 - 1; int_0^1 u^2/(3-u) = 9 ln 1.5 - 3.5 (u^2/(3-u) =
    # -u - 3 + 9/(3-u)): the centroid is their ratio, 0.68941...; the engine integrates on
    # its 2001-point grid (not closed form), so within 1e-6
    ln = math.log(1.5)
    assert evaluate(rb, [[0.5]])[0, 0] == pytest.approx((9 * ln - 3.5) / (3 * ln - 1), abs=1e-6)
    two = read_fll(EINSTEIN_FLL, "e.fll")
    # x = 1: levels 1 and 0.5: E(1, u) = u, E(0.5, u) = u/(3-u); folded with the Einstein sum
    # (a + b) / (1 + ab).  At u = 1: (1 + 0.5) / 1.5 = 1, at u = 0.5: (0.5 + 0.2) / 1.1
    y = evaluate(two.rulebase, [[1.0]])[0, 0]
    sampled = evaluate_as(two.rulebase, [[1.0]], "fuzzylite", 100000)[0, 0]
    assert y == pytest.approx(sampled, abs=1e-6)
    assert "aggregation = einstein_sum" in write_fz(two)
    assert "implication = einstein_product" in write_fz(two)
    back = parse(write_fz(two), "e.fz").rulebase
    assert evaluate(back, [[1.0]])[0, 0] == y
    with pytest.raises(FuzzycError) as err:
        check_supported(two.rulebase)
    assert "einstein_sum" in str(err.value)


def test_einstein_sum_grouping_by_hand():
    # WeightedAverage grouped by EinsteinSum is the center of area: x = 1 fires `up` at 1 and
    # at 0.5 -> (1 + 0.5) / (1 + 0.5) = 1; `zero` (value 0) at 0.5: y = 1*1 / (1 + 0.5) = 2/3
    text = EINSTEIN_FLL.replace("defuzzifier: Centroid 1000", "defuzzifier: WeightedAverage") \
        .replace("term: up Triangle 0 1 1", "term: up Constant 1\n  term: zero Constant 0") \
        .replace("then y is up with 0.5", "then y is zero with 0.5") + \
        "  rule: if x is on then y is up with 0.5\n"
    rb = read_fll(text, "g.fll").rulebase
    assert rb.inference.defuzzifier == Defuzzifier.CENTER_OF_AREA
    assert evaluate(rb, [[1.0]])[0, 0] == pytest.approx(2 / 3, abs=1e-15)


# Two plateaus of equal height: x = 0.25 gives mid = 0.5, and both rules clip their rectangle
# at 0.5: M = 0.5 on [0, 0.25] and on [0.75, 1].  fuzzylite 6's MeanOfMaximum keeps the first
# plateau: its 100 midpoints 0.005 .. 0.245 give (0.005 + 0.245) / 2 = 0.125; pyfuzzylite 8
# averages every maximal sample, symmetric about 0.5: 0.5; exact: the mean of the set where M
# is largest, [0, 0.25] and [0.75, 1], 0.5.
TWO_PLATEAUS_FLL = """Engine: plateaus
InputVariable: x
  range: 0 1
  term: mid Triangle 0 0.5 1
OutputVariable: y
  range: 0 1
  aggregation: Maximum
  defuzzifier: MeanOfMaximum 100
  default: nan
  term: a Rectangle 0 0.25
  term: b Rectangle 0.75 1
RuleBlock:
  implication: Minimum
  rule: if x is mid then y is a
  rule: if x is mid then y is b
"""


@pytest.mark.parametrize("semantics, expected", [("fuzzylite", 0.125), ("pyfuzzylite", 0.5),
                                                 ("exact", 0.5)])
def test_mean_of_maximum_over_two_plateaus(semantics, expected):
    rb = read_fll(TWO_PLATEAUS_FLL, "plateaus.fll").rulebase
    got = evaluate_as(rb, np.array([[0.25]]), semantics, 100 if semantics != "exact" else None)
    np.testing.assert_allclose(got, [[expected]], rtol=0, atol=1e-12)


def test_fuzzylite_fcl_unbounded_sum_accumulation_by_hand():
    # fuzzylite 6's FclExporter writes UnboundedSum by its class name (it has no FCL word) and
    # its importer reads no `SUM` (the differential fuzzer's `out.fld is empty` tool errors)
    text = """FUNCTION_BLOCK s
VAR_INPUT x: REAL; END_VAR
VAR_OUTPUT y: REAL; END_VAR
FUZZIFY x
  RANGE := (0 .. 1);
  TERM all := Rectangle -1 2;
END_FUZZIFY
DEFUZZIFY y
  RANGE := (0 .. 2);
  TERM a := Rectangle 0 1;
  TERM b := Rectangle 0 2;
  METHOD : COG;
  ACCU : {accu};
  DEFAULT := nan;
END_DEFUZZIFY
RULEBLOCK r
  AND : MIN;
  OR : MAX;
  ACT : MIN;
  RULE 1 : if x is all then y is a;
  RULE 2 : if x is all then y is b;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""
    # summed: M = 2 on [0, 1], 1 on [1, 2]: (2 * 1/2 + 1 * 3/2) / (2 + 1) = 5/6; MAX: 1
    for accu, expected in (("UnboundedSum", 5 / 6), ("SUM", 5 / 6), ("MAX", 1.0)):
        rb = read_fcl(text.replace("{accu}", accu), "s.fcl").rulebase
        assert evaluate(rb, [[0.5]])[0, 0] == pytest.approx(expected, abs=1e-12), accu


OCTAVE_DRASTIC = """[System]
Name='ds'
Type='mamdani'
Version=2.0
NumInputs=1
NumOutputs=2
NumRules=3
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='drastic_sum'
DefuzzMethod='centroid'

[Input1]
Name='x'
Range=[0 2]
NumMFs=2
MF1='half':'trimf',[0 1 2]
MF2='other':'trimf',[1 2 3]

[Output1]
Name='out1'
Range=[0 2]
NumMFs=2
MF1='a':'trimf',[0 0.5 1]
MF2='b':'trimf',[0 1.5 2]

[Output2]
Name='out2'
Range=[0 2]
NumMFs=1
MF1='c':'trimf',[0 1 2]

[Rules]
1, 1 0 (1) : 1
1, 2 0 (1) : 1
2, 0 1 (1) : 1
"""


def test_octave_drastic_sum_aggregates_every_rule_at_once():
    # drastic_sum.m's vector_arg over the column of every rule's output: the max where some
    # rule's value is 0, else 1.  Rule 3 concludes only out2, so out1's column always holds a
    # 0: at x = 0.5 (half = 0.5) out1's set is max(min(0.5, a), min(0.5, b)), the trapezoid
    # (0, 0.25, 1.75, 2) at 0.5: centroid 1 (Octave 1.0000000000000002).  The pairwise fold
    # is 1 where a and b are both positive, (0, 1): further left (differential case
    # octave-fis/aggregation-drastic-sum, Octave 172.16 where the fold gave 173.75)
    rb = read_fis(OCTAVE_DRASTIC, "ds.fis").rulebase
    assert evaluate_as(rb, [[0.5]], "octave")[0, 0] == pytest.approx(1.0, abs=1e-12)
    assert evaluate(rb, [[0.5]])[0, 0] < 0.9
    # rule 3 on rule 1's premise: one rule concluding out1 and out2 in fuzzyc, still a row
    # with no out1 in Octave's column (measured: 1.0000000000000002 again)
    merged = read_fis(OCTAVE_DRASTIC.replace("2, 0 1 (1) : 1", "1, 0 1 (1) : 1"), "m.fis")
    assert merged.rulebase.n_rules == 2
    assert evaluate_as(merged.rulebase, [[0.5]], "octave")[0, 0] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("method, expected", [
    # measured: Octave 7, fuzzy-logic-toolkit 0.4.6, evalfis([0.5], readfis(FILE)); out2's
    # rule does not fire at 0.5, its set is 0: no default, defuzz.m's own values
    ("centroid", [1.0, math.nan]),           # 0/0
    ("mom", [1.0, 1.0]),                     # every sample is maximal: the middle
    ("som", [0.26, 0.0]), ("lom", [1.74, 2.0]),
    ("bisector", [51.0, 101.0]),             # a sample's index (defuzz.m: crisp_x = midpoint)
])
def test_octave_defuzz_as_the_toolkit_computes_it(method, expected):
    text = OCTAVE_DRASTIC.replace("DefuzzMethod='centroid'", f"DefuzzMethod='{method}'")
    got = evaluate_as(read_fis(text, "d.fis").rulebase, [[0.5]], "octave")[0]
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)


OCTAVE_NARY = """[System]
Name='nary'
Type='sugeno'
Version=2.0
NumInputs=3
NumOutputs=1
NumRules=2
AndMethod='{and}'
OrMethod='{or}'
ImpMethod='prod'
AggMethod='{agg}'
DefuzzMethod='{defuzz}'

[Input1]
Name='a'
Range=[0 1]
NumMFs=1
MF1='up':'trimf',[0 1 2]

[Input2]
Name='b'
Range=[0 1]
NumMFs=1
MF1='up':'trimf',[0 1 2]

[Input3]
Name='c'
Range=[0 1]
NumMFs=1
MF1='up':'trimf',[0 1 2]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='ten':'constant',[10]
MF2='four':'constant',[4]

[Rules]
{rules}
"""


@pytest.mark.parametrize("methods, rules, x, octave, pairwise", [
    # drastic_product over [1, .5, .5] at once: max is 1, so min = .5 (pairwise: dp(.5, .5)
    # = 0); rule 2's one clause .5 alone: max is not 1, so 0 (pairwise: .5).  Octave 10
    (("drastic_product", "max", "sum", "wtaver"), "1 1 1, 1 (1) : 1\n0 0 1, 2 (1) : 1",
     [1, 0.5, 0.5], 10.0, 4.0),
    # the same with a hedged clause (very b: .25; a clause program in fuzzyc): max(1, .25,
    # .5) is 1, so .25 (pairwise 0).  Octave 10
    (("drastic_product", "max", "sum", "wtaver"), "1 1.2 1, 1 (1) : 1\n0 0 1, 2 (1) : 1",
     [1, 0.5, 0.5], 10.0, 4.0),
    # wtsum after merging the rules of one value with max: .5 * 10 (summed per rule: 10).
    # Octave 5 (differential cases octave-fis/defuzzifier-wtsum, -wtaver-wtsum)
    (("min", "max", "max", "wtsum"), "0 0 1, 1 (1) : 1\n0 1 0, 1 (1) : 1",
     [1, 0.5, 0.5], 5.0, 10.0),
    # drastic_sum over [0, .5, .5] at once: min is 0, so max = .5 (pairwise: ds(.5, .5) = 1):
    # (.5 * 10 + .5 * 4) / 1 = 7 (pairwise (10 + 2) / 1.5 = 8).  Octave 7
    (("min", "drastic_sum", "sum", "wtaver"), "1 1 1, 1 (1) : 2\n0 0 1, 2 (1) : 1",
     [0, 0.5, 0.5], 7.0, 8.0),
])
def test_octave_norms_over_all_clauses_and_merged_sugeno_sums(methods, rules, x, octave,
                                                             pairwise):
    # measured: Octave 7, fuzzy-logic-toolkit 0.4.6, evalfis(x, readfis(FILE))
    text = OCTAVE_NARY
    for key, value in zip(("and", "or", "agg", "defuzz"), methods):
        text = text.replace("{" + key + "}", value)
    rb = read_fis(text.replace("{rules}", rules), "n.fis").rulebase
    assert evaluate_as(rb, [x], "octave")[0, 0] == pytest.approx(octave, abs=1e-12)
    assert evaluate(rb, [x])[0, 0] == pytest.approx(pairwise, abs=1e-12)


BISECTOR_FLL = """Engine: bisector
InputVariable: x
  enabled: true
  range: 0 1
  term: all Rectangle -1 2
OutputVariable: y
  enabled: true
  range: 0 4
  aggregation: Maximum
  defuzzifier: Bisector 4
  default: nan
  term: up Ramp 0 4
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  activation: General
  rule: if x is all then y is up
"""


def test_bisector_of_each_fuzzylite_by_hand():
    # up = u/4 at the midpoints 0.5, 1.5, 2.5, 3.5: 1/8, 3/8, 5/8, 7/8.
    # fuzzylite 6 (Bisector.cpp) sweeps from both ends, the left side while its area is at
    # most the right's: left 0.5 (1/8), right 3.5 (7/8), left 1.5 (1/2), left 2.5 (9/8);
    # (9/8 * 3.5 + 7/8 * 2.5) / 2 = 3.0625, as the fuzzylite 6 CLI gives (differential cases
    # fuzzylite-*/defuzzifier-bisector*).  pyfuzzylite 8: the cumulative areas 1/8, 1/2, 9/8, 2 are nearest half of
    # 2 at the third midpoint: 2.5
    rb = read_fll(BISECTOR_FLL, "b.fll").rulebase
    assert evaluate_as(rb, [[0.5]], "fuzzylite", 4)[0, 0] == pytest.approx(3.0625, abs=1e-12)
    assert evaluate_as(rb, [[0.5]], "pyfuzzylite", 4)[0, 0] == pytest.approx(2.5, abs=1e-12)


TINY_FLL = """Engine: tiny
InputVariable: x
  enabled: true
  range: 0 1
  term: up Triangle 0 1 2
OutputVariable: y
  enabled: true
  range: 0 2
  aggregation: Maximum
  defuzzifier: Centroid 100
  default: nan
  term: mid Triangle 0 1 2
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  activation: General
  rule: if x is up then y is mid
"""


def test_fuzzylite6_fires_no_rule_below_its_epsilon():
    # up(x) = x: the rule's activation is 5e-7 or 2e-6.  fuzzylite 6 (Rule::trigger,
    # Op::isGt within 1e-6) fires it only at 2e-6: nan, then the centroid of mid clipped
    # flat, 1 (measured: the fuzzylite 6 CLI prints nan and 1); pyfuzzylite 8 fires both: 1, 1
    rb = read_fll(TINY_FLL, "tiny.fll").rulebase
    got = evaluate_as(rb, [[5e-7], [2e-6]], "fuzzylite")[:, 0]
    assert math.isnan(got[0]) and got[1] == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_allclose(evaluate_as(rb, [[5e-7], [2e-6]], "pyfuzzylite")[:, 0],
                               [1.0, 1.0], rtol=0, atol=1e-9)


def test_fuzzylite6_defuzzifies_a_fired_set_that_is_zero_throughout():
    # DrasticProduct implication: min(a, mu) where max(a, mu) is 1, else 0; the rule fires
    # at 0.5 and mid < 1 at every midpoint of [0, 2] (100: 0.01, 0.03, ..., none is 1), so
    # the set is 0 throughout.  fuzzylite 6 still defuzzifies it (the default only where no
    # rule fired): its LargestOfMaximum scan keeps the last sample, 1.99, the smallest the
    # first, 0.01, the mean of maximum the middle, 1 (measured: the fuzzylite 6 CLI)
    for method, expected in (("LargestOfMaximum", 1.99), ("SmallestOfMaximum", 0.01),
                             ("MeanOfMaximum", 1.0)):
        text = TINY_FLL.replace("Centroid 100", f"{method} 100").replace(
            "implication: Minimum", "implication: DrasticProduct")
        rb = read_fll(text, "zero.fll").rulebase
        assert evaluate_as(rb, [[0.5]], "fuzzylite")[0, 0] == pytest.approx(expected,
                                                                              abs=1e-12)


OCTAVE_DSIGMF = """[System]
Name='dsig'
Type='sugeno'
Version=2.0
NumInputs=1
NumOutputs=1
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='prod'
AggMethod='sum'
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 2]
NumMFs=2
MF1='d':'dsigmf',[1 0 2 0]
MF2='half':'trimf',[0 2 4]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='ten':'constant',[10]
MF2='four':'constant',[4]

[Rules]
1, 1 (1) : 1
2, 2 (1) : 1
"""


def test_octave_dsigmf_is_the_clipped_difference():
    # dsigmf [1 0 2 0] at x = 1: sig(1) - sig(2) = 0.7311 - 0.8808 < 0.  dsigmf.m clips it to
    # 0 (max(0, min(1, ...))): only rule 2 (half = 0.5) counts, y = 4 (Octave: 4); fuzzyc's
    # SigmoidDifference, fuzzylite's, is |0.1497|: (0.1497 * 10 + 0.5 * 4) / 0.6497 = 5.3828
    # (differential case octave-fis/shape-dsigmf: 21 of 200 Octave files disagreed so)
    rb = read_fis(OCTAVE_DSIGMF, "ds.fis").rulebase
    assert evaluate_as(rb, [[1.0]], "octave")[0, 0] == pytest.approx(4.0, abs=1e-12)
    d = abs(1 / (1 + math.exp(-1)) - 1 / (1 + math.exp(-2)))
    assert evaluate(rb, [[1.0]])[0, 0] == pytest.approx((10 * d + 2) / (d + 0.5), abs=1e-12)


def test_drastic_product_within_fuzzylite6_epsilon_and_pyfuzzylite_empty_set():
    # DrasticProduct implication, x = 0.5 (activation 0.5), mid peaks at 1.0100005: at the
    # midpoint 1.01 mid = 0.9999995, which fuzzylite 6 takes as 1 (DrasticProduct.cpp:
    # Op::isEq(max, 1) within 1e-6), so the set is 0.5 there alone: centroid 1.01 (the
    # fuzzylite 6 CLI: 1.01).  pyfuzzylite 8 compares exactly: the set is 0 throughout and
    # its centroid NaN (measured), the file's default nan (was the model's default, 0)
    text = TINY_FLL.replace("implication: Minimum", "implication: DrasticProduct").replace(
        "term: mid Triangle 0 1 2", "term: mid Triangle 0 1.0100005 2")
    rb = read_fll(text, "dp.fll").rulebase
    assert evaluate_as(rb, [[0.5]], "fuzzylite")[0, 0] == pytest.approx(1.01, abs=1e-12)
    assert math.isnan(evaluate_as(rb, [[0.5]], "pyfuzzylite")[0, 0])


def test_a_fis_row_without_input_index_is_fuzzylites_chained_rule_that_never_fires():
    # fuzzylite 6 writes its chained Laundry engine's `if Detergent is ... then Cycle is ...`
    # as a row of zeros on the inputs; it reads such a row back as a rule that never fires
    # (its CLI gives Cycle = nan everywhere, measured); so does the importer, with a note
    text = ("[System]\nName='chained'\nType='mamdani'\nNumInputs=1\nNumOutputs=2\nNumRules=2\n"
            "AndMethod='min'\nOrMethod='max'\nImpMethod='min'\nAggMethod='max'\n"
            "DefuzzMethod='centroid'\n\n[Input1]\nName='x'\nRange=[0 10]\nNumMFs=1\n"
            "MF1='a':'trimf',[0 10 20]\n\n[Output1]\nName='y'\nRange=[0 10]\nNumMFs=1\n"
            "MF1='b':'trimf',[0 5 10]\n\n[Output2]\nName='z'\nRange=[0 10]\nNumMFs=1\n"
            "MF1='c':'trimf',[0 5 10]\n\n[Rules]\n1, 1 0 (1) : 1\n0, 0 1 (1) : 1\n")
    model = read_fis(text, "chained.fis")
    assert any("rule at line 33 has no input index" in n for n in model.notes), model.notes
    # x = 5: a = 0.5, y = 5 (a symmetric set); z's rule never fires: its default (the
    # range's middle, 5, in the model) and NaN under fuzzylite's semantics
    got = Chain(model).evaluate(np.array([[5.0]]))[0]
    assert got.tolist() == pytest.approx([5.0, 5.0], abs=1e-12)
    tool = Chain(model).evaluate(np.array([[5.0]]), "fuzzylite")[0]
    assert tool[0] == pytest.approx(5.0, abs=1e-3) and math.isnan(tool[1])
