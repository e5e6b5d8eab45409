"""Wide rule bases (more than 6 inputs) stay on the sparse path: a sample fires at most 2**I
term tuples, looked up in a direct cell table or, where that table would be too big, among the
rules' sorted cell codes.  Both agree with the dense reference; a hand-computed 7-input value;
the C back end keeps its cell table (direct up to 10 inputs of 3 terms, sorted codes past
that) and loops over every rule past its limit.  Past the grid's per-cell tables the grid path
tables columns per term tuple: the same bits as the sparse candidates' scatter and as
the per-cell tables, and the dense reference's values, on random wide rule bases."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from fuzzyc.engine import strength_grid as grid
from fuzzyc.backends.c.header import HeaderWriter
from fuzzyc.backends.c.expressions import REAL_TYPES
from fuzzyc.backends.c.load import CController
from fuzzyc.language.builder import RuleSpec, assemble_rulebase
from fuzzyc.engine.defuzz import term_strengths
from fuzzyc.engine.inference import MAX_LOOKUP_CELLS, CompiledRuleBase, evaluate
from fuzzyc.semantics.model import (Aggregation, Connective, Defuzzifier, Hedge, Implication, Inference,
                          Model, SourceLoc, TermKind, TNorm, Variable)

LOC = SourceLoc("wide", 0, 0)


def partition(name: str, n_terms: int) -> Variable:
    """n_terms uniform triangles on [0, 1] (shoulders cut by the range)."""
    peaks = np.linspace(0, 1, n_terms)
    h = peaks[1] - peaks[0]
    return Variable(name, 0.0, 1.0, [f"t{k}" for k in range(n_terms)],
                    np.full(n_terms, int(TermKind.TRAPEZOID)),
                    np.stack([peaks - h, peaks, peaks, peaks + h], axis=1))


def rulebase(n_in: int, n_terms: int, combos, inference: Inference):
    inputs = [partition(f"x{i}", n_terms) for i in range(n_in)]
    out = Variable("y", 0.0, 10.0, ["lo", "mid", "hi"], np.full(3, int(TermKind.SINGLETON)),
                   np.array([[0.0, 0, 0, 0], [5.0, 0, 0, 0], [10.0, 0, 0, 0]]))
    rules = [RuleSpec({f"x{i}": (int(t), False, Hedge.NONE) for i, t in enumerate(combo)},
                      Connective.AND, {"y": int(sum(combo)) % 3}, 1.0, LOC, "")
             for combo in combos]
    return assemble_rulebase(inputs, [out], rules, inference)


def points(n_in: int, n: int = 400) -> np.ndarray:
    rng = np.random.default_rng(n_in)
    x = rng.uniform(0, 1, (n, n_in))
    x[:20] = rng.choice([0.0, 0.5, 1.0], (20, n_in))     # exact break points
    x[20, 3] = np.nan
    return x


@pytest.mark.parametrize("inference", [
    Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA),
    Inference(and_=TNorm.PRODUCT, implication=Implication.PRODUCT, aggregation=Aggregation.SUM,
              defuzzifier=Defuzzifier.WEIGHTED_AVERAGE),
])
def test_seven_input_full_grid_is_sparse_and_equals_dense(inference):
    rb = rulebase(7, 3, itertools.product(range(3), repeat=7), inference)
    fast = CompiledRuleBase(rb)
    assert fast.sparse and fast.codes is None               # 4**7 cells: a direct table
    assert fast.grid is not None and fast.grid.columns is None     # tables per term tuple
    x = points(7)
    np.testing.assert_allclose(fast.evaluate_chunk(x),
                               CompiledRuleBase(rb, allow_sparse=False).evaluate_chunk(x),
                               rtol=0, atol=1e-12)


def test_sorted_codes_beyond_the_direct_table_equal_dense():
    rng = np.random.default_rng(1)
    combos = {tuple(c) for c in rng.integers(0, 7, (600, 8))}   # 8**8 cells > MAX_LOOKUP_CELLS
    rb = rulebase(8, 7, sorted(combos), Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))
    assert 8 ** 8 > MAX_LOOKUP_CELLS
    fast = CompiledRuleBase(rb)
    assert fast.sparse and fast.codes is not None and fast.grid.columns is None
    x = points(8, 2000)
    np.testing.assert_allclose(fast.evaluate_chunk(x),
                               CompiledRuleBase(rb, allow_sparse=False).evaluate_chunk(x),
                               rtol=0, atol=1e-12)


def test_seven_inputs_by_hand():
    rb = rulebase(7, 3, itertools.product(range(3), repeat=7),
                  Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))
    # x0 = .25: t0 .5, t1 .5; the other six at 0: t0 1.  Two rules fire at min .5:
    # (0,0,...) sum 0 -> lo, (1,0,...) sum 1 -> mid; (.5*0 + .5*5) / (.5 + .5) = 2.5
    assert evaluate(rb, [[0.25] + [0.0] * 6])[0, 0] == pytest.approx(2.5, abs=1e-12)


WIDE_INFERENCES = [
    Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA),                           # min, max
    Inference(and_=TNorm.PRODUCT, aggregation=Aggregation.PROBSUM,
              defuzzifier=Defuzzifier.CENTER_OF_AREA),
    Inference(and_=TNorm.PRODUCT, implication=Implication.PRODUCT, aggregation=Aggregation.SUM,
              defuzzifier=Defuzzifier.CENTROID),
    Inference(aggregation=Aggregation.SUM, defuzzifier=Defuzzifier.WEIGHTED_AVERAGE),
    Inference(defuzzifier=Defuzzifier.CENTROID),                                  # min, max
]


def random_wide(n_in: int, inference: Inference, seed: int):
    """Random rules over 3-4 term partitions: repeated premises (lookup depth > 1), weights
    in (0, 1], two triangle outputs, one rule in five silent about the second."""
    rng = np.random.default_rng(seed)
    inputs = [partition(f"x{i}", int(rng.integers(3, 5))) for i in range(n_in)]
    outputs = [Variable(name, 0.0, 10.0, ["lo", "mid", "hi"], np.full(3, int(TermKind.TRAPEZOID)),
                        np.array([[-5.0, 0, 0, 5], [0, 5, 5, 10], [5, 10, 10, 15]]))
               for name in ("y", "z")]
    premises = [tuple(int(rng.integers(0, v.n_terms)) for v in inputs) for _ in range(700)]
    premises += premises[:60]
    rules = [RuleSpec({f"x{i}": (t, False, Hedge.NONE) for i, t in enumerate(premise)},
                      Connective.AND,
                      {"y": int(rng.integers(0, 3))} | ({"z": int(rng.integers(0, 3))}
                                                        if rng.random() < 0.8 else {}),
                      float(rng.uniform(0.05, 1.0)), LOC, "")
             for premise in premises]
    return assemble_rulebase(inputs, outputs, rules, inference)


@pytest.mark.parametrize("inference", WIDE_INFERENCES)
@pytest.mark.parametrize("n_in", [7, 9])
def test_tuple_tables_equal_the_sparse_scatter_and_dense(inference, n_in):
    rb = random_wide(n_in, inference, seed=n_in)
    fast = CompiledRuleBase(rb)
    assert fast.grid is not None and fast.grid.columns is None and fast.lookup.shape[1] > 1
    x = points(n_in, 600)
    x[21] = np.inf
    x[22, 1] = -np.inf
    # term strengths: the very bits of the sparse path's candidates and scatter
    act, rid = fast.candidates(x)
    alpha = fast.grid(x)
    for o, d in enumerate(fast.defuzzifiers):
        expected = term_strengths(act, fast.consequents[rid, o], 3, d.strength_aggregation())
        np.testing.assert_array_equal(alpha[fast.grid.slices[o]].T, expected)
    # outputs: the dense reference's values (it aggregates in rule order, hence not bit for
    # bit).  Probsum's 1 - prod(1 - a) keeps only the top digits of a small strength (a product
    # of 9 memberships near 1e-5 keeps ~11 of its 16 in 1 - a), so there the two orders agree
    # to ~1e-11 of the output range [0, 10], not to the last bits.
    atol = 1e-9 if inference.aggregation == Aggregation.PROBSUM else 1e-12
    np.testing.assert_allclose(fast.evaluate_chunk(x),
                               CompiledRuleBase(rb, allow_sparse=False).evaluate_chunk(x),
                               rtol=0, atol=atol)


@pytest.mark.parametrize("inference", WIDE_INFERENCES[:3])
def test_tuple_tables_equal_the_per_cell_tables(inference, monkeypatch):
    rb = random_wide(4, inference, seed=4)
    per_cell = CompiledRuleBase(rb)
    monkeypatch.setattr(grid, "MAX_TABLE_ENTRIES", 0)     # nothing fits: tables per tuple
    per_tuple = CompiledRuleBase(rb)
    assert per_cell.grid.columns is not None and per_tuple.grid.columns is None
    x = points(4, 600)
    np.testing.assert_array_equal(per_tuple.grid(x), per_cell.grid(x))
    np.testing.assert_array_equal(per_tuple.evaluate_rows(np.ascontiguousarray(x.T)),
                                  per_cell.evaluate_chunk(x).T)


def test_few_rules_over_many_inputs_stay_dense():
    # 2**9 = 512 candidates per sample would exceed the 20 rules: every rule is cheaper
    rb = rulebase(9, 3, [tuple([k % 3] * 9) for k in range(20)],
                  Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))
    assert not CompiledRuleBase(rb).sparse


@pytest.mark.parametrize("n_in, n_terms, sorted_codes", [
    (7, 3, False), (8, 3, False), (9, 3, False), (10, 3, False), (9, 4, True)])
def test_c_header_takes_the_cell_table(n_in, n_terms, sorted_codes):
    # issue 14: past 6 inputs the header looped over every rule (4.1 us per call at 7 inputs,
    # 14 us at 8, 42 us at 9). The cell table has a code per tuple of terms, 3**I for I inputs
    # of 3 terms (a slot without a term reads term 0 at membership 0): direct up to 10 inputs
    # (59,049 cells, within fuzzyc.language.limits.MAX_C_TABLE_CELLS). 9 inputs of 4 terms (262,144
    # cells) with rules on 3 of them keep the 3**9 = 19,683 occupied cells' codes and find a
    # tuple's row by binary search. A call visits the 2**I active term tuples either way; the
    # points include NaN and the outer break points (one term active) and every peak.
    rb = rulebase(n_in, n_terms, itertools.product(range(3), repeat=n_in),
                  Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))
    model = Model.of_rulebase(rb, "wide")
    writer = HeaderWriter(model, REAL_TYPES["float"])
    assert writer.sparse and (writer.cells.codes is not None) == sorted_codes
    assert writer.cells.rows.shape == ((3 ** n_in + 1, 1) if sorted_codes else (3 ** n_in, 1))
    x = points(n_in)
    x[21:40] = np.random.default_rng(1).choice(np.linspace(0, 1, n_terms), (19, n_in))
    got = CController(model, numeric="double").evaluate(x)
    assert np.max(np.abs(got - evaluate(rb, x))) <= 1e-12 * 10.0    # of the range [0, 10]


def test_c_header_keeps_every_rule_past_the_cell_limit():
    # 11 inputs: 3**11 = 177,147 occupied cells, more than MAX_C_TABLE_CELLS (gcc took 19 s
    # and 1.9 GB on a 1.8M-cell table, then refused it): every rule is looped over
    rb = rulebase(11, 3, itertools.product(range(3), repeat=11),
                  Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))
    assert not HeaderWriter(Model("wide", [rb]), REAL_TYPES["float"]).sparse
