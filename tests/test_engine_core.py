"""The engine against hand-computed answers (arithmetic in the comments)."""
import math

import numpy as np
import pytest

from fuzzyc.engine.defuzz import GRID_POINTS, OutputDefuzzifier
from fuzzyc.engine.inference import CompiledRuleBase, activations, evaluate, evaluate_one, explain
from fuzzyc.engine.membership import memberships, term_values
from fuzzyc.semantics.model import (Aggregation, Connective, Defuzzifier, Hedge, Implication, Inference,
                          RuleBase, SNorm, TermKind, TNorm, Variable)

INF = math.inf
KIND = {"tri": TermKind.TRAPEZOID, "trap": TermKind.TRAPEZOID, "gauss": TermKind.GAUSSIAN,
        "bell": TermKind.BELL, "sig": TermKind.SIGMOID, "single": TermKind.SINGLETON}


def var(name, terms, lo=-1.0, hi=1.0, default=0.0):
    """terms: {name: (shape, *params)}; tri(a, b, c) is stored as the trapezoid (a, b, b, c)."""
    kinds, params = [], []
    for shape, *p in terms.values():
        if shape == "tri":
            p = [p[0], p[1], p[1], p[2]]
        kinds.append(KIND[shape])
        params.append(list(p) + [0.0] * (4 - len(p)))
    return Variable(name, lo, hi, list(terms), np.array(kinds), np.array(params, dtype=float),
                    default=default)


def uniform(name, labels, lo=-1.0, hi=1.0, shoulders=True):
    """Uniform triangles with peaks spread over [lo, hi]; end terms shoulders if asked."""
    peaks = np.linspace(lo, hi, len(labels))
    h = peaks[1] - peaks[0]
    terms = {t: ("tri", c - h, c, c + h) for t, c in zip(labels, peaks)}
    if shoulders:
        terms[labels[0]] = ("trap", -INF, -INF, lo, lo + h)
        terms[labels[-1]] = ("trap", hi - h, hi, INF, INF)
    return var(name, terms, lo, hi)


def rulebase(inputs, outputs, rules, **inference):
    """rules: (antecedent term names or None per input, consequent names or None per output,
    options) with options weight, negated (per input), hedges (per input), conn."""
    ant, con, w, neg, hed, conn = [], [], [], [], [], []
    for antecedent, consequent, *opts in rules:
        o = opts[0] if opts else {}
        ant.append([-1 if t is None else v.index(t) for v, t in zip(inputs, antecedent)])
        con.append([-1 if t is None else v.index(t) for v, t in zip(outputs, consequent)])
        w.append(o.get("weight", 1.0))
        neg.append(o.get("negated", [False] * len(inputs)))
        hed.append(o.get("hedges", [Hedge.NONE] * len(inputs)))
        conn.append(o.get("conn", Connective.AND))
    return RuleBase(inputs, outputs, np.array(ant, dtype=int).reshape(len(rules), len(inputs)),
                    np.array(con, dtype=int).reshape(len(rules), len(outputs)),
                    np.array(w, dtype=float),
                    np.array(neg, dtype=bool).reshape(len(rules), len(inputs)),
                    np.array(hed, dtype=int).reshape(len(rules), len(inputs)),
                    np.array(conn, dtype=int), Inference(**inference))


def driven(levels_terms, out, **inference):
    """One input per rule, its only term 'on' = 1 - x on [0, 1], so x = 1 - activation.
    Returns (rule base, x row giving the wanted activations)."""
    inputs = [var(f"x{i}", {"on": ("trap", -INF, -INF, 0.0, 1.0)}) for i in range(len(levels_terms))]
    rules = [([("on" if j == i else None) for j in range(len(inputs))], [term])
             for i, (_, term) in enumerate(levels_terms)]
    x = np.array([[1.0 - a for a, _ in levels_terms]])
    return rulebase(inputs, [out], rules, **inference), x


# -- memberships -------------------------------------------------------------------------------

def test_triangle_trapezoid_and_shoulders():
    v = var("v", {"T": ("tri", 0, 1, 2), "Z": ("trap", 0, 1, 2, 4),
                  "L": ("trap", -INF, -INF, -1, -0.5), "R": ("trap", 0.5, 1, INF, INF)})
    x = np.array([0.5, 1.0, 1.5, 3.0, -0.75, -5.0, -INF, INF, np.nan])
    mu = memberships(v, x)
    # T: 0.5/1, peak, (2-1.5)/1, 0 ... ; Z at 3: (4-3)/(4-2) = 0.5; L at -0.75: (-0.5+0.75)/0.5
    np.testing.assert_allclose(mu[:, 0], [0.5, 1, 0.5, 0, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(mu[:, 1], [0.5, 1, 1, 0.5, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(mu[:, 2], [0, 0, 0, 0, 0.5, 1, 1, 0, 0])
    np.testing.assert_allclose(mu[:, 3], [0, 1, 1, 1, 0, 0, 0, 1, 0])


def test_smooth_terms_and_singleton():
    v = var("v", {"G": ("gauss", 0, 1), "B": ("bell", 0, 2, 1), "S": ("sig", 0, 2),
                  "P": ("single", 0.5)})
    mu = memberships(v, np.array([1.0, 2.0, 4.0, 0.0, 0.5, INF, -INF, np.nan]))
    # G(1) = exp(-1/2); B(2) = 1/(1+1); B(4) = 1/(1+2^2); S(0) = 1/2; S(1) = 1/(1+e^-2)
    assert mu[0, 0] == pytest.approx(math.exp(-0.5))
    assert mu[1, 1] == pytest.approx(0.5) and mu[2, 1] == pytest.approx(0.2)
    assert mu[3, 2] == pytest.approx(0.5) and mu[0, 2] == pytest.approx(1 / (1 + math.exp(-2)))
    np.testing.assert_array_equal(mu[:, 3], [0, 0, 0, 0, 1, 0, 0, 0])
    np.testing.assert_allclose(mu[5], [0, 0, 1, 0])   # +inf: only the sigmoid's limit is 1
    np.testing.assert_allclose(mu[6], [0, 0, 0, 0])
    np.testing.assert_array_equal(mu[7], [0, 0, 0, 0])


# -- activations -------------------------------------------------------------------------------

AB = [var("a", {"Z": ("tri", -1, 0, 1)}), var("b", {"Z": ("tri", -1, 0, 1)})]
OUT = var("y", {"N": ("single", -1.0), "P": ("single", 1.0)})
X_AB = np.array([[0.4, 0.7]])     # mu_a = 0.6, mu_b = 0.3


@pytest.mark.parametrize("conn, tnorm, snorm, expected", [
    (Connective.AND, TNorm.MIN, SNorm.MAX, 0.3),          # min(0.6, 0.3)
    (Connective.AND, TNorm.PRODUCT, SNorm.MAX, 0.18),     # 0.6 * 0.3
    (Connective.OR, TNorm.MIN, SNorm.MAX, 0.6),           # max(0.6, 0.3)
    (Connective.OR, TNorm.MIN, SNorm.PROBSUM, 0.72),      # 0.6 + 0.3 - 0.18
])
def test_connectives(conn, tnorm, snorm, expected):
    rb = rulebase(AB, [OUT], [(["Z", "Z"], ["P"], {"conn": conn})], and_=tnorm, or_=snorm)
    assert activations(rb, X_AB)[0, 0] == pytest.approx(expected)


def test_not_hedges_weights_wildcards():
    rules = [(["Z", None], ["P"], {"negated": [True, False]}),                # 1 - 0.6
             (["Z", None], ["P"], {"hedges": [Hedge.VERY, 0]}),               # 0.6^2
             ([None, "Z"], ["P"], {"hedges": [0, Hedge.SOMEWHAT]}),           # sqrt(0.3)
             (["Z", None], ["P"], {"hedges": [Hedge.EXTREMELY, 0]}),          # 0.6^3
             (["Z", None], ["P"], {"hedges": [Hedge.VERY, 0], "negated": [True, False]}),  # 1-0.36
             (["Z", "Z"], ["P"], {"weight": 0.5}),                            # 0.5 * 0.3
             ([None, None], ["P"], {"conn": Connective.OR}),                  # wildcards only: 1
             (["Z", None], ["P"], {"conn": Connective.OR})]                   # absent clause: 0.6
    act = activations(rulebase(AB, [OUT], rules), X_AB)[0]
    np.testing.assert_allclose(act, [0.4, 0.36, math.sqrt(0.3), 0.216, 0.64, 0.15, 1.0, 0.6])


def test_nan_input_fires_nothing_and_gives_default():
    rb = rulebase(AB, [var("y", {"P": ("single", 1.0)}, default=0.25)], [(["Z", "Z"], ["P"])])
    assert activations(rb, [[np.nan, 0.0]])[0, 0] == 0.0
    assert evaluate(rb, [[np.nan, 0.0]])[0, 0] == 0.25


# -- defuzzifiers ------------------------------------------------------------------------------

Y_TRI = var("y", {"A": ("tri", 0, 1, 2), "B": ("tri", 1, 2, 3)}, lo=0.0, hi=3.0, default=2.5)


def numeric(levels_terms, out, implication, aggregation, n=1_000_001):
    """Centroid by brute force on n points (trapezoid rule), for the agreement checks."""
    u = np.linspace(out.lo, out.hi, n)
    mu = term_values(out.kinds, out.params, u)
    parts = [np.minimum(a, mu[:, out.index(t)]) if implication == Implication.MIN
             else a * mu[:, out.index(t)] for a, t in levels_terms]
    m = np.max(parts, axis=0) if aggregation == Aggregation.MAX else np.sum(parts, axis=0)
    return np.trapezoid(u * m, u) / np.trapezoid(m, u)


@pytest.mark.parametrize("implication, aggregation, levels, expected", [
    # M: u on [0,1]; 2-u on [1,1.5]; 0.5 on [1.5,2.5]; 3-u on [2.5,3].
    # area 0.5 + 0.375 + 0.5 + 0.125 = 1.5; moment 1/3 + 0.458333 + 1 + 1/3 = 2.125 -> 17/12
    (Implication.MIN, Aggregation.MAX, [(1.0, "A"), (0.5, "B")], 17 / 12),
    # M = max(A, B/2): the scaled edges cross at 2-u = (u-1)/2, u = 5/3.
    # area 0.5 + 4/9 + 5/36 + 1/4 = 4/3; moment 1/3 + 46/81 + 83/324 + 7/12 = 47/27 -> 47/36
    (Implication.PRODUCT, Aggregation.MAX, [(1.0, "A"), (0.5, "B")], 47 / 36),
    # M = 2 min(0.5, A): symmetric about 1 -> 1
    (Implication.MIN, Aggregation.SUM, [(0.5, "A"), (0.5, "A")], 1.0),
    # A clipped at 0.5 (area 0.75, centroid 1) plus A at 0.25 (area 0.4375, centroid 1)
    # plus B at 0.5 (area 0.75, centroid 2): (0.75 + 0.4375 + 1.5) / 1.9375 = 2.6875/1.9375
    (Implication.MIN, Aggregation.SUM, [(0.5, "A"), (0.25, "A"), (0.5, "B")], 2.6875 / 1.9375),
])
def test_exact_centroid(implication, aggregation, levels, expected):
    rb, x = driven(levels, Y_TRI, implication=implication, aggregation=aggregation,
                   defuzzifier=Defuzzifier.CENTROID)
    y = evaluate(rb, x)[0, 0]
    assert y == pytest.approx(expected, abs=1e-12)
    assert y == pytest.approx(numeric(levels, Y_TRI, implication, aggregation), abs=1e-7)


def test_centroid_of_shoulders_clipped_to_range():
    # L = 1 below 0, falls to 0 at 1; range [-1, 1]; alone at 1: area 1 + 0.5 = 1.5,
    # moment -1/2 + 1/6 = -1/3 -> -2/9
    out = var("y", {"L": ("trap", -INF, -INF, 0, 1)}, lo=-1, hi=1)
    rb, x = driven([(1.0, "L")], out)
    assert evaluate(rb, x)[0, 0] == pytest.approx(-2 / 9)


def test_bisector_and_mean_of_maximum():
    # Same M as the first centroid case: half the area (0.75) is 0.5 in [0,1] plus 0.25 of the
    # piece 2-u: t - t^2/2 = 0.25, t = 1 - sqrt(1/2)
    rb, x = driven([(1.0, "A"), (0.5, "B")], Y_TRI, defuzzifier=Defuzzifier.BISECTOR)
    assert evaluate(rb, x)[0, 0] == pytest.approx(2 - math.sqrt(0.5))
    rb.inference.defuzzifier = Defuzzifier.MEAN_OF_MAXIMUM
    assert evaluate(rb, x)[0, 0] == pytest.approx(1.0)        # the single peak at u = 1
    # A and B both clipped at 0.5: the plateau is [0.5, 2.5] -> 1.5
    rb, x = driven([(0.5, "A"), (0.5, "B")], Y_TRI, defuzzifier=Defuzzifier.MEAN_OF_MAXIMUM)
    assert evaluate(rb, x)[0, 0] == pytest.approx(1.5)


@pytest.mark.parametrize("method, expected", [
    (Defuzzifier.CENTER_OF_AREA, (0.6 * 1 + 0.5 * 2) / 1.1),      # alpha_A = max(0.6, 0.3)
    (Defuzzifier.WEIGHTED_AVERAGE, (0.9 * 1 + 0.5 * 2) / 1.4),    # every rule counts
    (Defuzzifier.WEIGHTED_SUM, 0.9 * 1 + 0.5 * 2),
])
def test_peak_based(method, expected):
    rb, x = driven([(0.6, "A"), (0.3, "A"), (0.5, "B")], Y_TRI, defuzzifier=method)
    assert evaluate(rb, x)[0, 0] == pytest.approx(expected)


def test_centroid_of_singletons_is_weighted_point_masses():
    out = var("y", {"A": ("single", 1.0), "B": ("single", 2.0)}, lo=0, hi=3)
    rb, x = driven([(0.6, "A"), (0.3, "A"), (0.5, "B")], out, defuzzifier=Defuzzifier.CENTROID)
    assert evaluate(rb, x)[0, 0] == pytest.approx((0.6 + 1.0) / 1.1)


@pytest.mark.parametrize("method", list(Defuzzifier))
def test_default_when_nothing_fires(method):
    rb, x = driven([(0.0, "A"), (0.0, "B")], Y_TRI, defuzzifier=method)
    assert evaluate(rb, x)[0, 0] == 2.5


@pytest.mark.parametrize("method", list(Defuzzifier))
def test_a_rule_base_without_rules_gives_the_default(method):
    # found by the fuzzer: a Takagi-Sugeno file whose rules were all deleted had zero work per
    # sample and the chunk size divided by it (ZeroDivisionError)
    x = uniform("x", ["N", "P"])
    rb = rulebase([x], [var("y", {"c": ("single", 1.0)}, lo=0, hi=3, default=2.5)], [],
                  defuzzifier=method)
    assert evaluate(rb, np.array([[0.3], [-0.7]]))[:, 0].tolist() == [2.5, 2.5]


def test_gaussian_output_is_sampled_on_the_documented_grid():
    out = var("y", {"G": ("gauss", 1.0, 0.5), "H": ("gauss", 2.0, 0.3)}, lo=0, hi=3)
    levels = [(0.8, "G"), (0.4, "H")]
    rb, x = driven(levels, out, defuzzifier=Defuzzifier.CENTROID)
    u = np.linspace(0, 3, GRID_POINTS)
    mu = term_values(out.kinds, out.params, u)
    m = np.maximum(np.minimum(0.8, mu[:, 0]), np.minimum(0.4, mu[:, 1]))
    assert evaluate(rb, x)[0, 0] == pytest.approx(np.trapezoid(u * m, u) / np.trapezoid(m, u))
    assert evaluate(rb, x)[0, 0] == pytest.approx(numeric(levels, out, Implication.MIN,
                                                          Aggregation.MAX), abs=1e-4)


# -- the sparse path equals the dense reference ---------------------------------------------------

LABELS5 = ["NB", "NS", "ZO", "PS", "PB"]


def wedm_like(outputs, seed=0, depth=1, weights=False, **inference):
    """3 inputs (3, 5, 5 terms), a random full table, `depth` rules per cell."""
    e1 = var("e1", {"N": ("tri", -2, -1, 0), "ZO": ("tri", -1, 0, 1), "P": ("tri", 0, 1, 2)})
    ins = [e1, uniform("e2", LABELS5), uniform("ce2", LABELS5)]
    rng = np.random.default_rng(seed)
    rules = []
    for _ in range(depth):
        for a in e1.names:
            for b in LABELS5:
                for c in LABELS5:
                    cons = [LABELS5[k] for k in rng.integers(0, 5, len(outputs))]
                    w = float(rng.uniform(0.2, 1.0)) if weights else 1.0
                    rules.append(([a, b, c], cons, {"weight": w}))
    return rulebase(ins, outputs, rules, **inference)


def random_inputs(n, seed=1):
    x = np.random.default_rng(seed).uniform(-1.3, 1.3, (n, 3))
    x[::17, 0] = np.nan
    x[::23, 1] = INF
    x[::29, 2] = -INF
    x[5, :] = [0.0, 0.5, -1.0]        # exactly on break points
    return x


TRI_OUT = [uniform(n, LABELS5, shoulders=False) for n in ("du1", "du2")]
SINGLE_OUT = [var(n, {t: ("single", c) for t, c in zip(LABELS5, np.linspace(-1, 1, 5))})
              for n in ("du1", "du2")]


@pytest.mark.parametrize("outputs", [TRI_OUT, SINGLE_OUT])
@pytest.mark.parametrize("method", list(Defuzzifier))
@pytest.mark.parametrize("tnorm, imp, agg, depth, weights", [
    (TNorm.MIN, Implication.MIN, Aggregation.MAX, 1, False),
    (TNorm.PRODUCT, Implication.PRODUCT, Aggregation.SUM, 2, True),
    (TNorm.MIN, Implication.MIN, Aggregation.SUM, 1, True),
])
def test_sparse_equals_dense(outputs, method, tnorm, imp, agg, depth, weights):
    rb = wedm_like(outputs, depth=depth, weights=weights, and_=tnorm, implication=imp,
                   aggregation=agg, defuzzifier=method)
    sparse = CompiledRuleBase(rb)
    assert sparse.sparse
    x = random_inputs(600)
    dense = CompiledRuleBase(rb, allow_sparse=False).evaluate_chunk(x)
    np.testing.assert_allclose(sparse.evaluate_chunk(x), dense, rtol=0, atol=1e-12)
    assert np.all(np.isfinite(dense))


def test_exact_centroid_of_wedm_like_matches_brute_force():
    rb = wedm_like(TRI_OUT[:1], defuzzifier=Defuzzifier.CENTROID)
    x = np.random.default_rng(3).uniform(-1, 1, (4, 3))
    y = evaluate(rb, x)[:, 0]
    act = activations(rb, x)
    for k in range(len(x)):
        levels = [(a, LABELS5[rb.consequents[r, 0]]) for r, a in enumerate(act[k]) if a > 0]
        assert y[k] == pytest.approx(numeric(levels, TRI_OUT[0], Implication.MIN,
                                             Aggregation.MAX), abs=1e-7)


def test_chunks_do_not_change_results():
    rb = wedm_like(TRI_OUT, defuzzifier=Defuzzifier.CENTROID)
    x = random_inputs(1000)
    np.testing.assert_array_equal(evaluate(rb, x, chunk=7), evaluate(rb, x))


def test_evaluate_one_and_explain():
    # e1 = 0.3 -> ZO 0.7, P 0.3; e2 = -0.2 -> NS 0.4, ZO 0.6; ce2 = 0.6 -> PS 0.8, PB 0.2
    rb = wedm_like(SINGLE_OUT, defuzzifier=Defuzzifier.CENTER_OF_AREA)
    out = evaluate_one(rb, {"e1": 0.3, "e2": -0.2, "ce2": 0.6})
    ex = explain(rb, np.array([0.3, -0.2, 0.6]))
    assert len(ex.fired) == 8
    assert ex.fired[0][1] == pytest.approx(0.6)          # min(0.7, 0.6, 0.8)
    assert ex.memberships["e1"]["ZO"] == pytest.approx(0.7)
    assert ex.outputs == pytest.approx(out)
    # COA from the explanation's own activations
    alpha = np.zeros(5)
    for r, a, _, _ in ex.fired:
        alpha[rb.consequents[r, 0]] = max(alpha[rb.consequents[r, 0]], a)
    assert out["du1"] == pytest.approx(alpha @ np.linspace(-1, 1, 5) / alpha.sum())
    assert "fired (8)" in str(ex)


def test_shipped_wedm_rule_base_equals_the_plain_baseline():
    """The benchmark's baseline (Table 2 typed in by hand) and the .fz file agree."""
    import pathlib
    import sys
    root = pathlib.Path(__file__).resolve().parents[1]
    sys.path.insert(0, str(root / "benchmarks"))
    from dense_numpy_wedm import evaluate as baseline
    from fuzzyc.language.parser import load
    rb = load(root / "rulebases" / "wedm_three_region.fz").rulebase
    x = np.random.default_rng(5).uniform(-1, 1, (2000, 3))
    np.testing.assert_allclose(evaluate(rb, x), baseline(x), rtol=0, atol=1e-12)


RECTANGLES = """controller rect {
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  var y in [0, 1]
  terms y : a = trap(0, 0, 0.5, 0.5), b = trap(0.5, 0.5, 1, 1)
  inference implication = min, aggregation = max, defuzzify = METHOD
  rule if x is lo then y is a
  rule if x is hi then y is b
  output u in [0, 1] = y
}
"""


@pytest.mark.parametrize("method, expected", [
    # x = 0.25: lo 0.75, hi 0.25, so M = 0.75 on [0, 0.5) and 0.25 on (0.5, 1]
    ("centroid", 0.375),        # (0.75*0.125 + 0.25*0.375) / (0.375 + 0.125) = 0.1875 / 0.5
    ("bisector", 1 / 3),        # half the area, 0.25, is reached at 0.25 / 0.75
    ("mean_of_maximum", 0.25),  # the plateau [0, 0.5] at 0.75
])
def test_rectangle_output_terms(method, expected):
    """Output terms with only vertical edges: no sloped line meets a clip level (this once
    stacked an empty list of candidate points)."""
    from fuzzyc.language.parser import parse
    rb = parse(RECTANGLES.replace("METHOD", method), "rect.fz").rulebase
    assert evaluate(rb, np.array([[0.25]]))[0, 0] == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("aggregation", [Aggregation.MAX, Aggregation.SUM])
@pytest.mark.parametrize("h", [2.6e-18, 1.27e-14, 1e-6, 0.3])
def test_a_vertical_edged_term_clipped_at_tiny_levels(aggregation, h):
    # found by the FIS round-trip property: y = trap(0, 0, 0, 0.5) on [0, 10] (1 at 0,
    # falling to 0 at 0.5) clipped at a Gaussian tail's 1e-18 gave 1/6, the unclipped
    # centroid (a + h (b - a) rounds to the foot), and at 1e-14 lost 2.5e-5 (the rounded
    # crossing lay where the term is already below h). Clipped at h the term is h on [0, w],
    # w = (1 - h) / 2, then falls to 0 at 0.5: area h w + h^2 / 4, moment
    # h w^2 / 2 + (h^2 / 4)(w + h / 6), so the centroid is
    # (w^2 / 2 + (h / 4)(w + h / 6)) / (w + h / 4), 1/4 as h -> 0 (0.3: 0.09125 / 0.425).
    out = var("y", {"S": ("trap", 0.0, 0.0, 0.0, 0.5)}, lo=0.0, hi=10.0)
    inference = Inference(implication=Implication.MIN, aggregation=aggregation,
                          defuzzifier=Defuzzifier.CENTROID)
    got = OutputDefuzzifier(out, inference)(np.array([[h]]), np.array([0]))[0]
    w = (1 - h) / 2
    assert got == pytest.approx((w * w / 2 + h / 4 * (w + h / 6)) / (w + h / 4), abs=1e-12)
