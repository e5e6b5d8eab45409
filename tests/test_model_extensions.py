"""fuzzylite's term shapes, norms, hedges and linear (first-order Takagi-Sugeno) consequents:
hand-computed values, the importers and exporters carrying them, .fz saying them, the C back end
refusing what it does not emit, and agreement with pyfuzzylite where it is installed."""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.backends.c.header import check_supported
from fuzzyc.engine.inference import activations, compiled, evaluate, evaluate_one
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any, read_fll
from fuzzyc.formats.fll import SNORMS, TNORMS, write_fll
from fuzzyc.formats.fuzzylite_compat import evaluate_sampled
from fuzzyc.formats.fz import write_fz
from fuzzyc.engine.membership import apply_hedges, term_values
from fuzzyc.semantics.model import Hedge, SNorm, TermKind, TNorm
from fuzzyc.engine.norms import S_NORMS, T_NORMS
from fuzzyc.language.parser import parse

CORPUS = Path(__file__).parent / "format_corpus"


def mu(kind: TermKind, params, x) -> np.ndarray:
    p = np.array([tuple(params) + (0.0,) * (4 - len(params))])
    return term_values(np.array([int(kind)]), p, np.asarray(x, dtype=float))[:, 0]


@pytest.mark.parametrize("kind, params, x, expected", [
    # sshape(2, 6): middle 4; 2((3-2)/4)^2 = 0.125; 2(2/4)^2 = 0.5; 1 - 2((5-6)/4)^2 = 0.875
    (TermKind.SSHAPE, (2, 6), [1, 2, 3, 4, 5, 6, 7], [0, 0, 0.125, 0.5, 0.875, 1, 1]),
    # zshape(2, 6): the mirror, 1 - 0.125 = 0.875 at 3, 2((5-6)/4)^2 = 0.125 at 5
    (TermKind.ZSHAPE, (2, 6), [1, 2, 3, 4, 5, 6, 7], [1, 1, 0.875, 0.5, 0.125, 0, 0]),
    # pishape(1, 3, 5, 8): s(1,3)(2) = 2(1/2)^2 = 0.5; z(5,8)(6.5) = 2((6.5-8)/3)^2 = 0.5
    (TermKind.PISHAPE, (1, 3, 5, 8), [0, 2, 4, 6.5, 9], [0, 0.5, 1, 0.5, 0]),
    # spike(5, 4): exp(-|10/4 * 0.4|) = exp(-1)
    (TermKind.SPIKE, (5, 4), [5, 5.4, 4.6], [1, math.exp(-1), math.exp(-1)]),
    # cosine(5, 6): (1 + cos(2 pi/6 * 1.5))/2 = (1 + cos(pi/2))/2 = 0.5; at 8: (1 + cos pi)/2 = 0
    (TermKind.COSINE, (5, 6), [5, 6.5, 8, 9, -np.inf], [1, 0.5, 0, 0, 0]),
    # concave(4, 7) rising: (7-4)/(14-4-x): x=4 -> 3/6, x=1 -> 3/9, 1 from 7 on
    (TermKind.CONCAVE, (4, 7), [1, 4, 7, 8], [1 / 3, 0.5, 1, 1]),
    # concave(7, 4) falling: (7-4)/(7-8+x): x=7 -> 3/6, x=10 -> 3/9, 1 up to 4
    (TermKind.CONCAVE, (7, 4), [2, 4, 7, 10], [1, 1, 0.5, 1 / 3]),
])
def test_shapes_by_hand(kind, params, x, expected):
    np.testing.assert_allclose(mu(kind, params, x), expected, rtol=0, atol=1e-15)


def test_nan_input_gives_zero_for_every_new_shape():
    for kind, params in [(TermKind.SSHAPE, (2, 6)), (TermKind.ZSHAPE, (2, 6)),
                         (TermKind.PISHAPE, (1, 3, 5, 8)), (TermKind.SPIKE, (5, 4)),
                         (TermKind.COSINE, (5, 6)), (TermKind.CONCAVE, (4, 7))]:
        assert mu(kind, params, [np.nan])[0] == 0.0


A, B = np.array([0.3, 0.7, 1.0, 0.0]), np.array([0.6, 0.6, 0.6, 0.0])


@pytest.mark.parametrize("norm, expected", [
    # max(0, a+b-1): 0.3+0.6-1 < 0; 0.7+0.6-1 = 0.3; 1+0.6-1 = 0.6
    (TNorm.BOUNDED_DIFFERENCE, [0, 0.3, 0.6, 0]),
    # min(a, b) only where max(a, b) = 1
    (TNorm.DRASTIC_PRODUCT, [0, 0, 0.6, 0]),
    # ab/(2-(a+b-ab)): 0.18/1.28 = 0.140625; 0.42/(2-0.88) = 0.375; 0.6/1 = 0.6
    (TNorm.EINSTEIN_PRODUCT, [0.140625, 0.375, 0.6, 0]),
    # ab/(a+b-ab): 0.18/0.72 = 0.25; 0.42/0.88 = 0.4772727..; 0.6/1; 0 at a = b = 0
    (TNorm.HAMACHER_PRODUCT, [0.25, 0.42 / 0.88, 0.6, 0]),
    # min(a, b) where a+b > 1
    (TNorm.NILPOTENT_MIN, [0, 0.6, 0.6, 0]),
])
def test_tnorms_by_hand(norm, expected):
    np.testing.assert_allclose(T_NORMS[norm](A, B), expected, rtol=1e-15, atol=1e-15)


@pytest.mark.parametrize("norm, expected", [
    (SNorm.BOUNDED_SUM, [0.9, 1, 1, 0]),                     # min(1, a+b)
    (SNorm.DRASTIC_SUM, [1, 1, 1, 0]),                       # max where min = 0, else 1
    # (a+b)/(1+ab): 0.9/1.18; 1.3/1.42; 1.6/1.6
    (SNorm.EINSTEIN_SUM, [0.9 / 1.18, 1.3 / 1.42, 1, 0]),
    # (a+b-2ab)/(1-ab): 0.54/0.82; (1.3-0.84)/0.58; 1 - 1.2 + ... = (1.6-1.2)/0.4 = 1
    (SNorm.HAMACHER_SUM, [0.54 / 0.82, 0.46 / 0.58, 1, 0]),
    (SNorm.NILPOTENT_MAX, [0.6, 1, 1, 0]),                   # max where a+b < 1, else 1
])
def test_snorms_by_hand(norm, expected):
    np.testing.assert_allclose(S_NORMS[norm](A, B), expected, rtol=1e-15, atol=1e-15)


def test_norm_edge_cases_without_nan():
    # Hamacher sum at a = b = 1 divides 0 by 0: fuzzylite defines it as 1
    assert S_NORMS[SNorm.HAMACHER_SUM](np.array([1.0]), np.array([1.0]))[0] == 1.0
    # 1 is neutral for every t-norm and 0 for every s-norm: what lets wildcards stand in
    x = np.linspace(0, 1, 11)
    for op in T_NORMS.values():
        np.testing.assert_allclose(op(x, np.ones_like(x)), x, atol=1e-15)
    for op in S_NORMS.values():
        np.testing.assert_allclose(op(x, np.zeros_like(x)), x, atol=1e-15)


def test_hedges_by_hand():
    m = np.array([[0.32, 0.68, 0.25, 0.75, 0.5]])
    # seldom: sqrt(0.32/2) = 0.4; 1 - sqrt(0.32/2) = 0.6; sharply: 2 * 0.25^2 = 0.125,
    # 1 - 2 * 0.25^2 = 0.875; both leave 0.5 where it is (2 * 0.25 and sqrt(0.25))
    hedges = np.array([Hedge.SELDOM, Hedge.SELDOM, Hedge.SHARPLY, Hedge.SHARPLY, Hedge.SELDOM])
    np.testing.assert_allclose(apply_hedges(m, hedges), [[0.4, 0.6, 0.125, 0.875, 0.5]],
                               atol=1e-15)
    # the power hedges alongside: very 0.32^2, somewhat sqrt(0.25)
    np.testing.assert_allclose(apply_hedges(m[:, :3], np.array([1, 0, 2])),
                               [[0.1024, 0.68, 0.5]], atol=1e-15)


NORMS_FZ = """controller norms {{
  input a in [0, 1]
  input b in [0, 1]
  terms a : t = tri(0, 1, 2)
  terms b : t = tri(0, 1, 2)
  var y in [0, 1]
  terms y : one = singleton(1)
  inference and = {and_}, or = {or_}, defuzzify = weighted_sum
  rule if a is t and b is t then y is one
  rule if a is t or b is sharply t then y is one
  output y_out in [0, 1] = y
}}
"""


@pytest.mark.parametrize("tnorm, snorm", list(zip(TNorm, SNorm)))
def test_fz_norms_fire_rules_as_the_formulas_say(tnorm, snorm):
    model = parse(NORMS_FZ.format(and_=tnorm.name.lower(), or_=snorm.name.lower()), "n.fz")
    act = activations(model.rulebase, np.array([[0.3, 0.6]]))[0]
    # a is t = 0.3, b is t = 0.6, b is sharply t = 1 - 2 * 0.4^2 = 0.68
    a, b, sharp = np.array([0.3]), np.array([0.6]), np.array([0.68])
    np.testing.assert_allclose(act, [T_NORMS[tnorm](a, b)[0], S_NORMS[snorm](a, sharp)[0]],
                               atol=1e-15)
    # the sparse and grid paths know only min and product
    and_only = parse(NORMS_FZ.format(and_=tnorm.name.lower(), or_=snorm.name.lower())
                     .replace("rule if a is t or b is sharply t then y is one", ""), "n.fz")
    assert compiled(and_only.rulebase).sparse == (tnorm in (TNorm.MIN, TNorm.PRODUCT))


def test_sugeno_linear_fis_by_hand():
    rb = load_any(CORPUS / "sugeno_linear.fis").rulebase
    # x=3, w=0.25: low = zmf(1,5)(3) = 2((3-5)/4)^2 = 0.5; mid = smf(1,4)(3) * zmf(6,9)(3)
    # = (1 - 2((3-4)/3)^2) * 1 = 7/9; high = smf(5,9)(3) = 0; neg = zmf(-0.5,0.5)(0.25)
    # = 2(0.25-0.5)^2 = 0.125, so `not neg` = 0.875.
    # Rules: low*neg = 0.0625 -> flat 2; mid = 7/9 -> ramp; high|not neg = probor(0, 0.875)
    # -> ramp; ramp = 2x - 3w + 1 = 6.25.  (0.0625*2 + (7/9 + 0.875)*6.25)/(0.0625 + 7/9 + 0.875)
    mid = 7 / 9
    expected = (0.0625 * 2 + (mid + 0.875) * 6.25) / (0.0625 + mid + 0.875)
    assert evaluate_one(rb, {"x": 3, "w": 0.25})["z"] == pytest.approx(expected, abs=1e-13)


def test_any_is_said_with_wildcards():
    rb = load_any(CORPUS / "shapes_tsk.fll").rulebase
    # `a is somewhat p and b is any`: b drops out; `a is k or b is not any`: not any is 0, the
    # neutral element of or, so only `a is k` is left (one clause: read as and)
    assert rb.antecedents[2].tolist() == [2, -1] and rb.antecedents[3].tolist() == [3, -1]
    text = ("Engine: e\nInputVariable: x\n  range: 0 1\n  term: t Triangle 0 0.5 1\n"
            "OutputVariable: y\n  range: 0 1\n  defuzzifier: WeightedAverage\n"
            "  term: c Constant 1\nRuleBlock:\n  conjunction: Minimum\n  disjunction: Maximum\n"
            "  rule: if x is t and x is not any then y is c\n")
    text = text.replace("x is t and x is not any", "x is not any")
    # a rule whose only clause is `not any` never fires: weight 0
    assert read_fll(text).rulebase.weights.tolist() == [0.0]


FOUR_INPUTS = """controller tsk4 {
  input x1 in [0, 1]
  input x2 in [0, 1]
  input x3 in [0, 1]
  input x4 in [0, 1]
  terms x1 : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  terms x2 : all = trap(-1, 0, 1, 2)
  terms x3 : all = trap(-1, 0, 1, 2)
  terms x4 : all = trap(-1, 0, 1, 2)
  var y in [-10, 10]
  terms y : p = linear(1, 2, -1, 0.5, 3), q = linear(-2, 0, 0, 0, 1)
  inference and = product, defuzzify = weighted_average
  rule if x1 is lo then y is p
  rule if x1 is hi and x2 is all and x3 is all and x4 is all then y is q
  output y_out in [-10, 10] = y
}
"""


def test_linear_terms_with_more_coefficients_than_params_hold():
    model = parse(FOUR_INPUTS, "tsk4.fz")
    y = model.rulebase.outputs[0]
    assert y.coefficients is not None and y.coefficients[0].tolist() == [1, 2, -1, 0.5, 3]
    # x = (0.25, 0.5, 1, 0.2): lo = 0.75, hi = 0.25; p = 1 + 0.5 - 0.5 + 0.5 + 0.6 = 2.1,
    # q = -2 + 0.2 = -1.8; (0.75 * 2.1 + 0.25 * -1.8) / 1 = 1.125
    x = np.array([[0.25, 0.5, 1.0, 0.2]])
    assert evaluate(model.rulebase, x)[0, 0] == pytest.approx(1.125, abs=1e-14)
    # carried through .fz and FLL (constant last there) with the same outputs
    rng = np.random.default_rng(3)
    xs = rng.uniform(0, 1, (300, 4))
    for back in (parse(write_fz(model), "back.fz"), read_fll(write_fll(model), "back.fll")):
        np.testing.assert_allclose(evaluate(back.rulebase, xs), evaluate(model.rulebase, xs),
                                   rtol=0, atol=1e-13)
    assert "Linear 2 -1 0.5 3 1" in write_fll(model)


@pytest.mark.parametrize("text, words", [
    (FOUR_INPUTS.replace("weighted_average", "centroid"), "needs defuzzify = weighted_average"),
    (FOUR_INPUTS.replace("linear(-2, 0, 0, 0, 1)", "linear(-2, 0, 0, 0, 1, 7)"),
     "more coefficients than c0 and one per rule-base input (4)"),
    (FOUR_INPUTS.replace("x2 : all = trap(-1, 0, 1, 2)", "x2 : all = linear(1)"),
     "input `x2` cannot have one"),
    (FOUR_INPUTS.replace("lshoulder(0, 1)", "sshape(1, 0)"), "sshape(start, end) with start"),
])
def test_fz_reports_misused_extensions(text, words):
    with pytest.raises(FuzzycError) as err:
        parse(text, "bad.fz")
    assert words in str(err.value)


@pytest.mark.parametrize("change, words", [
    (("and = product", "and = einstein_product"), "and = einstein_product"),
    (("rule if x1 is lo", "rule if x1 is seldom lo"), "not seldom"),
    (("lshoulder(0, 1)", "zshape(0, 1)"), "zshape terms (`lo` of `x1`)"),
    (("", ""), "linear terms (`p` of `y`)"),
])
def test_c_back_end_refuses_what_it_does_not_emit(change, words):
    model = parse(FOUR_INPUTS.replace(*change), "c.fz")
    with pytest.raises(FuzzycError) as err:
        check_supported(model.rulebase)
    assert words in str(err.value)


# ---------------------------------------------------------------- agreement with pyfuzzylite
def _pyfuzzylite_outputs(text: str, rb, x: np.ndarray) -> np.ndarray:
    fl = pytest.importorskip("fuzzylite")
    engine = fl.FllImporter().from_string(text)
    for i, v in enumerate(rb.inputs):
        engine.input_variable(v.name).value = x[:, i]
    engine.process()
    return np.column_stack([engine.output_variable(v.name).value for v in rb.outputs])


@pytest.mark.parametrize("tnorm, snorm", list(zip(TNORMS, [*SNORMS, "Maximum"])))
def test_shapes_norms_hedges_and_linear_terms_agree_with_pyfuzzylite(tnorm, snorm):
    text = (CORPUS / "shapes_tsk.fll").read_text()
    text = re.sub(r"conjunction: \w+", f"conjunction: {tnorm}", text)
    text = re.sub(r"disjunction: \w+", f"disjunction: {snorm}", text)
    rb = read_fll(text).rulebase
    x = np.random.default_rng(7).uniform(0, 10, (400, 2))
    np.testing.assert_allclose(evaluate(rb, x), _pyfuzzylite_outputs(text, rb, x),
                               rtol=0, atol=1e-12)


MAMDANI = """Engine: curves
InputVariable: e
  enabled: true
  range: -1 1
  term: neg ZShape -0.8 0.2
  term: zero Cosine 0 1.2
  term: pos SShape -0.2 0.8
InputVariable: d
  enabled: true
  range: -1 1
  term: pos SShape -0.5 0.5
OutputVariable: u
  enabled: true
  range: 0 10
  aggregation: Maximum
  defuzzifier: Centroid 1000
  default: 5
  term: low Concave 3 1
  term: mid PiShape 2 4.5 5.5 8
  term: high Spike 8 3
RuleBlock: r
  conjunction: HamacherProduct
  disjunction: EinsteinSum
  implication: AlgebraicProduct
  activation: General
  rule: if e is seldom neg then u is low
  rule: if e is extremely zero or d is very pos then u is mid
  rule: if e is pos then u is high
"""


def test_mamdani_with_curved_output_terms_agrees_with_pyfuzzylite_sampling():
    rb = read_fll(MAMDANI).rulebase
    x = np.random.default_rng(11).uniform(-1, 1, (300, 2))
    expected = _pyfuzzylite_outputs(MAMDANI, rb, x)
    np.testing.assert_allclose(evaluate_sampled(rb, x, resolution=1000), expected,
                               rtol=0, atol=1e-12)
    # the model's own (sampled on its fine grid) centroid is close to fuzzylite's midpoints
    np.testing.assert_allclose(evaluate(rb, x), expected, rtol=0, atol=2e-2)
