"""Aggregation by the probabilistic sum (probsum) and the bounded sum: known answers by hand,
the same numbers from FLL, FCL and FIS files, round trips, the speed paths, and the back ends
that refuse them.

The hand case: two rules conclude the same term A at levels 0.5 and 0.4.
  alpha_A: max 0.5, sum 0.9, probsum 0.5 + 0.4 - 0.5 * 0.4 = 0.7, bounded sum min(1, 0.9) = 0.9.
Centroid over the output term A = the ramp mu(u) = 1 - u/2 on [0, 2] (a triangle (0, 0, 2)),
MIN implication.  Write v = 1 - u/2 (u = 2 - 2v, du = -2 dv); the items are min(0.5, v) and
min(0.4, v), so three pieces: u in [0, 1] (v >= 0.5), [1, 1.2] (0.4 <= v <= 0.5), [1.2, 2].
  probsum M: 0.7;  1 - (1 - v)(1 - 0.4) = 0.4 + 0.6 v;  1 - (1 - v)^2 = 2v - v^2
    area   = 0.7 + 2 int_.4^.5 (0.4 + 0.6v) dv + 2 int_0^.4 (2v - v^2) dv
           = 0.7 + 2 (0.04 + 0.027) + 2 (0.16 - 0.064/3) = 0.7 + 0.134 + 0.832/3 = 3.334/3
    moment = 0.7/2 + 4 int_.4^.5 (1 - v)(0.4 + 0.6v) dv + 4 int_0^.4 (1 - v)(2v - v^2) dv
           = 0.35 + 4 (0.04 + 0.009 - 0.0122) + 4 (0.16 - 0.064 + 0.0064)
           = 0.35 + 0.1472 + 0.4096 = 0.9068
    centroid = 0.9068 / (3.334/3) = 2.7204 / 3.334
  bounded sum M (= the sum here, 0.9 < 1): 0.9;  v + 0.4;  2v
    area   = 0.9 + 2 (0.045 + 0.04) + 2 (0.16) = 0.9 + 0.17 + 0.32 = 1.39
    moment = 0.45 + 4 (0.04 + 0.027 - 0.061/3) + 8 (0.08 - 0.064/3) = 1.106
    centroid = 1.106 / 1.39
  max M: min(0.5, v): area 0.5 + 2 (0.125) = 0.75, moment 0.25 + 4 (0.125 - 0.125/3) = 7/12,
    centroid 7/9.
  The clip of A at 0.7 (what probsum is NOT): area 0.7 * 0.6 + 2 int_0^.7 v dv = 0.42 + 0.49,
    moment 0.7 * 0.18 + 4 (0.245 - 0.343/3): 0.6486667 / 0.91 = 0.71282.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c_fixed.header import generate_fixed_header
from fuzzyc.engine.defuzz import OutputDefuzzifier, term_strengths
from fuzzyc.engine.inference import CompiledRuleBase, evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fis, read_fll, write_fcl, write_fis, write_fll
from fuzzyc.formats.fz import write_fz
from fuzzyc.semantics.model import ACTIVATION_FLOOR, Aggregation, Defuzzifier, Implication, Inference, TNorm
from fuzzyc.language.parser import parse
from fuzzyc.verifier import Status, proof
from test_engine_core import SINGLE_OUT, TRI_OUT, driven, random_inputs, var, wedm_like

INF = math.inf
PROBSUM, BOUNDED = Aggregation.PROBSUM, Aggregation.BOUNDED_SUM
RAMP = var("y", {"A": ("trap", 0.0, 0.0, 0.0, 2.0)}, lo=0.0, hi=2.0)     # 1 - u/2 on [0, 2]
CENTROIDS = {Aggregation.MAX: 7 / 9, Aggregation.SUM: 1.106 / 1.39,
             PROBSUM: 2.7204 / 3.334, BOUNDED: 1.106 / 1.39}


# -- the engine -------------------------------------------------------------------------------

@pytest.mark.parametrize("aggregation, alpha", [(Aggregation.MAX, 0.5), (Aggregation.SUM, 0.9),
                                                (PROBSUM, 0.7), (BOUNDED, 0.9)])
def test_two_rules_on_one_term(aggregation, alpha):
    act = np.array([[0.5, 0.4]])
    for J in (np.array([0, 0]), np.array([[0, 0]])):     # static and per-sample consequents
        got = term_strengths(act, J, 1, aggregation)
        assert got[0, 0] == pytest.approx(alpha, abs=1e-15)


def test_bounded_sum_caps_at_one_where_probsum_does_not():
    # 0.8 and 0.6: sum 1.4, bounded min(1, 1.4) = 1, probsum 0.8 + 0.6 - 0.48 = 0.92
    act, J = np.array([[0.8, 0.6]]), np.array([[0, 0]])
    assert term_strengths(act, J, 1, BOUNDED)[0, 0] == 1.0
    assert term_strengths(act, J, 1, PROBSUM)[0, 0] == pytest.approx(0.92, abs=1e-15)
    assert term_strengths(act, J, 1, Aggregation.SUM)[0, 0] == pytest.approx(1.4, abs=1e-15)



def test_probsum_keeps_the_digits_of_small_activations():
    # 1 - (1 - 1e-14)(1 - 3e-14) in doubles keeps about two digits (1 - 1e-14 rounds to a
    # multiple of 2**-53 ~ 1.1e-16, and it gives 3.9968e-14); the exact value is 4e-14 - 3e-28.
    act = np.array([[1e-14, 3e-14]])
    for J in (np.array([0, 0]), np.array([[0, 0]])):
        assert term_strengths(act, J, 1, PROBSUM)[0, 0] == pytest.approx(4e-14 - 3e-28,
                                                                          rel=1e-15, abs=0.0)
    # a full activation still gives 1: log(1 - 1) = -inf, 1 - exp(-inf) = 1
    assert term_strengths(np.array([[1.0, 0.3]]), np.array([0, 0]), 1, PROBSUM)[0, 0] == 1.0


def test_probsum_centroid_of_a_faint_symmetric_term_is_its_middle():
    # one rule fires the triangle (0, 5, 10) at 1.3e-12 (a Gaussian's tail, just above
    # ACTIVATION_FLOOR): product implication scales it, so its centroid is 5 at any level.
    # Found by CI's round-trip search at 1.3e-14: 1 - prod(1 - g) put it at 5.0018 (the lost
    # digits of g are noise across u, and the unused term B's break point at 0.5 splits the
    # pieces unevenly, so it does not cancel).  At 1.3e-14, below the floor, it does not fire.
    out = var("y", {"A": ("tri", 0.0, 5.0, 10.0), "B": ("trap", 0.0, 0.0, 0.0, 0.5)},
              lo=0.0, hi=10.0)
    for level in (1.3e-14, 1.3e-12, 1e-9, 0.5):
        rb, x = driven([(level, "A")], out, aggregation=PROBSUM,
                       implication=Implication.PRODUCT, defuzzifier=Defuzzifier.CENTROID)
        expected = out.default if level < ACTIVATION_FLOOR else 5.0
        assert evaluate(rb, x)[0, 0] == pytest.approx(expected, abs=1e-12)

@pytest.mark.parametrize("aggregation, expected", [
    # a third rule concludes B (peak 2) at 0.6: (alpha_A * 1 + 0.6 * 2) / (alpha_A + 0.6)
    (Aggregation.MAX, 1.7 / 1.1), (Aggregation.SUM, 2.1 / 1.5),
    (PROBSUM, 1.9 / 1.3), (BOUNDED, 2.1 / 1.5)])
def test_center_of_area_by_hand(aggregation, expected):
    out = var("y", {"A": ("single", 1.0), "B": ("single", 2.0)}, lo=0.0, hi=3.0)
    rb, x = driven([(0.5, "A"), (0.4, "A"), (0.6, "B")], out, aggregation=aggregation,
                   defuzzifier=Defuzzifier.CENTER_OF_AREA)
    assert evaluate(rb, x)[0, 0] == pytest.approx(expected, abs=1e-14)


# the aggregations integrated exactly (the folded s-norms are sampled: test_formats_tool_dialects)
@pytest.mark.parametrize("aggregation", list(CENTROIDS))
def test_centroid_over_the_ramp_by_hand(aggregation):
    rb, x = driven([(0.5, "A"), (0.4, "A")], RAMP, aggregation=aggregation,
                   defuzzifier=Defuzzifier.CENTROID)
    assert evaluate(rb, x)[0, 0] == pytest.approx(CENTROIDS[aggregation], abs=1e-14)


def test_probsum_of_clipped_shapes_is_not_the_clip_at_the_probsum_level():
    rb, x = driven([(0.5, "A"), (0.4, "A")], RAMP, aggregation=PROBSUM,
                   defuzzifier=Defuzzifier.CENTROID)
    clipped_at_07 = 0.6486667 / 0.91                      # see the module docstring
    assert abs(evaluate(rb, x)[0, 0] - clipped_at_07) > 0.1


@pytest.mark.parametrize("aggregation, expected", [
    # probsum: half the area 3.334/6 lies in the flat first piece (area 0.7): u = (3.334/6)/0.7
    (PROBSUM, 3.334 / 4.2),
    # bounded sum: half of 1.39 = 0.695 in the flat 0.9 piece: u = 0.695 / 0.9
    (BOUNDED, 0.695 / 0.9)])
def test_bisector_by_hand(aggregation, expected):
    rb, x = driven([(0.5, "A"), (0.4, "A")], RAMP, aggregation=aggregation,
                   defuzzifier=Defuzzifier.BISECTOR)
    assert evaluate(rb, x)[0, 0] == pytest.approx(expected, abs=1e-13)


def test_probsum_bisector_inside_a_curved_piece():
    # levels 0.9 and 0.9 on the ramp: M = 1 - 0.1^2 = 0.99 on [0, 0.2] (v >= 0.9), then
    # 2v - v^2 with v = 1 - u/2 (one curved piece, [0.2, 2]):
    #   area = 0.198 + 2 int_0^.9 (2v - v^2) dv = 0.198 + 2 (0.81 - 0.243) = 1.332, half 0.666;
    #   the bisector u_b is in the curved piece, where int_{u_b}^2 M du = 2 (w^2 - w^3/3) with
    #   w = v(u_b) must be 1.332 - 0.666 = 0.666: w^2 - w^3/3 = 0.333, solved below by plain
    #   bisection on w, and u_b = 2 - 2w.
    rb, x = driven([(0.9, "A"), (0.9, "A")], RAMP, aggregation=PROBSUM,
                   defuzzifier=Defuzzifier.BISECTOR)
    lo, hi = 0.0, 0.9
    for _ in range(200):
        w = 0.5 * (lo + hi)
        lo, hi = (w, hi) if w * w - w ** 3 / 3 < 0.333 else (lo, w)
    assert evaluate(rb, x)[0, 0] == pytest.approx(2 - 2 * lo, abs=1e-12)


@pytest.mark.parametrize("aggregation", [PROBSUM, BOUNDED])
def test_mean_of_maximum_by_hand(aggregation):
    # M is largest (0.7, 0.9) on the flat piece [0, 1]: its middle 0.5
    rb, x = driven([(0.5, "A"), (0.4, "A")], RAMP, aggregation=aggregation,
                   defuzzifier=Defuzzifier.MEAN_OF_MAXIMUM)
    assert evaluate(rb, x)[0, 0] == pytest.approx(0.5, abs=1e-15)


def test_probsum_dip_between_two_full_terms_is_no_plateau():
    # L = 1 on [-1, 0] falling to 0 at 1, R rising from 0 at 0 to 1 on [1, 3], both at level 1:
    # M = 1 - (1 - L)(1 - R) is 1 on [-1, 0] and [1, 3], and 1 - u (1 - u) on [0, 1], which is
    # 1 at both ends but 0.75 at u = 0.5: a dip, not a plateau.  The maxima are [-1, 0] and
    # [1, 3]: length-weighted mean (1 * -0.5 + 2 * 2) / 3 = 3.5 / 3 (counting the dip as top
    # would give the middle of [-1, 3], 1).
    out = var("y", {"L": ("trap", -INF, -INF, 0.0, 1.0), "R": ("trap", 0.0, 1.0, INF, INF)},
              lo=-1.0, hi=3.0)
    rb, x = driven([(1.0, "L"), (1.0, "R")], out, aggregation=PROBSUM,
                   defuzzifier=Defuzzifier.MEAN_OF_MAXIMUM)
    assert evaluate(rb, x)[0, 0] == pytest.approx(3.5 / 3, abs=1e-14)


def test_bounded_sum_bends_where_the_sum_reaches_one():
    # A = tri(0, 1, 3), two rules at 0.7 and 0.6 (MIN): the sum is 2 mu for mu <= 0.6, and
    # min(1, 2 mu) caps it from mu = 0.5 on, at u = 0.5 and u = 2 -- neither is a break point of
    # the items (those sit at mu = 0.6 and 0.7), so the bend must be inserted.
    # M = 2u on [0, 0.5], 1 on [0.5, 2], 3 - u on [2, 3]:
    #   area   = 0.25 + 1.5 + 0.5 = 2.25
    #   moment = int_0^.5 2u^2 + int_.5^2 u + int_2^3 (3 - u) u
    #          = 0.25/3 + 1.875 + (4.5 - 10/3) = 3.125 -> centroid 3.125 / 2.25 = 25/18
    #   bisector: int_0^b M = 1.125 -> 0.25 + (b - 0.5) = 1.125 -> b = 1.375
    #   mean of maximum: the middle of [0.5, 2] = 1.25
    out = var("y", {"A": ("tri", 0.0, 1.0, 3.0)}, lo=0.0, hi=3.0)
    for method, expected in ((Defuzzifier.CENTROID, 25 / 18), (Defuzzifier.BISECTOR, 1.375),
                             (Defuzzifier.MEAN_OF_MAXIMUM, 1.25)):
        rb, x = driven([(0.7, "A"), (0.6, "A")], out, aggregation=BOUNDED, defuzzifier=method)
        assert evaluate(rb, x)[0, 0] == pytest.approx(expected, abs=1e-14)


# -- the speed paths ----------------------------------------------------------------------------

@pytest.mark.parametrize("aggregation", [PROBSUM, BOUNDED])
def test_grid_strengths_are_bit_equal_to_the_sparse_scatter(aggregation):
    rb = wedm_like(SINGLE_OUT, depth=2, weights=True, aggregation=aggregation,
                   defuzzifier=Defuzzifier.CENTER_OF_AREA)
    engine = CompiledRuleBase(rb)
    assert engine.grid is not None and engine.peak_ratio
    x = random_inputs(600)
    act, rid = engine.candidates(x)
    alpha = engine.grid(x)
    for o, d in enumerate(engine.defuzzifiers):
        expected = term_strengths(act, engine.consequents[rid, o], d.var.n_terms, aggregation)
        np.testing.assert_array_equal(alpha[engine.grid.slices[o]].T, expected)
    # and the controller's row layout gives the very same outputs
    np.testing.assert_array_equal(engine.evaluate_rows(np.ascontiguousarray(x.T)),
                                  engine.evaluate_chunk(x).T)


@pytest.mark.parametrize("aggregation", [PROBSUM, BOUNDED])
@pytest.mark.parametrize("method", [Defuzzifier.CENTROID, Defuzzifier.BISECTOR,
                                    Defuzzifier.MEAN_OF_MAXIMUM])
def test_area_methods_step_aside_from_grid_and_closed_form(aggregation, method):
    # every rule's own shape is needed: no term strengths, so no grid and no closed form
    # (the sparse candidates remain); the results equal the dense path's
    rb = wedm_like(TRI_OUT, aggregation=aggregation, defuzzifier=method)
    engine = CompiledRuleBase(rb)
    assert engine.sparse and engine.grid is None
    assert all(d.closed_form is None and d.strength_aggregation() is None
               for d in engine.defuzzifiers)
    x = random_inputs(300)
    np.testing.assert_allclose(engine.evaluate_chunk(x),
                               CompiledRuleBase(rb, allow_sparse=False).evaluate_chunk(x),
                               rtol=0, atol=1e-12)


def test_strengths_alone_are_refused_where_each_rule_shape_is_needed():
    d = OutputDefuzzifier(RAMP, Inference(aggregation=PROBSUM))
    with pytest.raises(ValueError, match="every rule's own shape"):
        d.from_strengths(np.array([[0.7]]))


def test_smooth_terms_under_probsum_are_sampled_like_the_others():
    # a gaussian output term: M on the grid; two rules at 0.5 and 0.4 on the one symmetric term
    # give its centre 0.25 whatever the aggregation (to the grid's step, 1.5 / 2000)
    out = var("y", {"G": ("gauss", 0.25, 0.2)}, lo=-0.5, hi=1.0)
    for aggregation in (PROBSUM, BOUNDED):
        rb, x = driven([(0.5, "G"), (0.4, "G")], out, aggregation=aggregation,
                       defuzzifier=Defuzzifier.MEAN_OF_MAXIMUM)
        assert evaluate(rb, x)[0, 0] == pytest.approx(0.25, abs=1e-3)


# -- the language -------------------------------------------------------------------------------

FZ = """controller agg {{
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0.25, 0.875)
  var y in [0, 2] default 0
  terms y : A = trap(0, 0, 0, 2)
  inference and = min, implication = min, aggregation = {agg}, defuzzify = centroid
  rule if x is lo then y is A
  rule if x is hi then y is A
  output u in [0, 2] = y
}}
"""
X = np.array([[0.5]])     # lo = 1 - 0.5 = 0.5, hi = (0.5 - 0.25) / 0.625 = 0.4


@pytest.mark.parametrize("word, aggregation", [("probsum", PROBSUM),
                                               ("probabilistic_sum", PROBSUM),
                                               ("bounded_sum", BOUNDED)])
def test_language_words(word, aggregation):
    model = parse(FZ.format(agg=word), "agg.fz")
    assert model.rulebase.inference.aggregation == aggregation
    assert evaluate(model.rulebase, X)[0, 0] == pytest.approx(CENTROIDS[aggregation], abs=1e-14)
    again = parse(write_fz(model), "again.fz").rulebase
    assert again.inference.aggregation == aggregation


def test_unknown_aggregation_word_is_a_diagnostic():
    with pytest.raises(FuzzycError, match="aggregation"):
        parse(FZ.format(agg="einstein_summ"), "agg.fz")


# -- the formats: the same hand-computed numbers from each tool's file --------------------------

FLL = """Engine: agg
InputVariable: x
  enabled: true
  range: 0 1
  lock-range: false
  term: lo Ramp 1 0
  term: hi Ramp 0.25 0.875
OutputVariable: y
  enabled: true
  range: 0 2
  lock-range: false
  aggregation: {agg}
  defuzzifier: Centroid 1000
  default: nan
  lock-previous: false
  term: A Ramp 2 0
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  implication: Minimum
  activation: General
  rule: if x is lo then y is A
  rule: if x is hi then y is A
"""
FCL = """FUNCTION_BLOCK agg
VAR_INPUT
  x : REAL;
END_VAR
VAR_OUTPUT
  y : REAL;
END_VAR
FUZZIFY x
  TERM lo := (0, 1) (1, 0);
  TERM hi := (0.25, 0) (0.875, 1);
  RANGE := (0 .. 1);
END_FUZZIFY
DEFUZZIFY y
  TERM A := (0, 1) (2, 0);
  METHOD : COG;
  DEFAULT := 0;
  RANGE := (0 .. 2);
END_DEFUZZIFY
RULEBLOCK rules
  AND : MIN;
  ACT : MIN;
  ACCU : {agg};
  RULE 1 : IF x IS lo THEN y IS A;
  RULE 2 : IF x IS hi THEN y IS A;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""
FIS = """[System]
Name='agg'
Type='mamdani'
Version=2.0
NumInputs=1
NumOutputs=1
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='{agg}'
DefuzzMethod='centroid'

[Input1]
Name='x'
Range=[0 1]
NumMFs=2
MF1='lo':'trimf',[-1 0 1]
MF2='hi':'trapmf',[0.25 0.875 2 3]

[Output1]
Name='y'
Range=[0 2]
NumMFs=1
MF1='A':'trimf',[0 0 2]

[Rules]
1, 1 (1) : 1
2, 1 (1) : 1
"""
FILES = [("fll", FLL, "AlgebraicSum", PROBSUM, read_fll, write_fll),
         ("fll", FLL, "BoundedSum", BOUNDED, read_fll, write_fll),
         ("fcl", FCL, "ASUM", PROBSUM, read_fcl, write_fcl),      # fuzzylite's word
         ("fcl", FCL, "BSUM", BOUNDED, read_fcl, write_fcl),
         ("fis", FIS, "probor", PROBSUM, read_fis, write_fis)]


@pytest.mark.parametrize("fmt, text, word, aggregation, read, write", FILES,
                         ids=[f"{f[0]}-{f[2]}" for f in FILES])
def test_file_gives_the_hand_computed_centroid_and_round_trips(fmt, text, word, aggregation,
                                                               read, write):
    model = read(text.format(agg=word), f"agg.{fmt}")
    rb = model.rulebase
    assert rb.inference.aggregation == aggregation
    assert evaluate(rb, X)[0, 0] == pytest.approx(CENTROIDS[aggregation], abs=1e-14)
    written = write(model)
    assert word in written
    again = read(written, f"again.{fmt}").rulebase
    assert again.inference.aggregation == aggregation
    grid = np.linspace(0, 1, 41)[:, None]
    np.testing.assert_allclose(evaluate(again, grid), evaluate(rb, grid), rtol=0, atol=1e-14)


def test_fis_export_refuses_the_bounded_sum_with_a_reason():
    model = read_fll(FLL.format(agg="BoundedSum"), "agg.fll")
    with pytest.raises(FuzzycError, match="aggregation bounded_sum has no FIS word"):
        write_fis(model)


# the same file with a third term and rule concluding B, and constant output terms
def test_fis_export_of_a_center_of_area_names_the_aggregation_that_has_no_wtaver():
    # two rules conclude A: probsum combines them, MATLAB's wtaver would sum them
    model = read_fll(COA_FLL.format(agg="AlgebraicSum"), "coa.fll")
    with pytest.raises(FuzzycError, match=r"center_of_area with probsum aggregation combines the "
                                          r"rules that conclude the same term \(`A` of `y`"):
        write_fis(model)


COA_FLL = (FLL.replace("term: hi Ramp 0.25 0.875",
                       "term: hi Ramp 0.25 0.875\n  term: mid Ramp -0.25 1")
           .replace("range: 0 2", "range: 0 3").replace("Centroid 1000", "WeightedAverage")
           .replace("term: A Ramp 2 0", "term: A Constant 1\n  term: B Constant 2")
           + "  rule: if x is mid then y is B\n")


@pytest.mark.parametrize("word, aggregation, expected", [
    # x = 0.5: lo 0.5 and hi 0.4 conclude A (value 1), mid (0.5 + 0.25) / 1.25 = 0.6 concludes B
    ("AlgebraicSum", PROBSUM, 1.9 / 1.3), ("BoundedSum", BOUNDED, 2.1 / 1.5)])
def test_fll_weighted_average_grouped_by_an_snorm_is_the_center_of_area(word, aggregation,
                                                                        expected):
    model = read_fll(COA_FLL.format(agg=word), "coa.fll")
    inf = model.rulebase.inference
    assert (inf.defuzzifier, inf.aggregation) == (Defuzzifier.CENTER_OF_AREA, aggregation)
    assert evaluate(model.rulebase, X)[0, 0] == pytest.approx(expected, abs=1e-14)
    written = write_fll(model)
    assert f"aggregation: {word}" in written and "WeightedAverage" in written
    again = read_fll(written, "again.fll").rulebase.inference
    assert (again.defuzzifier, again.aggregation) == (Defuzzifier.CENTER_OF_AREA, aggregation)
    # FCL says it as COGS with the ACCU word
    fcl = write_fcl(model)
    assert "METHOD : COGS;" in fcl
    assert read_fcl(fcl, "coa.fcl").rulebase.inference.aggregation == aggregation


# -- pyfuzzylite itself, where it is installed -----------------------------------------------

def _fuzzylite(text: str, x: np.ndarray) -> np.ndarray:
    fl = pytest.importorskip("fuzzylite")
    engine = fl.FllImporter().from_string(text)
    engine.input_variable("x").value = x[:, 0]
    engine.process()
    return np.atleast_1d(engine.output_variables[0].value)


@pytest.mark.parametrize("word, aggregation, expected", [
    ("AlgebraicSum", PROBSUM, 1.9 / 1.3), ("BoundedSum", BOUNDED, 2.1 / 1.5)])
def test_pyfuzzylite_center_of_area_agrees(word, aggregation, expected):
    text = COA_FLL.format(agg=word)
    x = np.linspace(0, 1, 201)[:, None]
    theirs = _fuzzylite(text, x)
    assert theirs[100] == pytest.approx(expected, abs=1e-14)        # x = 0.5
    np.testing.assert_allclose(evaluate(read_fll(text, "coa.fll").rulebase, x)[:, 0], theirs,
                               rtol=0, atol=1e-12)


@pytest.mark.parametrize("word", ["AlgebraicSum", "BoundedSum"])
@pytest.mark.parametrize("method", ["Centroid", "Bisector", "MeanOfMaximum"])
def test_pyfuzzylite_sampled_area_methods_agree(word, method):
    from fuzzyc.formats.fuzzylite_compat import evaluate_sampled
    text = FLL.format(agg=word).replace("Centroid 1000", f"{method} 1000")
    x = np.linspace(0, 1, 201)[:, None]
    theirs = _fuzzylite(text, x)
    rb = read_fll(text, "agg.fll").rulebase
    np.testing.assert_allclose(evaluate_sampled(rb, x, 1000)[:, 0], theirs, rtol=0, atol=1e-9)
    if method == "Centroid":   # the exact centroid differs by the midpoint rule's error only
        assert np.max(np.abs(evaluate(rb, x)[:, 0] - theirs)) < 1e-5


# -- the back ends and the proofs -------------------------------------------------------------

@pytest.mark.parametrize("aggregation", [PROBSUM, BOUNDED])
def test_c_back_ends_refuse_with_the_reason(aggregation):
    model = parse(FZ.format(agg=aggregation.name.lower()), "agg.fz")
    with pytest.raises(FuzzycError, match=f"aggregation = {aggregation.name.lower()}"):
        generate_header(model)
    model.rulebase.inference.defuzzifier = Defuzzifier.CENTER_OF_AREA
    for numeric in ("q15", "q31"):
        with pytest.raises(FuzzycError, match="emits aggregation = max | sum"):
            generate_fixed_header(model, numeric)


def test_c_back_end_takes_a_weighted_average_whatever_the_aggregation():
    # weighted average sums over rules: the aggregation plays no part
    model = parse(FZ.format(agg="probsum").replace("trap(0, 0, 0, 2)", "singleton(1)")
                  .replace("centroid", "weighted_average"), "agg.fz")
    assert model.rulebase.inference.aggregation == PROBSUM
    assert "#define" in generate_header(model)


def test_proofs_take_the_hull_and_leave_monotonicity_to_the_search():
    # center of area with probsum strengths is still a convex combination of the peaks
    rb = wedm_like(SINGLE_OUT, and_=TNorm.PRODUCT, implication=Implication.PRODUCT,
                   aggregation=PROBSUM, defuzzifier=Defuzzifier.CENTER_OF_AREA)
    bounded = proof.prove_bounded(rb, "du1", -1.0, 1.0)
    assert bounded.status == Status.PROVED and "convex combination" in bounded.detail
    monotone = proof.prove_monotone(rb, "du1", "e2", "increasing", [])
    assert monotone.status == Status.UNDECIDED
    assert "aggregation=probsum" in monotone.detail
    assert proof.multilinear(rb, 0) is None
