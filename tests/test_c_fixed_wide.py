"""Wide rule bases (7 to 10 inputs) in the q15/q31 headers (issue 14): the float header's cell
table (`fuzzyc.backends.c.cells`, a code per tuple of terms, + 1 where a rule has `*`),
direct up to MAX_C_TABLE_CELLS cells and by binary search among the occupied cells' codes past
that; a call visits the 2**I combinations of active terms (3 per input with `*`).  Against the
engine at the dequantized input within the stated bound ERROR_BOUND and the derived one, on
random inputs on the fixed-point grid, the ends of every range and every break point; inputs
below the scale saturate to 0; two points computed by hand."""
from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable
from typing import NamedTuple

import numpy as np
import pytest

from fuzzyc.backends.c_fixed.header import (ERROR_BOUND, FORMATS, FixedPointWriter,
                                     derived_error_bound, generate_fixed_header)
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.semantics.model import Aggregation, Defuzzifier, Inference, Model, TNorm

from test_c_fixed import fixed_point_runner
from test_engine_wide import rulebase

COA = Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA)


def full_grid(n_in: int, n_terms: int = 3, inference: Inference = COA) -> Model:
    """Rules on every tuple of the first 3 terms of each input (3**I rules), y in [0, 10]
    the singleton lo 0, mid 5, hi 10 of (sum of the term ids) mod 3 (test_engine_wide)."""
    rb = rulebase(n_in, n_terms, itertools.product(range(3), repeat=n_in), inference)
    return Model.of_rulebase(rb, f"wide{n_in}")


PRODUCT_SUM = Inference(and_=TNorm.PRODUCT, aggregation=Aggregation.SUM,
                        defuzzifier=Defuzzifier.WEIGHTED_AVERAGE)


def with_wildcards(n_in: int, inference: Inference = COA) -> Model:
    """The full grid with its first 3**(I-1) / 2 rules' last input left open (`*`): those
    rules then fire over the last input's every term, the rest of the grid's rules beside
    them."""
    model = full_grid(n_in, inference=inference)
    rb = model.rulebase
    rb.antecedents[: 3 ** (n_in - 1) // 2, -1] = -1
    return model


def fourth_term_open(n_in: int) -> Model:
    """Inputs of 4 terms: the grid of the first 3 terms (3**I rules) and, per input, a rule
    `x_i is t3` with every other input `*` (3 -> y lo), so every tuple of terms has a rule:
    5**I codes (4 terms and `*`), 3**I + I occupied cells."""
    combos = [*itertools.product(range(3), repeat=n_in),
              *(tuple(3 if k == i else 0 for k in range(n_in)) for i in range(n_in))]
    rb = rulebase(n_in, 4, combos, COA)
    for i in range(n_in):
        rb.antecedents[3 ** n_in + i, np.arange(n_in) != i] = -1
    return Model.of_rulebase(rb, f"open{n_in}")


class Case(NamedTuple):
    build: Callable[[], Model]
    table: str                   # the header's cell table: direct or sorted codes
    derived: bool                # whether the header derives its error bound
    formats: Iterable[str]       # the numeric formats that take it
    samples: int = 20_000        # random inputs


CASES = {
    "7 inputs": Case(lambda: full_grid(7), "direct", True, FORMATS),
    "10 inputs": Case(lambda: full_grid(10), "direct", True, FORMATS),
    # 4**9 = 262,144 codes, past MAX_C_TABLE_CELLS: the 3**9 = 19,683 occupied cells found by
    # binary search.  Not derived: no rule covers a tuple with a t3 (the default 0 there).
    "9 inputs of 4 terms": Case(lambda: full_grid(9, 4), "sorted codes", False, FORMATS),
    # 5**8 = 390,625 codes (`*` on every input): 6,569 occupied cells by search, 3**8 = 6,561
    # combinations a call (fewer samples); every tuple of terms has a rule: derived
    "8 inputs of 4 terms, t3 with *": Case(lambda: fourth_term_open(8), "sorted codes", True,
                                           FORMATS, 2_000),
    # `*` on the last input: 2**6 * 3 = 192 combinations, codes 3**6 * 4 = 2,916
    "7 inputs with *": Case(lambda: with_wildcards(7), "direct", True, FORMATS),
    # Not derived: the least activation a covering rule is sure of is the product of the
    # least top memberships, 0.5**7 = 0.0078, below the summed rounding D = eps_act * 192
    # combinations * 3 rules a cell (about 0.1 in q15).  q31 refuses it (below).
    "7 inputs with *, product, weighted average":
        Case(lambda: with_wildcards(7, PRODUCT_SUM), "direct", False, ["q15"]),
}


def grid_points(model: Model, numeric: str, n: int = 20_000) -> np.ndarray:
    """Random integer inputs, then every input alone at 0, FULL and each break point (the
    others random), and one row below the scale."""
    rb = model.rulebase
    full = FORMATS[numeric][1]
    rng = np.random.default_rng(len(rb.inputs))
    xq = rng.integers(0, full, (n, len(rb.inputs)), endpoint=True)
    edges = []
    for i, var in enumerate(rb.inputs):
        for b in [var.lo, var.hi, *np.unique(var.params)]:
            if var.lo <= b <= var.hi:
                row = rng.integers(0, full, len(rb.inputs), endpoint=True)
                row[i] = round((b - var.lo) / (var.hi - var.lo) * full)
                edges.append(row)
    return np.concatenate([xq, edges])


@pytest.mark.parametrize("case, numeric", [(case, numeric) for case in sorted(CASES)
                                           for numeric in sorted(CASES[case].formats)])
def test_wide_fixed_point_within_stated_bound(case, numeric):
    case = CASES[case]
    model = case.build()
    rb = model.rulebase
    cells = FixedPointWriter(model, numeric).tables.cells
    assert (cells.codes is None) == (case.table == "direct")
    full = FORMATS[numeric][1]
    xq = grid_points(model, numeric, case.samples)
    yq = fixed_point_runner(model, numeric)(xq)
    lo = np.array([v.lo for v in rb.inputs])
    hi = np.array([v.hi for v in rb.inputs])
    var = rb.outputs[0]
    expected = evaluate(rb, lo + xq / full * (hi - lo))[:, 0]
    error = np.abs(var.lo + yq[:, 0] / full * (var.hi - var.lo) - expected) / (var.hi - var.lo)
    assert error.max() <= ERROR_BOUND[numeric]
    bound = derived_error_bound(model, numeric)
    assert (bound is not None) == case.derived
    assert bound is None or error.max() <= bound[0]
    # not vacuous: the output moves over the sample
    assert np.ptp(expected) > 0.25 * (var.hi - var.lo)


def test_q31_refuses_summed_strengths_of_many_rules():
    # weighted average sums the strengths of up to 192 combinations x 3 rules in the deepest
    # cell (a prefix's three rules all made `*` on the last input) = 576 rules at 2^-28, times
    # a peak of up to 2^31 (0 guard bits): 576 * 2^28 * 2^31 = 2^68.2 > 2^63
    with pytest.raises(FuzzycError, match="576 rules x weight x peak x 2.28 exceeds 2.63"):
        generate_fixed_header(with_wildcards(7, PRODUCT_SUM), "q31")


@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_below_the_scale_saturates_to_zero(numeric):
    # as the float header clamps x to its outer break points: xq < 0 reads as 0 (an int16 or
    # int32 has no NaN, and nothing above FULL)
    model = full_grid(7)
    run = fixed_point_runner(model, numeric)
    xq = grid_points(model, numeric, 200)[:200]
    below = xq.copy()
    below[:, ::2] = -1000
    at_zero = xq.copy()
    at_zero[:, ::2] = 0
    np.testing.assert_array_equal(run(below), run(at_zero))


@pytest.mark.parametrize("n_in", [7, 10])
def test_wide_fixed_point_hand_computed(n_in):
    # Inputs 0..I-2 at 0 (xq = 0): term t0 alone at membership 1 (the other slot reads t0 at
    # 0).  The last input at xq = 8192 of 32767: x = 0.2500076, t0 = 1 - 2x = 0.4999847,
    # t1 = 2x = 0.5000153.  Two rules fire: all t0 (sum of ids 0 -> lo = 0) at
    # min(1, ..., 0.4999847) and all t0 but t1 last (sum 1 -> mid = 5) at 0.5000153, so
    # y = (0.4999847 * 0 + 0.5000153 * 5) / 1 = 2.5000763 of [0, 10]:
    # yq = 0.25000763 * 32767 = 8192.0.  q31: xq = round(0.25 * (2**31 - 1)) = 536870912,
    # x = 0.25 + 1e-10, y = 2.5, yq = 0.25 * 2147483647 = 536870911.75 -> 536870912.
    model = full_grid(n_in)
    for numeric, last, expected in (("q15", 8192, 8192), ("q31", 536870912, 536870912)):
        got = fixed_point_runner(model, numeric)([[0] * (n_in - 1) + [last]])[0, 0]
        assert abs(int(got) - expected) <= 1, numeric
