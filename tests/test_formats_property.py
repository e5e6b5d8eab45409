"""Random rule bases survive every writer -> reader pair unchanged (hypothesis): term shapes,
hedges, negations, wildcards, weights, connectives and the inference choices.  FIS keeps what a
.fis file carries (see test_formats_roundtrip.same_rulebase_fis) and the same outputs."""
from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from fuzzyc.language.builder import RuleSpec
from fuzzyc.errors import Reporter
from fuzzyc.engine.inference import evaluate
from fuzzyc.formats import (read_fcl, read_fis, read_fll, write_fcl, write_fis, write_fll,
                            write_fz)
from fuzzyc.formats.common import Collected, TermSpec, VarSpec
from fuzzyc.semantics.model import (Aggregation, Connective, Defuzzifier, Hedge, Implication, Inference,
                          SNorm, TermKind, TNorm)
from fuzzyc.language.parser import parse

from test_formats_roundtrip import same_rulebase, same_rulebase_fis

INF = math.inf
grid = st.integers(0, 20).map(lambda k: k / 2)     # break points on [0, 10], exactly readable
AREA = [Defuzzifier.CENTROID, Defuzzifier.BISECTOR, Defuzzifier.MEAN_OF_MAXIMUM]


@st.composite
def input_term(draw, fmt: str):
    kind = draw(st.sampled_from(["tri", "trap", "left", "right", "gauss", "bell", "sigmoid"]))
    p = sorted(draw(st.lists(grid, min_size=4, max_size=4)))
    if kind == "tri" and p[0] < p[3]:
        return TermKind.TRAPEZOID, (p[0], p[1], p[1], p[3])
    if kind == "trap" and p[0] < p[3]:
        return TermKind.TRAPEZOID, tuple(p)
    if kind == "left" and p[2] < p[3]:
        return TermKind.TRAPEZOID, (-INF, -INF, p[2], p[3])
    if kind == "right" and p[0] < p[1]:
        return TermKind.TRAPEZOID, (p[0], p[1], INF, INF)
    if kind == "gauss":
        return TermKind.GAUSSIAN, (p[1], 0.5 + p[0], 0.0, 0.0)
    if kind == "bell":
        return TermKind.BELL, (p[1], 0.5 + p[0], 1.0 + p[2], 0.0)
    if kind == "sigmoid":
        return TermKind.SIGMOID, (p[1], draw(st.sampled_from([-4.0, -0.5, 2.0])), 0.0, 0.0)
    return TermKind.TRAPEZOID, (0.0, 5.0, 5.0, 10.0)


@st.composite
def rule_base(draw, fmt: str):
    rep = Reporter("<random>")
    got = Collected(rep, "random")
    n_in, n_out = draw(st.integers(1, 3)), draw(st.integers(1, 2))
    for i in range(n_in):
        var = got.declare(VarSpec(f"x{i}", None, 0.0, 10.0), True)
        for t in range(draw(st.integers(1, 4))):
            var.add(TermSpec(f"T{t}", *draw(input_term(fmt))), rep)
    defuzz = {"fz": list(Defuzzifier), "fll": [Defuzzifier.CENTER_OF_AREA, *AREA,
                                               Defuzzifier.WEIGHTED_AVERAGE,
                                               Defuzzifier.WEIGHTED_SUM],
              "fcl": [Defuzzifier.CENTER_OF_AREA, *AREA],
              "fis": [*AREA, Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM]}[fmt]
    # FCL (IEC 61131-7) names three t-norms and three s-norms, MATLAB two; the others name all
    tnorms, snorms = {"fcl": ([TNorm.MIN, TNorm.PRODUCT, TNorm.BOUNDED_DIFFERENCE],
                              [SNorm.MAX, SNorm.PROBSUM, SNorm.BOUNDED_SUM]),
                      "fis": ([TNorm.MIN, TNorm.PRODUCT], [SNorm.MAX, SNorm.PROBSUM])}.get(
        fmt, (list(TNorm), list(SNorm)))
    got.inference = Inference(draw(st.sampled_from(tnorms)), draw(st.sampled_from(snorms)),
                              draw(st.sampled_from([Implication.MIN, Implication.PRODUCT]
                                                   if fmt == "fis" else list(Implication))),
                              Aggregation.MAX, draw(st.sampled_from(defuzz)))
    # FLL says center of area with a sum as WeightedAverage, which reads back as a weighted
    # average: the same numbers, another enum (test_formats_roundtrip compares those outputs).
    # MATLAB has max, sum and probor only (FIS export refuses the others)
    aggregations = [a for a in Aggregation if fmt != "fis" or a in (
        Aggregation.MAX, Aggregation.SUM, Aggregation.PROBSUM)]
    if fmt in ("fz", "fis") or got.inference.defuzzifier in AREA or (
            got.inference.defuzzifier == Defuzzifier.CENTER_OF_AREA and fmt == "fcl"):
        got.inference.aggregation = draw(st.sampled_from(aggregations))
    elif got.inference.defuzzifier == Defuzzifier.CENTER_OF_AREA and fmt == "fll":
        # WeightedAverage grouped by an s-norm reads back as the center of area
        got.inference.aggregation = draw(st.sampled_from(
            [Aggregation.MAX, Aggregation.PROBSUM, Aggregation.BOUNDED_SUM]))
    for o in range(n_out):
        # a .fis output's default is MATLAB's middle of the range
        default = 5.0 if fmt == "fis" else draw(grid)
        var = got.declare(VarSpec(f"y{o}", None, 0.0, 10.0, default=default), False)
        for t in range(draw(st.integers(1, 4))):
            if got.inference.defuzzifier in AREA:   # integrals need terms with an area
                var.add(TermSpec(f"S{t}", *draw(input_term(fmt))), rep)
            else:
                var.add(TermSpec(f"S{t}", TermKind.SINGLETON, (draw(grid), 0.0, 0.0, 0.0)), rep)
    hedges = {"fz": list(Hedge), "fll": [Hedge.NONE, Hedge.VERY, Hedge.SOMEWHAT],
              "fcl": [Hedge.NONE], "fis": [Hedge.NONE, Hedge.VERY, Hedge.SOMEWHAT,
                                            Hedge.EXTREMELY]}[fmt]
    for _ in range(draw(st.integers(1, 6))):
        clauses = {}
        for name, var in got.inputs.items():
            if draw(st.booleans()) or not clauses and name == list(got.inputs)[-1]:
                clauses[name] = (draw(st.integers(0, len(var.terms) - 1)), draw(st.booleans()),
                                 draw(st.sampled_from(hedges)))
        target = draw(st.sampled_from(list(got.outputs)))
        conclusions = {target: draw(st.integers(0, len(got.outputs[target].terms) - 1))}
        # one clause has no connective: every front end reads it as `and`
        connective = draw(st.sampled_from(list(Connective))) if len(clauses) > 1 \
            else Connective.AND
        got.rules.append(RuleSpec(clauses, connective, conclusions,
                               draw(st.sampled_from([1.0, 0.5, 0.25])), None, "random"))
    return got.model("<random>", "")


@settings(max_examples=40, deadline=None)
@given(rule_base("fz"))
def test_fz_round_trip(model):
    same_rulebase(model.rulebase, parse(write_fz(model), "random.fz").rulebase)


@settings(max_examples=40, deadline=None)
@given(rule_base("fll"))
def test_fll_round_trip(model):
    same_rulebase(model.rulebase, read_fll(write_fll(model), "random.fll").rulebase)


@settings(max_examples=40, deadline=None)
@given(rule_base("fcl"))
def test_fcl_round_trip(model):
    back = read_fcl(write_fcl(model), "random.fcl").rulebase
    same_rulebase(model.rulebase, back)
    assert np.array_equal(back.inputs[0].params, model.rulebase.inputs[0].params)


@settings(max_examples=40, deadline=None)
@given(rule_base("fis"))
def test_fis_round_trip(model):
    rb = model.rulebase
    back = read_fis(write_fis(model), "random.fis").rulebase
    same_rulebase_fis(rb, back)
    assert back.inference.defuzzifier == rb.inference.defuzzifier
    if rb.inference.defuzzifier in AREA:      # Mamdani: the file keeps every choice
        assert back.inference == rb.inference
    x = np.stack(np.meshgrid(*[np.linspace(0.0, 10.0, 11)] * len(rb.inputs)), -1)
    x = x.reshape(-1, len(rb.inputs))
    np.testing.assert_allclose(evaluate(back, x), evaluate(rb, x), rtol=0, atol=1e-12)
