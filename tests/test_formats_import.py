"""Importers: the corpus files in tests/format_corpus/ give the expected rule bases, and the engine
evaluates them to values computed here independently (hand arithmetic, or the shapes' formulas
written out below and integrated on a dense grid)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.formats import load_any
from fuzzyc.formats.fuzzylite_compat import evaluate_sampled
from fuzzyc.semantics.model import Defuzzifier, Hedge, SNorm, TermKind, TNorm

CORPUS = Path(__file__).parent / "format_corpus"
INF = math.inf


def ramp(x, start, end):
    """fuzzylite Ramp: 0 at start, 1 at end (either direction)."""
    return np.clip((x - start) / (end - start), 0.0, 1.0)


def tri(x, a, b, c):
    return np.maximum(0.0, np.minimum((x - a) / (b - a), (c - x) / (c - b)))


def trap(x, a, b, c, d):
    rise = np.ones_like(x) if a == b else np.clip((x - a) / (b - a), 0, 1)
    fall = np.ones_like(x) if c == d else np.clip((d - x) / (d - c), 0, 1)
    return np.minimum(np.where(x >= a, rise, 0.0), np.where(x <= d, fall, 0.0))


def gauss(x, mean, sigma):
    return np.exp(-((x - mean) ** 2) / (2 * sigma ** 2))


def centroid_max_min(strengths_and_terms, lo, hi, n=400_001):
    """Mamdani centroid written from its definition: M = max_r min(act_r, mu_r(u))."""
    u = np.linspace(lo, hi, n)
    m = np.zeros_like(u)
    for act, term in strengths_and_terms:
        m = np.maximum(m, np.minimum(act, term(u)))
    return np.trapezoid(u * m, u) / np.trapezoid(m, u)


def tip_terms():
    return (lambda u: tri(u, 0, 5, 10), lambda u: tri(u, 10, 15, 20), lambda u: tri(u, 20, 25, 30))


POINTS = [(5.0, 5.0), (1.0, 8.0), (9.7, 9.0), (3.0, 1.0), (7.5, 6.5), (0.0, 10.0)]


# ---------------------------------------------------------------------- FLL
def fll_tipper_reference(s, f):
    poor, good = ramp(s, 4, 0), tri(s, 2, 5, 8)
    excellent, perfect = trap(s, 6, 9, 10, 10), float(9.5 <= s <= 10)
    rancid = 1 / (1 + math.exp(3 * (f - 2)))          # Sigmoid inflection 2, slope -3
    fine = gauss(f, 5, 1.5)
    delicious = 1 / (1 + abs((f - 9) / 1.5) ** 4)     # Bell centre 9, width 1.5, slope 2
    fresh = ramp(f, 6, 10)
    cheap, average, generous = tip_terms()
    return centroid_max_min([(max(poor, rancid), cheap), (min(good, fine), average),
                             (max(excellent, delicious), generous),
                             (min(perfect, fresh), generous)], 0, 30)


def test_fll_tipper_structure():
    m = load_any(CORPUS / "tipper.fll")
    rb = m.rulebase
    service, food = rb.inputs
    # Ramp 4 0 falls: a left shoulder; Rectangle 9.5 10 is a trapezoid with vertical sides.
    assert service.params.tolist() == [[-INF, -INF, 0, 4], [2, 5, 5, 8], [6, 9, 10, 10],
                                       [9.5, 9.5, 10, 10]]
    assert food.kinds.tolist() == [TermKind.SIGMOID, TermKind.GAUSSIAN, TermKind.BELL,
                                   TermKind.TRAPEZOID]
    assert food.params[3].tolist() == [6, 10, INF, INF]
    assert rb.connective.tolist() == [1, 0, 1, 0]            # or, and, or, and
    assert rb.inference.defuzzifier == Defuzzifier.CENTROID
    assert [s.name for s in m.signals] == ["service", "food"]
    assert [o.name for o in m.outputs] == ["tip_out"]
    assert any("default nan" in n for n in m.notes)           # recorded, not silent


def test_fll_tipper_values_match_the_formulas():
    rb = load_any(CORPUS / "tipper.fll").rulebase
    got = evaluate(rb, np.array(POINTS))[:, 0]
    want = [fll_tipper_reference(s, f) for s, f in POINTS]
    np.testing.assert_allclose(got, want, atol=1e-6)


def test_fll_sugeno_hand_value():
    rb = load_any(CORPUS / "sugeno.fll").rulebase
    assert rb.inference.and_ == TNorm.PRODUCT and rb.inference.or_ == SNorm.PROBSUM
    assert rb.hedges[:, 0].tolist() == [Hedge.VERY, Hedge.NONE, Hedge.NONE]
    assert rb.hedges[:, 1].tolist() == [Hedge.NONE, Hedge.SOMEWHAT, Hedge.NONE]
    assert rb.negated[:, 0].tolist() == [False, False, True]
    assert rb.weights.tolist() == [1.0, 0.5, 0.25]           # two rule blocks, merged
    # x = 0.5, y = 0.25: low(x) = 0.5, high(x) = 0.5, low(y) = 0.75, high(y) = 0.25
    # r1 = very low(x) * low(y) = 0.25 * 0.75 = 0.1875                -> a = 2
    # r2 = 0.5 * probsum(0.5, sqrt(0.25)) = 0.5 * 0.75 = 0.375         -> b = 8
    # r3 = 0.25 * (1 - high(x)) = 0.125                                -> c = 5
    # z = (0.375 + 3 + 0.625) / 0.6875 = 5.818181...
    assert evaluate(rb, np.array([[0.5, 0.25]]))[0, 0] == pytest.approx(4 / 0.6875, abs=1e-12)


def test_fll_weighted_sum_hand_value():
    rb = load_any(CORPUS / "wsum.fll").rulebase
    assert rb.inference.defuzzifier == Defuzzifier.WEIGHTED_SUM
    # the same activations as above, not normalised: 0.1875*2 + 0.375*8 + 0.125*5 = 4
    assert evaluate(rb, np.array([[0.5, 0.25]]))[0, 0] == pytest.approx(4.0, abs=1e-12)


def test_fll_weighted_average_grouped_by_maximum_is_center_of_area():
    rb = load_any(CORPUS / "coa.fll").rulebase
    assert rb.inference.defuzzifier == Defuzzifier.CENTER_OF_AREA
    # x = 0.25, y = 0.5: rules for a fire 0.75 and 0.5 -> alpha_a = max = 0.75; b fires 0.25
    # z = (0.75*2 + 0.25*8) / (0.75 + 0.25) = 3.5   (ungrouped it would be 4.5/1.5 = 3.0)
    assert evaluate(rb, np.array([[0.25, 0.5]]))[0, 0] == pytest.approx(3.5, abs=1e-12)


def test_compat_sampled_centroid_is_the_midpoint_rule():
    """evaluate_sampled = sum u_k M(u_k) / sum M(u_k) at the 100 midpoints of [0, 30]."""
    rb = load_any(CORPUS / "tipper.fll").rulebase
    u = (np.arange(100) + 0.5) * 0.3
    cheap, average, generous = tip_terms()
    s, f = 5.0, 5.0
    acts = [(1 / (1 + math.exp(9)), cheap), (min(tri(s, 2, 5, 8), gauss(f, 5, 1.5)), average),
            (1 / (1 + (4 / 1.5) ** 4), generous)]
    m = np.max([np.minimum(a, t(u)) for a, t in acts], axis=0)
    want = (u * m).sum() / m.sum()
    got = evaluate_sampled(rb, np.array([[s, f]]), resolution=100)[0, 0]
    assert got == pytest.approx(want, abs=1e-12)
    exact = evaluate(rb, np.array([[s, f]]))[0, 0]
    assert abs(got - exact) < 0.05 and got != exact          # sampling error, not a mistake


# ---------------------------------------------------------------------- FCL
def fcl_tipper_reference(s, f):
    poor, good, excellent = ramp(s, 4, 0), trap(s, 1, 4, 6, 9), ramp(s, 6, 9)
    rancid, tasty, delicious = ramp(f, 3, 1), gauss(f, 6, 1.5), tri(f, 7, 9, 11)
    cheap, generous = (lambda u: tri(u, 0, 5, 10)), (lambda u: tri(u, 20, 25, 30))
    average = lambda u: trap(u, 10, 12.5, 17.5, 20)  # noqa: E731
    return centroid_max_min([(max(poor, rancid), cheap), (min(good, tasty), average),
                             (0.8 * min(excellent, 1 - rancid), generous),
                             (min(1 - poor, delicious), generous)], 0, 30)


def test_fcl_tipper_structure_and_values():
    rb = load_any(CORPUS / "tipper.fcl").rulebase
    service, food = rb.inputs
    # (0,1) (4,0): IEC keeps the first point's value to the left -> a left shoulder
    assert service.params.tolist() == [[-INF, -INF, 0, 4], [1, 4, 6, 9], [6, 9, INF, INF]]
    assert food.params[0].tolist() == [-INF, -INF, 1, 3]
    assert food.kinds[1] == TermKind.GAUSSIAN and food.params[1, :2].tolist() == [6, 1.5]
    assert rb.negated.tolist() == [[False, False], [False, False], [False, True], [True, False]]
    assert rb.weights.tolist() == [1, 1, 0.8, 1]
    got = evaluate(rb, np.array(POINTS))[:, 0]
    np.testing.assert_allclose(got, [fcl_tipper_reference(s, f) for s, f in POINTS], atol=1e-6)


def test_fcl_cogs_singletons_hand_value():
    rb = load_any(CORPUS / "valve.fcl").rulebase
    assert rb.inference.defuzzifier == Defuzzifier.CENTER_OF_AREA
    assert rb.outputs[0].default == 50
    # level 40, flow 5: low 0.6, mid (40-25)/25 = 0.6, high 0.4; small(5) = 0.5 -> rule 4 fires
    # 0.6*0.5 = 0.3 on `open` too, but ACCU MAX keeps 0.6.
    # valve = (0.6*100 + 0.6*50 + 0.4*0) / (0.6 + 0.6 + 0.4) = 90 / 1.6 = 56.25
    assert evaluate(rb, np.array([[40.0, 5.0]]))[0, 0] == pytest.approx(56.25, abs=1e-12)


# ---------------------------------------------------------------------- FIS
def fis_tipper_reference(s, f):
    poor, good, excellent = gauss(s, 0, 1.5), gauss(s, 5, 1.5), gauss(s, 10, 1.5)
    rancid, delicious = trap(f, 0, 0, 1, 3), trap(f, 7, 9, 10, 10)
    cheap, average, generous = tip_terms()
    return centroid_max_min([(max(poor, rancid), cheap), (good, average),
                             (max(excellent, delicious), generous),
                             (0.5 * min(1 - poor, delicious), generous)], 0, 30)


def test_fis_tipper_structure_and_values():
    rb = load_any(CORPUS / "tipper.fis").rulebase
    service = rb.inputs[0]
    # gaussmf [sigma c] -> (mean, sigma)
    assert service.params[:, :2].tolist() == [[0, 1.5], [5, 1.5], [10, 1.5]]
    assert rb.antecedents.tolist() == [[0, 0], [1, -1], [2, 1], [0, 1]]
    assert rb.negated[3].tolist() == [True, False]
    got = evaluate(rb, np.array(POINTS))[:, 0]
    np.testing.assert_allclose(got, [fis_tipper_reference(s, f) for s, f in POINTS], atol=1e-6)


def test_fis_sugeno_hand_value():
    rb = load_any(CORPUS / "sugeno.fis").rulebase
    assert rb.inference.defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
    y_low, y_high = rb.inputs[1].params[:, :3].tolist()
    assert y_low[:2] == [0.5, -10] and y_high == [1, 0.5, 2]   # sigmf [a c], gbellmf [a b c]
    # x = 0.25, y = 0.5: low(x) 0.75, high(x) 0.25; sigmf(0.5; -10, 0.5) = 0.5,
    # gbellmf(0.5; 0.5, 2, 1) = 1 / (1 + 1^4) = 0.5
    # r1 = 0.75 * 0.5 = 0.375 -> 2;  r2 = 0.5 * probor(0.25, 0.5) = 0.5 * 0.625 = 0.3125 -> 8
    # z = (0.75 + 2.5) / 0.6875 = 4.7272...
    assert evaluate(rb, np.array([[0.25, 0.5]]))[0, 0] == pytest.approx(3.25 / 0.6875, abs=1e-12)
