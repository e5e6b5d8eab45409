"""Seeded faults in the shipped rule bases, each caught by one of their own properties, with the
report pointing at the right place; and the unmutated files raise no false alarm."""
import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.semantics.model import set_entries
from fuzzyc.language.parser import load
from fuzzyc.verifier import Options, Status, verify_model
from fuzzyc.verifier.report import format_result
from conftest import ROOT

FAST = dict(max_examples=10, grid_budget=4000)


def _model(name):
    return load(f"{ROOT}/rulebases/{name}.fz")


def _check(model, only):
    results = verify_model(model, Options(only=only, **FAST))
    assert len(results) == 1, [r.name for r in results]
    return results[0]


def _rule(rb, origin):
    return next(r for r, o in enumerate(rb.origins) if origin in o)


def _delete(rb, r):
    keep = np.arange(rb.n_rules) != r
    for name in ("antecedents", "consequents", "weights", "negated", "hedges", "connective"):
        setattr(rb, name, getattr(rb, name)[keep])
    rb.origins = [o for k, o in enumerate(rb.origins) if keep[k]]
    rb.rule_locs = [o for k, o in enumerate(rb.rule_locs) if keep[k]]


@pytest.mark.parametrize("name", ["wedm_three_region", "wedm_corner", "milling_neurofuzzy",
                                  "edm_sink_gap"])
def test_shipped_rule_bases_raise_no_false_alarm(name):
    # the closed loops of the files run as items of `pytest rulebases/`
    model = _model(name)
    model.properties = [p for p in model.properties if p.kind != "closed_loop"]
    results = verify_model(model, Options(**FAST))
    assert results and not [format_result(r) for r in results if r.is_failure]
    # every table-level and coverage property of the shipped files is proved exactly
    exact = [r for r in results if r.prop.kind in ("covers", "consistent", "complete")]
    assert exact and all(r.status == Status.PROVED for r in exact)


# ---------------------------------------------------------------- a flipped table cell
def test_wedm_flipped_cell_breaks_the_safe_region_monotonicity():
    model = _model("wedm_three_region")
    rb = model.rulebase
    r = _rule(rb, "table du1 when e1 is P, row e2=PS, col ce2=ZO")
    set_entries(rb, "consequents", (r, 0), rb.outputs[0].index("NB"))   # printed PS
    result = _check(model, "monotone du1 increasing in e2 where e1 is P")
    table = result.evidence[0]
    # the table names the cells as a warning; the violation is an evaluated pair of points
    assert table.method == "table" and table.status == Status.WARNING
    assert result.status == Status.VIOLATED and result.violation.method == "grid"
    # the file records a finding for this property (a dip inside cells), but not this cell:
    # the old note does not hide the new fault
    assert result.finding is None and result.is_failure
    # NB at row PS sits below ZO (row ZO) and NS (row NS) of the same column
    assert all("row e2=PS, col ce2=ZO" in c for c in table.cells)
    assert len(table.cells) == 2


def test_corner_flipped_cell_breaks_monotone_in_feed():
    model = _model("wedm_corner")
    rb = model.rulebase
    r = _rule(rb, "table rule 19")                      # B B S -> VB
    set_entries(rb, "consequents", (r, 0), rb.outputs[0].index("VS"))
    result = _check(model, "monotone y increasing in feedrate")
    table = result.evidence[0]
    assert table.status == Status.WARNING
    assert result.status == Status.VIOLATED and result.violation.method == "grid"
    assert any("table rule 19" in c for c in table.cells)


def test_edm_flipped_cell_breaks_continuity_between_named_cells():
    model = _model("edm_sink_gap")
    rb = model.rulebase
    r = _rule(rb, "row e=ZO, col ce=Z")
    # ZO -> PB: 3 terms above NS (row NS)
    set_entries(rb, "consequents", (r, 0), rb.outputs[0].index("PB"))
    result = _check(model, "continuous dv")
    assert result.is_failure
    assert all("row e=ZO, col ce=Z]" in c for c in result.evidence[0].cells)


def test_milling_weight_out_of_range_breaks_the_bound_at_its_cell():
    model = _model("milling_neurofuzzy")
    rb = model.rulebase
    r = _rule(rb, "row e=PS, col cf=NS")
    term = rb.consequents[r, 0]
    set_entries(rb.outputs[0], "params", (term, 0), 80.0)   # a learned weight beyond [-50, 50]
    result = _check(model, "bounded du in [-50, 50]")
    proof = result.evidence[0]
    assert proof.method == "proof" and proof.status == Status.VIOLATED
    # the weighted sum peaks at the rule's own cell: e and cf at the peaks of PS and NS
    assert proof.point == pytest.approx({"e": 1 / 3, "cf": -1 / 3})


# ---------------------------------------------------------------- a deleted rule
# WEDM: the du1 and du2 tables' cells with one premise are one rule, so both outputs lose it;
# corner rule 2 has a wildcard thickness, so both thickness cells lose it.
@pytest.mark.parametrize("name, only, origin, cell, n_missing", [
    ("wedm_three_region", "complete", "table du1 when e1 is N, row e2=NS, col ce2=PS",
     "e1 is N and e2 is NS and ce2 is PS", 2),
    ("wedm_corner", "complete y", "table rule 2",
     "feedrate is VS and thickness is S and angle is M", 2),
    ("milling_neurofuzzy", "complete", "row e=ZE, col cf=ZE", "e is ZE and cf is ZE", 1),
    ("edm_sink_gap", "complete", "row e=PB, col ce=N", "e is PB and ce is N", 1),
])
def test_deleted_rule_leaves_a_named_cell_uncovered(name, only, origin, cell, n_missing):
    model = _model(name)
    _delete(model.rulebase, _rule(model.rulebase, origin))
    result = _check(model, only)
    assert result.is_failure
    cells = result.evidence[0].cells
    assert any(f"({cell})" in c for c in cells) and len(cells) == n_missing


# ---------------------------------------------------------------- a term moved: coverage gap
def test_wedm_moved_term_opens_a_coverage_gap_where_it_was():
    model = _model("wedm_three_region")
    e2 = model.rulebase.inputs[1]
    set_entries(e2, "params", e2.index("PS"), [0.6, 0.8, 0.8, 1.0])   # was tri(0, 0.5, 1)
    result = _check(model, "covers e1, e2, ce2 at least 0.5")
    proof = result.evidence[0]
    assert proof.method == "proof" and proof.status == Status.VIOLATED
    # ZO >= 0.5 up to e2 = 0.25, PB >= 0.5 from 0.75, PS now from 0.7: the gap is (0.25, 0.7)
    assert 0.25 < proof.point["e2"] < 0.7


def test_corner_narrowed_angle_term_opens_a_gap():
    model = _model("wedm_corner")
    angle = model.rulebase.inputs[2]
    # was tri(30, 82.5, 135)
    set_entries(angle, "params", angle.index("M"), [70, 82.5, 82.5, 95])
    proof = _check(model, "covers feedrate, thickness, angle at least 0.5").evidence[0]
    # S >= 0.5 up to 56.25 deg, M now 76.25-88.75, B from 108.75: gaps on both sides of M
    assert proof.status == Status.VIOLATED
    a = proof.point["angle"]
    assert 56.25 < a < 76.25 or 88.75 < a < 108.75


def test_milling_moved_term_lowers_the_product_coverage():
    model = _model("milling_neurofuzzy")
    e = model.rulebase.inputs[0]
    # was tri(-1/3, 0, 1/3)
    set_entries(e, "params", e.index("ZE"), [0.0, 1 / 6, 1 / 6, 1 / 3])
    proof = _check(model, "covers e, cf at least 0.25").evidence[0]
    assert proof.status == Status.VIOLATED
    # NS falls to 0 at e = 0 where ZE now starts: max membership of e is 0 there
    assert proof.point["e"] == pytest.approx(0.0)


def test_edm_moved_term_opens_a_gap():
    model = _model("edm_sink_gap")
    ce = model.rulebase.inputs[1]
    set_entries(ce, "params", ce.index("Z"), [0.2, 0.6, 0.6, 1.0])   # was tri(-1, 0, 1)
    proof = _check(model, "covers e, ce at least 0.5").evidence[0]
    assert proof.status == Status.VIOLATED
    # N >= 0.5 up to -0.5, Z now 0.4..0.8, P from 0.5: the gap is (-0.5, 0.4)
    assert -0.5 < proof.point["ce"] < 0.4


# ---------------------------------------------------------------- an output limit removed
def test_wedm_feed_without_its_limit_is_driven_past_it():
    model = _model("wedm_three_region")
    feed = next(o for o in model.outputs if o.name == "feed")
    feed.hi = np.inf
    evidence = _check(model, "bounded feed in [0, 3]").evidence[0]
    assert evidence.status == Status.VIOLATED
    # the largest du1 is the PB peak, 1: 1.8e-4 mm/min per sample from 0.3 needs
    # floor(2.7 / 1.8e-4) + 1 = 15001 samples (600 s at 40 ms) to pass 3 mm/min
    assert "after 15001 samples (600.04 s)" in evidence.detail
    x = [[evidence.point[v.name] for v in model.rulebase.inputs]]
    assert evaluate(model.rulebase, x)[0, 0] == pytest.approx(1.0)


def test_corner_reduction_without_its_limit():
    model = _model("wedm_corner")
    model.params["like"].value = 2.0                    # precision: w = 2 y, up to 120 %
    out = model.outputs[0]
    out.lo, out.hi = -np.inf, np.inf
    evidence = _check(model, "bounded reduction in [0, 90]").evidence[0]
    assert evidence.status == Status.VIOLATED and "= 120 outside" in evidence.detail


def test_edm_velocity_without_its_limit_and_a_larger_gain():
    model = _model("edm_sink_gap")
    model.params["Vmax"].value = 10.0
    out = model.outputs[0]
    out.lo, out.hi = -np.inf, np.inf
    evidence = _check(model, "bounded velocity in [-2, 2]").evidence[0]
    # dv reaches its NB peak -0.3 (and PB 0.3): velocity = 10 dv = -3 (or 3)
    assert evidence.status == Status.VIOLATED and "= -3 outside" in evidence.detail


def test_milling_feed_without_its_limit_once_weights_are_learned():
    model = _model("milling_neurofuzzy")
    du = model.rulebase.outputs[0]
    set_entries(du, "params", np.s_[:, 0], 8.0)   # any positive learned weights
    model.outputs[0].hi = np.inf
    evidence = _check(model, "bounded feed in [0, 75]").evidence[0]
    # du = 8 everywhere (memberships sum to 1), dU = GU du = 0.8 mm/min per sample:
    # from 0, floor(75 / 0.8) + 1 = 94 samples pass 75 mm/min
    assert evidence.status == Status.VIOLATED and "after 94 samples" in evidence.detail
