"""The operator registry (fuzzyc.semantics.operators): one record per t-norm, s-norm, hedge,
aggregation and defuzzifier, and everything that reads it.

- every enum member has a record, and the grammar, the builder and the formats use the
  records' words;
- each record's numpy function against values computed by hand, and its algebraic laws on
  random arrays (identity, commutativity, the monotonicity the record claims);
- each record with a C text: the compiled float header against the engine on random inputs
  of a small rule base using that operator; each without: the C back end refuses it by name.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.api import parse
from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.load import CController
from fuzzyc.backends.c_fixed.header import generate_fixed_header
from fuzzyc.engine import crisp
from fuzzyc.engine.defuzz import term_strengths
from fuzzyc.engine.inference import evaluate
from fuzzyc.engine.membership import HEDGE_EXPONENT, apply_hedges
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import fcl, fis, fll, fz
from fuzzyc.language.builder.rules import HEDGES as FZ_CLAUSE_HEDGES
from fuzzyc.language.builder.rules import INFERENCE_VALUES
from fuzzyc.semantics import operators as ops
from fuzzyc.semantics.model import (Aggregation, Defuzzifier, Hedge, Implication, SNorm, TNorm,
                                    aggregation_snorm)

ROOT = Path(__file__).resolve().parents[1]
RNG = np.random.default_rng(27)
# random truths with the ends 0 and 1 among them, where norms have their special cases
A = np.concatenate([RNG.uniform(0, 1, 2000), [0.0, 1.0, 0.0, 1.0, 0.5]])
B = np.concatenate([RNG.uniform(0, 1, 2000), [0.0, 0.0, 1.0, 1.0, 0.5]])
LAW_TOLERANCE = 1e-12     # a + 1 - a is 1 only to rounding (Hamacher's, Einstein's denominators)


# -- coverage and words --------------------------------------------------------------------

def test_every_member_has_a_record():
    assert set(ops.T_NORMS) == set(TNorm)
    assert set(ops.S_NORMS) == set(SNorm)
    assert set(ops.HEDGES) == set(Hedge)
    assert set(ops.AGGREGATIONS) == set(Aggregation)
    assert set(ops.DEFUZZIFIERS) == set(Defuzzifier)
    # an implication is a t-norm: the same enum and the same records, numbers unchanged
    assert Implication is TNorm and ops.IMPLICATIONS is ops.T_NORMS
    assert [(m.name, int(m)) for m in Implication] == [
        ("MIN", 0), ("PRODUCT", 1), ("BOUNDED_DIFFERENCE", 2), ("DRASTIC_PRODUCT", 3),
        ("EINSTEIN_PRODUCT", 4), ("HAMACHER_PRODUCT", 5), ("NILPOTENT_MIN", 6)]


def test_words_are_unique_per_kind():
    for table in ops.REGISTRIES.values():
        words = [w for w in ops.format_words(table, "fz")]
        assert len(words) == len(set(words))
        assert len(ops.format_words(table, "fz")) >= len(table)


def test_the_grammar_hedge_words_are_the_registry_words():
    grammar = (ROOT / "fuzzyc/language/grammar/fuzzyc.lark").read_text()
    alternatives = re.search(r"^HEDGE\.2:\s*\(([^)]*)\)", grammar, re.M).group(1)
    words = set(re.findall(r'"(\w+)"', alternatives))
    assert words == {rec.word for h, rec in ops.HEDGES.items() if h != Hedge.NONE}
    assert {w: h for w, h in FZ_CLAUSE_HEDGES.items() if w} == \
        {rec.word: h for h, rec in ops.HEDGES.items() if h != Hedge.NONE}


@pytest.mark.parametrize("key", ["and", "or", "implication", "aggregation", "defuzzify"])
def test_the_builder_reads_the_registry_words(key):
    assert INFERENCE_VALUES[key] == ops.format_words(ops.REGISTRIES[key], "fz")


def test_the_formats_write_and_read_the_registry_names():
    written = lambda table, f: ops.format_words(table, f, read=False)   # noqa: E731
    assert fll.TNORMS == ops.format_words(ops.T_NORMS, "fll")
    assert fll.SNORMS == ops.format_words(ops.S_NORMS, "fll")           # + NormalizedSum
    assert fll.IMPLICATIONS == fll.TNORMS
    assert fll.AGGREGATIONS == ops.format_words(ops.AGGREGATIONS, "fll")
    assert fll.HEDGES == ops.format_words(ops.HEDGES, "fll")            # extremely = SHARPLY
    assert fll.INTEGRAL == {rec.fll: d for d, rec in ops.DEFUZZIFIERS.items()
                            if rec.family == "area"}
    assert fcl.OPERATORS["and_op"][2] == written(ops.T_NORMS, "fcl")
    assert fcl.OPERATORS["or_op"][2] == written(ops.S_NORMS, "fcl")
    assert fcl.OPERATORS["act"][2] == written(ops.IMPLICATIONS, "fcl")
    assert fcl.OPERATORS["accu"][2] == written(ops.AGGREGATIONS, "fcl")
    assert fcl.METHODS == written(ops.DEFUZZIFIERS, "fcl")
    for key, table in (("OR", ops.S_NORMS), ("ACCU", ops.AGGREGATIONS)):   # read only
        assert fcl.ALIASES[key] == {w.upper(): rec.fcl for rec in table.values()   # read
                                    for w in rec.also_in("fcl")}                # upper-cased
    for key, table in (("AndMethod", ops.T_NORMS), ("OrMethod", ops.S_NORMS),
                       ("ImpMethod", ops.IMPLICATIONS), ("AggMethod", ops.AGGREGATIONS),
                       ("DefuzzMethod", ops.DEFUZZIFIERS)):
        assert fis.SETTINGS[key][1] == written(table, "fis")
        also = {w: k for k, rec in table.items() for w in rec.also_in("fis")}
        assert fis.READ_ALSO.get(key, {}) == also
    assert fis.FIS_HEDGE_WORDS == {h: rec.fis for h, rec in ops.HEDGES.items() if rec.fis}
    assert fz.FZ_HEDGES == {h: rec.word for h, rec in ops.HEDGES.items() if h != Hedge.NONE}
    for _, field, words in fz.FZ_INFERENCE:
        table = {"and_": ops.T_NORMS, "or_": ops.S_NORMS, "implication": ops.IMPLICATIONS,
                 "aggregation": ops.AGGREGATIONS, "defuzzifier": ops.DEFUZZIFIERS}[field]
        assert words == {k: rec.word for k, rec in table.items()}


# -- the numpy functions by hand ----------------------------------------------------------

T_HAND = {   # at (a, b) = (0.7, 0.6), and at (1, 0.6) / (0.3, 0.6) where a case changes
    TNorm.MIN: [(0.7, 0.6, 0.6)],
    TNorm.PRODUCT: [(0.7, 0.6, 0.42)],                                  # 0.7 * 0.6
    TNorm.BOUNDED_DIFFERENCE: [(0.7, 0.6, 0.3), (0.3, 0.6, 0.0)],       # max(0, a + b - 1)
    TNorm.DRASTIC_PRODUCT: [(0.7, 0.6, 0.0), (1.0, 0.6, 0.6)],          # min if max = 1, else 0
    TNorm.EINSTEIN_PRODUCT: [(0.7, 0.6, 0.375)],                        # 0.42 / (2 - 0.88)
    TNorm.HAMACHER_PRODUCT: [(0.7, 0.6, 0.42 / 0.88), (0.0, 0.0, 0.0)],  # ab / (a + b - ab)
    TNorm.NILPOTENT_MIN: [(0.7, 0.6, 0.6), (0.3, 0.6, 0.0)],            # min if a + b > 1
}
S_HAND = {   # at (a, b) = (0.3, 0.6), and elsewhere where a case changes
    SNorm.MAX: [(0.3, 0.6, 0.6)],
    SNorm.PROBSUM: [(0.3, 0.6, 0.72)],                                  # 0.9 - 0.18
    SNorm.BOUNDED_SUM: [(0.3, 0.6, 0.9), (0.7, 0.6, 1.0)],              # min(1, a + b)
    SNorm.DRASTIC_SUM: [(0.3, 0.6, 1.0), (0.0, 0.6, 0.6)],              # max if min = 0, else 1
    SNorm.EINSTEIN_SUM: [(0.3, 0.6, 0.9 / 1.18)],                       # (a + b) / (1 + ab)
    SNorm.HAMACHER_SUM: [(0.3, 0.6, 0.54 / 0.82), (1.0, 1.0, 1.0)],     # (a+b-2ab) / (1-ab)
    SNorm.NILPOTENT_MAX: [(0.3, 0.6, 0.6), (0.7, 0.6, 1.0)],            # max if a + b < 1
    SNorm.UNBOUNDED_SUM: [(0.3, 0.6, 0.9), (0.7, 0.6, 1.3)],            # a + b, unbounded
}
HEDGE_HAND = [   # (hedge, mu, hedged)
    (Hedge.NONE, 0.3, 0.3),
    (Hedge.VERY, 0.5, 0.25),                # 0.5^2
    (Hedge.SOMEWHAT, 0.25, 0.5),            # sqrt(0.25)
    (Hedge.EXTREMELY, 0.5, 0.125),          # 0.5^3
    (Hedge.SELDOM, 0.08, 0.2),              # sqrt(0.08 / 2)
    (Hedge.SELDOM, 0.92, 0.8),              # 1 - sqrt(0.08 / 2)
    (Hedge.SHARPLY, 0.25, 0.125),           # 2 * 0.25^2
    (Hedge.SHARPLY, 0.75, 0.875),           # 1 - 2 * 0.25^2
]
AGGREGATION_HAND = {   # two rules at 0.5 and 0.4
    Aggregation.MAX: 0.5, Aggregation.SUM: 0.9,
    Aggregation.PROBSUM: 0.7,               # 0.9 - 0.2
    Aggregation.BOUNDED_SUM: 0.9,           # min(1, 0.9)
    Aggregation.DRASTIC_SUM: 1.0,           # min(a, b) > 0
    Aggregation.EINSTEIN_SUM: 0.75,         # 0.9 / 1.2
    Aggregation.HAMACHER_SUM: 0.625,        # (0.9 - 0.4) / (1 - 0.2)
    Aggregation.NILPOTENT_MAX: 0.5,         # a + b < 1: max
}


@pytest.mark.parametrize("norm", list(TNorm))
def test_t_norm_by_hand_and_laws(norm):
    f = ops.T_NORMS[norm].numpy
    for a, b, expected in T_HAND[norm]:
        assert f(np.array([a]), np.array([b]))[0] == pytest.approx(expected, abs=1e-15)
    np.testing.assert_allclose(f(A, np.ones_like(A)), A, atol=LAW_TOLERANCE)   # 1: identity
    np.testing.assert_allclose(f(np.ones_like(A), A), A, atol=LAW_TOLERANCE)
    assert np.all(f(A, np.zeros_like(A)) == 0.0)                            # 0 annihilates
    np.testing.assert_allclose(f(A, B), f(B, A), atol=LAW_TOLERANCE)         # commutative
    assert np.all(f(A, B) <= np.minimum(A, B) + LAW_TOLERANCE)               # below min
    _check_monotone(f, ops.T_NORMS[norm].monotone)


@pytest.mark.parametrize("norm", list(SNorm))
def test_s_norm_by_hand_and_laws(norm):
    f = ops.S_NORMS[norm].numpy
    for a, b, expected in S_HAND[norm]:
        assert f(np.array([a]), np.array([b]))[0] == pytest.approx(expected, abs=1e-15)
    np.testing.assert_allclose(f(A, np.zeros_like(A)), A, atol=LAW_TOLERANCE)  # 0: identity
    np.testing.assert_allclose(f(np.zeros_like(A), A), A, atol=LAW_TOLERANCE)
    if norm != SNorm.UNBOUNDED_SUM:     # fuzzylite's a + b is no s-norm: 1 does not absorb
        np.testing.assert_allclose(f(A, np.ones_like(A)), 1.0, atol=LAW_TOLERANCE)
    np.testing.assert_allclose(f(A, B), f(B, A), atol=LAW_TOLERANCE)
    assert np.all(f(A, B) >= np.maximum(A, B) - LAW_TOLERANCE)               # above max
    _check_monotone(f, ops.S_NORMS[norm].monotone)


def _check_monotone(f, claimed: bool) -> None:
    """Raising either argument never lowers f (what reach/rulebase.py relies on)."""
    assert claimed
    up = np.minimum(A + RNG.uniform(0, 0.3, A.shape), 1.0)
    assert np.all(f(up, B) >= f(A, B) - LAW_TOLERANCE)
    assert np.all(f(B, up) >= f(B, A) - LAW_TOLERANCE)


@pytest.mark.parametrize("hedge, mu, expected", HEDGE_HAND)
def test_hedge_by_hand_record_and_engine(hedge, mu, expected):
    rec = ops.HEDGES[hedge]
    if rec.numpy is not None:
        assert rec.numpy(np.array([mu]))[0] == pytest.approx(expected, abs=1e-15)
    engine = apply_hedges(np.array([[mu]]), np.array([int(hedge)]))[0, 0]
    assert engine == pytest.approx(expected, abs=1e-15)


@pytest.mark.parametrize("hedge", list(Hedge))
def test_hedge_monotone_and_engine_uses_the_record(hedge):
    rec = ops.HEDGES[hedge]
    mu = np.sort(A)
    got = apply_hedges(mu[:, None], np.array([int(hedge)]))[:, 0]
    assert rec.monotone and np.all(np.diff(got) >= 0)
    if rec.exponent is not None:     # a power hedge: the engine's exponent is the record's
        assert HEDGE_EXPONENT[int(hedge)] == rec.exponent
        np.testing.assert_allclose(got, mu ** rec.exponent, rtol=1e-15)
    else:                            # piecewise: the record's own function, bit for bit
        assert int(hedge) >= len(HEDGE_EXPONENT)
        assert np.array_equal(got, rec.numpy(mu))


@pytest.mark.parametrize("aggregation", list(Aggregation))
def test_aggregation_by_hand_and_engine(aggregation):
    rec = ops.AGGREGATIONS[aggregation]
    assert rec.numpy(np.array([0.5]), np.array([0.4]))[0] == \
        pytest.approx(AGGREGATION_HAND[aggregation], abs=1e-15)
    assert rec.snorm == aggregation_snorm(aggregation)
    _check_monotone(rec.numpy, rec.monotone)
    # the engine's term strengths: the record's function folded over the rules of each term
    act = RNG.uniform(0, 1, (200, 5))
    J = np.array([0, 1, 0, 0, 1])
    got = term_strengths(act, J, 2, aggregation)
    for term in range(2):
        cols = act[:, J == term]
        folded = cols[:, 0]
        for c in range(1, cols.shape[1]):
            folded = rec.numpy(folded, cols[:, c])
        np.testing.assert_allclose(got[:, term], folded, rtol=1e-12, atol=1e-15)


def test_defuzzifiers_by_hand():
    d = ops.DEFUZZIFIERS
    tri = (np.array([[0.0, 1.0, 2.0]]), np.array([[0.0, 1.0, 0.0]]))
    ramp = (np.array([[0.0, 3.0]]), np.array([[0.0, 1.0]]))
    plateau = (np.array([[0.0, 1.0, 2.0, 3.0]]), np.array([[0.0, 1.0, 1.0, 0.0]]))
    assert d[Defuzzifier.CENTROID].numpy(*tri, 9.0)[0] == pytest.approx(1.0)
    assert d[Defuzzifier.CENTROID].numpy(*ramp, 9.0)[0] == pytest.approx(2.0)   # 2/3 of 3
    # half of the ramp's area 3/2 lies left of u where u^2 / 6 = 3/4: u = sqrt(4.5)
    assert d[Defuzzifier.BISECTOR].numpy(*ramp, 9.0)[0] == pytest.approx(np.sqrt(4.5))
    assert d[Defuzzifier.MEAN_OF_MAXIMUM].numpy(*plateau, 9.0)[0] == pytest.approx(1.5)
    empty = (np.array([[0.0, 1.0]]), np.array([[0.0, 0.0]]))
    for method in (Defuzzifier.CENTROID, Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM):
        assert d[method].numpy(*empty, 9.0)[0] == 9.0                  # nothing: the default
    # strengths 0.5 and 0.25 at peaks 1 and -1: num = 0.25, den = 0.75
    num, den = np.array([0.25, 0.0]), np.array([0.75, 0.0])
    for method in (Defuzzifier.CENTER_OF_AREA, Defuzzifier.WEIGHTED_AVERAGE,
                   Defuzzifier.TSUKAMOTO):
        np.testing.assert_allclose(d[method].numpy(num, den, 9.0), [1 / 3, 9.0])
    for method in (Defuzzifier.WEIGHTED_SUM, Defuzzifier.GROUPED_SUM, Defuzzifier.TSUKAMOTO_SUM):
        np.testing.assert_allclose(d[method].numpy(num, den, 9.0), [0.25, 9.0])


def test_defuzzifiers_are_not_monotone_in_the_strengths():
    """The records say so: raising the strength of the term at -1 lowers the output."""
    assert not any(rec.monotone for rec in ops.DEFUZZIFIERS.values())
    ratio = ops.DEFUZZIFIERS[Defuzzifier.CENTER_OF_AREA].numpy
    z = np.array([1.0, -1.0])
    low, high = (ratio(np.array([a @ z]), np.array([a.sum()]), 0.0)[0]
                 for a in (np.array([0.5, 0.25]), np.array([0.5, 0.5])))
    assert high < low


# -- the C back end: every record with a C text against the engine, the others refused ------

TINY = """controller ops "one operator at a time" {{
  input a in [0, 1]
  input b in [0, 1]
  terms a, b : uniform L M H over [0, 1]
  var y in [-1, 1] default 0.1
  terms y : {terms}
  inference and = {and_}, or = {or_}, implication = {imp}, aggregation = {agg}, defuzzify = {d}
  rule if a is {h}L and b is H then y is L
  rule if a is M {conn} b is {h}M then y is M
  rule if a is {neg}{h}H {conn} b is L then y is H
  rule if a is H and b is {h}M then y is M
  output y_out in [-1, 1] = y
}}
"""
TRIANGLES = "L = tri(-1, -0.5, 0), M = tri(-0.5, 0, 0.5), H = tri(0, 0.5, 1)"
SINGLETONS = "singletons L=-0.8 M=0.1 H=0.7"


def tiny(and_="min", or_="max", imp="min", agg="max", d="centroid", h="", conn="and",
         neg="not "):
    terms = SINGLETONS if d in ("center_of_area", "weighted_average", "weighted_sum", "tsukamoto",
                                "grouped_sum", "tsukamoto_sum") else TRIANGLES
    return parse(TINY.format(terms=terms, and_=and_, or_=or_, imp=imp, agg=agg, d=d,
                             h=f"{h} " if h else "", conn=conn, neg=neg))


def _c_against_engine(model) -> None:
    x = RNG.uniform(-0.05, 1.05, (4000, 2))
    got = CController(model).evaluate(x)[:, 0]
    want = evaluate(model.rulebase, x)[:, 0]
    np.testing.assert_allclose(got, want, atol=1e-5 * 2)     # float C: 1e-5 of the range 2


def _refused(model, word: str) -> None:
    with pytest.raises(FuzzycError, match=rf"\b{word}\b"):
        generate_header(model, "float")


CASES = ([("and", t, dict(and_=rec.word, conn="and")) for t, rec in ops.T_NORMS.items()]
         + [("or", s, dict(or_=rec.word, conn="or")) for s, rec in ops.S_NORMS.items()]
         + [("hedge", h, dict(h=rec.word if h != Hedge.NONE else "", conn="or",
                              and_="product", or_="probsum"))
            for h, rec in ops.HEDGES.items()]
         + [("aggregation", a, dict(agg=rec.word, d="center_of_area"))
            for a, rec in ops.AGGREGATIONS.items()]
         + [("defuzzify", d, dict(d=rec.word, and_="product"))
            for d, rec in ops.DEFUZZIFIERS.items()])


@pytest.mark.parametrize("kind, member, words", CASES,
                         ids=[f"{k}-{m.name.lower()}" for k, m, _ in CASES])
def test_c_emits_each_record_with_a_c_text_and_refuses_the_others(kind, member, words):
    rec = ops.REGISTRIES[kind][member]
    model = tiny(**words)
    if rec.c_float is None:
        _refused(model, rec.word)
    else:
        _c_against_engine(model)


def test_the_c_allow_lists_are_the_records():
    from fuzzyc.backends.c import header
    assert header.C_TNORMS == (TNorm.MIN, TNorm.PRODUCT)
    assert header.C_SNORMS == (SNorm.MAX, SNorm.PROBSUM)
    assert header.C_HEDGES == (Hedge.NONE, Hedge.VERY, Hedge.SOMEWHAT, Hedge.EXTREMELY)
    assert header.C_AGGREGATIONS == (Aggregation.MAX, Aggregation.SUM)
    for table, allowed in ((ops.T_NORMS, header.C_TNORMS), (ops.S_NORMS, header.C_SNORMS),
                           (ops.HEDGES, header.C_HEDGES),
                           (ops.AGGREGATIONS, header.C_AGGREGATIONS)):
        assert set(allowed) == {k for k, rec in table.items() if rec.c_float is not None}


def test_the_c_texts_are_what_the_header_writes():
    text = generate_header(tiny(and_="product", or_="probsum", h="very", conn="or"), "float")
    # or = probsum "({a} + {b} - {a} * {b})", and = product "{a} * {b}", per rule
    assert "act = ops_fired((OPS_IS_OR[r] ? (g0 + g1 - g0 * g1) : g0 * g1));" in text
    assert "hedge == 1 ? mu * mu : (hedge == 2 ? sqrtf(mu) : (hedge == 3 ? mu * mu * mu : mu))" \
        in text
    text = generate_header(tiny(and_="min", or_="max", h="very", conn="or"), "double")
    assert "act = ops_fired((OPS_IS_OR[r] ? ops_greater(g0, g1) : ops_lesser(g0, g1)));" in text
    assert "(hedge == 2 ? sqrt(mu) :" in text


@pytest.mark.parametrize("numeric", ["q15", "q31"])
def test_fixed_point_refuses_by_name(numeric):
    for t, rec in ops.T_NORMS.items():
        if rec.c_float is not None and rec.fixed is None:     # none today; kept honest
            with pytest.raises(FuzzycError, match=rec.word):
                generate_fixed_header(tiny(and_=rec.word, d="center_of_area", neg=""),
                                      numeric)
    with pytest.raises(FuzzycError, match="einstein_product"):       # no C text at all
        generate_fixed_header(tiny(and_="einstein_product", d="center_of_area", neg=""),
                              numeric)
    for d, rec in ops.DEFUZZIFIERS.items():
        if rec.c_float is not None and rec.fixed is None:
            with pytest.raises(FuzzycError, match=f"`{rec.word}` is not supported"):
                generate_fixed_header(tiny(d=rec.word, neg=""), numeric)
    text = generate_fixed_header(tiny(and_="product", d="center_of_area", neg=""), numeric)
    assert f"int64_t act = ops_{numeric}_product(" in text      # the record's helper
    # max: the record's (one rule per cell: the consequents tabled per cell)
    assert f"alpha0[OPS_{numeric.upper()}_CELL_CONSEQUENTS[cell][0]] = " in text


def test_monotone_claims_cover_what_reach_relies_on():
    """reach/rulebase.py bounds activations and strengths through the engine's own code: every
    norm, hedge and aggregation must be monotone (defuzzifiers it treats on its own)."""
    for table in (ops.T_NORMS, ops.S_NORMS, ops.HEDGES, ops.AGGREGATIONS):
        assert all(rec.monotone for rec in table.values())


def test_crisp_functions_are_the_engines():
    """The engine's defuzzification calls the records' functions (a centroid of two points)."""
    assert ops.DEFUZZIFIERS[Defuzzifier.CENTROID].numpy is crisp.centroid
    model = tiny(d="centroid")
    x = np.array([[0.0, 1.0]])     # rule 1 alone: a = L at 1, b = H at 1 -> y is L (symmetric)
    assert evaluate(model.rulebase, x)[0, 0] == pytest.approx(-0.5)
