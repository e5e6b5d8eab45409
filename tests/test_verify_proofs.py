"""Exact proofs on small rule bases whose answers are computed by hand."""
import numpy as np
import pytest

from fuzzyc.language.parser import parse
from fuzzyc.verifier import Options, Status, verify_model
from conftest import ROOT

ONE_INPUT = """controller t {
  input x in [0, 10]
  terms x : L = lshoulder(2, 6), H = rshoulder(4, 8)
  var y in [0, 1]
  terms y : singletons lo = 0 hi = 1
  rule if x is L then y is lo
  rule RULE2
  verify { PROPERTY }
}
"""


def _verify(rule2, prop):
    model = parse(ONE_INPUT.replace("RULE2", rule2).replace("PROPERTY", prop), "t.fz")
    (result,) = verify_model(model, Options(max_examples=10, grid_budget=2000))
    return result


# L >= lam  <=>  x <= 6 - 4 lam ;  H >= lam  <=>  x >= 4 + 4 lam ;  very H = H^2
@pytest.mark.parametrize("rule2, level, gap", [
    # L >= 0.5: x <= 4; very H >= 0.5: H >= 0.7071, x >= 6.828: a gap (4, 6.828)
    ("if x is very H then y is hi", 0.5, (4.0, 6.8285)),
    # L >= 0.25: x <= 5; H >= 0.5: x >= 6: a gap (5, 6)
    ("if x is very H then y is hi", 0.25, (5.0, 6.0)),
    # L >= 0.1: x <= 5.6; H >= 0.3162: x >= 5.265: covered
    ("if x is very H then y is hi", 0.1, None),
    # not L >= 0.5 <=> L <= 0.5 <=> x >= 4: meets L >= 0.5 (x <= 4) exactly at 4: covered
    ("if x is not L then y is hi", 0.5, None),
    # L >= 0.6: x <= 3.6; not L >= 0.6 <=> x >= 4.4: a gap (3.6, 4.4)
    ("if x is not L then y is hi", 0.6, (3.6, 4.4)),
])
def test_coverage_is_decided_exactly_with_hedges_and_not(rule2, level, gap):
    result = _verify(rule2, f"covers x at least {level}")
    proof = result.evidence[0]
    assert proof.method == "proof"
    if gap is None:
        assert proof.status == Status.PROVED
    else:
        assert proof.status == Status.VIOLATED
        assert gap[0] < proof.point["x"] < gap[1]


def test_two_rules_with_one_premise_and_two_conclusions_are_inconsistent():
    result = _verify("if x is L then y is hi", "consistent")
    table = result.evidence[0]
    assert table.status == Status.VIOLATED and len(table.cells) == 1
    assert "says y is lo" in table.cells[0] and "says hi" in table.cells[0]


def test_monotone_table_and_its_continuous_form():
    # lo below L, hi above H: y = H/(L+H) with center of area rises with x: table and grid agree
    result = _verify("if x is H then y is hi", "monotone y increasing in x")
    table, proof, grid = result.evidence[:3]
    # a monotone table is a remark, not a proof of the output: HELD on the search's cases
    assert table.status == Status.UNDECIDED and grid.status == Status.HELD
    assert proof.status == Status.UNDECIDED          # max-min: no proof method, said so
    assert result.status == Status.HELD
    decreasing = _verify("if x is H then y is hi", "monotone y decreasing in x")
    assert decreasing.evidence[0].status == Status.WARNING
    assert decreasing.status == Status.VIOLATED and decreasing.violation.method == "grid"


def test_bounded_output_of_center_of_area_is_the_hull_of_its_peaks():
    assert _verify("if x is H then y is hi", "bounded y in [0, 1]").status == Status.PROVED
    # the hull [0, 1] is wider than [0, 0.9]; the search finds y = 1 where only H fires
    narrow = _verify("if x is H then y is hi", "bounded y in [0, 0.9]")
    assert narrow.status == Status.VIOLATED and narrow.violation.point["x"] >= 6.0


def test_sum_product_corner_table_is_proved_monotone_and_max_min_is_not():
    # With and = product and aggregation = sum, the memberships of each input sum to 1 and
    # every cell has one rule, so y is multilinear per cell and the vertex check is a proof.
    from fuzzyc.semantics.model import Aggregation, TNorm
    from fuzzyc.language.parser import load
    from fuzzyc.verifier import proof
    rb = load(f"{ROOT}/rulebases/wedm_corner.fz").rulebase
    published = proof.prove_monotone(rb, "y", "feedrate", "increasing", [])
    assert published.status == Status.UNDECIDED
    rb.inference.and_, rb.inference.aggregation = TNorm.PRODUCT, Aggregation.SUM
    for name, direction in (("feedrate", "increasing"), ("thickness", "increasing"),
                            ("angle", "decreasing")):
        assert proof.prove_monotone(rb, "y", name, direction, []).status == Status.PROVED


def test_sum_product_proof_names_the_wedm_critical_region_reversal():
    # e1 = ZO block, column ce2 = NS: row e2 = PS says ZO (0), row PB says NS (-0.5). At the
    # vertex (e1 = 0, ce2 = -0.5) the output is the cell's peak, so du1 falls by 0.5 from
    # e2 = 0.5 to e2 = 1.
    from fuzzyc.semantics.model import Aggregation, TNorm
    from fuzzyc.language.parser import load
    from fuzzyc.verifier import proof
    rb = load(f"{ROOT}/rulebases/wedm_three_region.fz").rulebase
    rb.inference.and_, rb.inference.aggregation = TNorm.PRODUCT, Aggregation.SUM
    evidence = proof.prove_monotone(rb, "du1", "e2", "increasing", [("e1", 1, False)])
    assert evidence.status == Status.VIOLATED
    assert evidence.point == {"e1": 0.0, "e2": 0.5, "ce2": -0.5}
    assert "by -0.5 from e2=0.5 to 1" in evidence.detail


def _first_uncovered_by_every_point(lows, highs, candidates):
    """The plain method the sweep replaced: every grid point, axis 0 outermost."""
    import itertools
    for point in itertools.product(*candidates):
        p = np.array(point)
        if not ((p >= lows - 1e-12) & (p <= highs + 1e-12)).all(axis=1).any():
            return list(point)
    return None


@pytest.mark.parametrize("seed", range(40))
def test_the_coverage_sweep_finds_what_every_point_finds(seed):
    # random boxes on 2-4 axes (some covering, some leaving holes): the same first uncovered
    # grid point, or none, as testing every point of the grid
    from fuzzyc.verifier.coverage import _first_uncovered
    rng = np.random.default_rng(seed)
    n_axes, n_boxes = int(rng.integers(2, 5)), int(rng.integers(1, 30))
    a, b = rng.choice(np.linspace(0, 1, 6), (2, n_boxes, n_axes))
    lows, highs = np.minimum(a, b), np.maximum(a, b)
    lows[0], highs[0] = 0.0, 1.0 if seed % 3 == 0 else highs[0]    # sometimes all covered
    candidates = [np.unique(np.concatenate([[0.0, 1.0], lows[:, k], highs[:, k]]))
                  for k in range(n_axes)]
    candidates = [np.concatenate([c, 0.5 * (c[:-1] + c[1:])]) for c in candidates]
    assert _first_uncovered(lows, highs, candidates) == \
        _first_uncovered_by_every_point(lows, highs, candidates)


def test_a_seven_input_table_is_proved_covering_and_a_missing_cell_is_found():
    # 3 triangles per input (peaks -1, 0, 1), every term tuple a rule: each point has a term
    # >= 0.5 on every axis, so the table covers at 0.5 (the grid had 9**7 = 4.8M points x
    # 2,187 boxes). Without the rule (P, P, ..., P) the corner x = 1 on every axis fires
    # no rule at all.
    import itertools
    from fuzzyc.formats import read_fll
    from fuzzyc.verifier.coverage import prove_covers
    names = ["N", "Z", "P"]
    head = "Engine: w\n" + "".join(
        f"InputVariable: x{i}\n  range: -1 1\n  term: N Triangle -2 -1 0\n"
        f"  term: Z Triangle -1 0 1\n  term: P Triangle 0 1 2\n" for i in range(7)) + \
        "OutputVariable: y\n  range: 0 1\n  aggregation: Maximum\n  defuzzifier: Centroid\n" \
        "  term: lo Triangle 0 0.5 1\nRuleBlock: r\n  conjunction: Minimum\n" \
        "  implication: Minimum\n"
    rules = ["  rule: if " + " and ".join(f"x{i} is {names[t]}" for i, t in enumerate(c))
             + " then y is lo\n" for c in itertools.product(range(3), repeat=7)]
    inputs = [f"x{i}" for i in range(7)]
    full = read_fll(head + "".join(rules), "w.fll").rulebase
    assert prove_covers(full, inputs, 0.5).status == Status.PROVED
    missing = prove_covers(read_fll(head + "".join(rules[:-1]), "w.fll").rulebase, inputs, 0.5)
    assert missing.status == Status.VIOLATED
    assert min(missing.point.values()) > 0.5      # in the P corner (N or Z would fire there)
