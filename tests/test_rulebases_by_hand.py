"""The shipped rule bases at points worked out by hand, with the arithmetic in the comments.

Terms (see the rule files): uniform partitions on [-1, 1] put NB, NS, ZO, PS, PB peaks at
-1, -0.5, 0, 0.5, 1 (7 terms: every 1/3); center of area is sum(alpha_j * peak_j) / sum(alpha_j)
with alpha_j the largest activation of a rule concluding term j (max-min inference).
"""
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate, explain
from fuzzyc.language.parser import load, parse

RULEBASES = Path(__file__).resolve().parents[1] / "rulebases"


def core(model, **inputs):
    rb = model.rulebase
    x = np.array([[inputs[v.name] for v in rb.inputs]], dtype=float)
    y = evaluate(rb, x)[0]
    return {v.name: y[o] for o, v in enumerate(rb.outputs)}


@pytest.fixture(scope="module")
def wedm():
    return load(RULEBASES / "wedm_three_region.fz")


def test_wedm_has_the_75_rules_of_table_2(wedm):
    rb = wedm.rulebase
    assert rb.n_rules == 75 and (rb.consequents >= 0).all()
    # Table 2, e1 = N block, row e2 = PB, col ce2 = NB: du1 NS, du2 NS.
    r = next(i for i, o in enumerate(rb.origins)
             if o.startswith("table du1 when e1 is N, row e2=PB, col ce2=NB"))
    assert rb.describe_rule(r) == "if e1 is N and e2 is PB and ce2 is NB then du1 is NS, du2 is NS"


def test_wedm_one_rule_fires_fully(wedm):
    # e1 = 1 (P), e2 = 1 (PB), ce2 = 1 (PB): only rule (P, PB, PB) fires, with 1.
    # Table 2: du1 = PB (peak 1), du2 = PB (peak 1).
    out = core(wedm, e1=1.0, e2=1.0, ce2=1.0)
    assert out == pytest.approx({"du1": 1.0, "du2": 1.0})
    fired = explain(wedm.rulebase, np.array([1.0, 1.0, 1.0])).fired
    assert len(fired) == 1 and fired[0][1] == pytest.approx(1.0)


def test_wedm_between_terms_on_e2(wedm):
    # e1 = 1 (P 1), e2 = 0.75 (PB 0.5, PS 0.5), ce2 = 0 (ZO 1).
    # (P, PB, ZO) -> du1 PB, du2 PB with min(1, .5, 1) = .5; (P, PS, ZO) -> du1 PS, du2 PS with .5.
    # du1 = (.5*1 + .5*.5) / (.5 + .5) = 0.75, and the same for du2.
    assert core(wedm, e1=1.0, e2=0.75, ce2=0.0) == pytest.approx({"du1": 0.75, "du2": 0.75})


def test_wedm_eight_rules_across_two_regions(wedm):
    # e1 = .5 (ZO .5, P .5), e2 = .75 (PS .5, PB .5), ce2 = .75 (PS .5, PB .5): 8 rules at .5.
    # P block:  (PB,PB) PB/PB, (PB,PS) PB/PB, (PS,PB) PB/PB, (PS,PS) PB/PS   [du1/du2]
    # ZO block: (PB,PB) PS/ZO, (PB,PS) PS/ZO, (PS,PB) PS/ZO, (PS,PS) PS/ZO
    # du1: PB .5, PS .5 -> (.5*1 + .5*.5) / 1 = 0.75
    # du2: PB .5, PS .5, ZO .5 -> (.5*1 + .5*.5 + .5*0) / 1.5 = 0.5
    assert core(wedm, e1=0.5, e2=0.75, ce2=0.75) == pytest.approx({"du1": 0.75, "du2": 0.5})


def test_wedm_whole_signal_chain_first_step(wedm):
    # spark_freq 26 kHz: e1 = (30 - 26) * .25 = 1; abnormal ratio .325: e2 = (.4 - .325) * 10 = .75;
    # first sample: ce2 = 0. As above du1 = du2 = .75.
    # feed = .3 + .75 * 1.8e-4 = .300135 mm/min
    # 1/t_off = 1/32 + .75 * .8e-4 = .03125 + .00006 = .03131 -> t_off = 31.93868... us
    c = Controller(wedm, batch=1)
    out = c.step({"spark_freq": np.array([26.0]), "abnormal_ratio": np.array([0.325])})
    assert out["feed"][0] == pytest.approx(0.300135, abs=1e-12)
    assert out["t_off"][0] == pytest.approx(1 / 0.03131, rel=1e-12)


@pytest.fixture(scope="module")
def corner():
    return load(RULEBASES / "wedm_corner.fz")


def test_corner_rule_25_alone(corner):
    # feedrate 180 (VB 1), thickness 50 (B 1), angle 30 (S 1): rule 25 -> y = VB = 60 %.
    assert core(corner, feedrate=180.0, thickness=50.0, angle=30.0)["y"] == pytest.approx(60.0)


def test_corner_between_feed_terms(corner):
    # feedrate 92.5: S = (110 - 92.5) / 35 = .5, M = .5; thickness 50: B 1; angle 82.5: M 1.
    # rule 8 (S, B, M) -> S = 15 with .5; rule 14 (M, B, M) -> M = 30 with .5.
    # y = (.5*15 + .5*30) / 1 = 22.5 %
    assert core(corner, feedrate=92.5, thickness=50.0, angle=82.5)["y"] == pytest.approx(22.5)


def test_corner_wildcard_rules_ignore_thickness(corner):
    # feedrate 40 (VS 1); thickness 35 (S .5, B .5) does not matter to rules 1-3 (`*`);
    # angle 56.25: S = (82.5 - 56.25) / 52.5 = .5, M = .5.
    # rule 1 (VS, *, S) -> S = 15 with .5; rule 2 (VS, *, M) -> VS = 5 with .5.
    # y = (.5*15 + .5*5) / 1 = 10 %
    assert core(corner, feedrate=40.0, thickness=35.0, angle=56.25)["y"] == pytest.approx(10.0)


def test_corner_chain_applies_users_like(corner):
    # First sample: the low-pass passes the feed through (F_ave(0) = F_now(0)); y = 60 as in
    # rule 25; like = 1.2 for precision: reduction = 1.2 * 60 = 72 %.
    corner.params["like"].value = 1.2
    try:
        c = Controller(corner, batch=1)
        out = c.step({"feed": np.array([180.0]), "thickness": np.array([50.0]),
                      "angle": np.array([30.0])})
    finally:
        corner.params["like"].value = 1.0
    assert out["reduction"][0] == pytest.approx(72.0)


def milling_with_weights(weights: dict[tuple[str, str], float]):
    """The milling rule base with some learned weights written into its table."""
    text = (RULEBASES / "milling_neurofuzzy.fz").read_text()
    names = "NB NM NS ZE PS PM PB".split()
    rows = [[weights.get((r, c), 0) for c in names] for r in names]
    zero_block = "\n".join("    0 0 0 0 0 0 0" for _ in names)
    assert zero_block in text
    block = "\n".join("    " + " ".join(f"{w:g}" for w in row) for row in rows)
    return parse(text.replace(zero_block, block), "milling.fz")


def test_milling_starts_empty():
    # All 49 weights start at 0: du = sum_j mu_j * 0 = 0 everywhere.
    model = load(RULEBASES / "milling_neurofuzzy.fz")
    x = np.random.default_rng(1).uniform(-1, 1, size=(1000, 2))
    assert np.all(evaluate(model.rulebase, x) == 0.0)
    assert model.rulebase.outputs[0].learnable.sum() == 49


def test_milling_weighted_sum_by_hand():
    model = milling_with_weights({("ZE", "ZE"): 2.0, ("PS", "ZE"): 4.0})
    # e = 0, cf = 0: only (ZE, ZE) fires, mu = 1 * 1: du = 1 * 2 = 2.
    assert core(model, e=0.0, cf=0.0)["du"] == pytest.approx(2.0)
    # e = 1/6 (ZE .5, PS .5), cf = 0 (ZE 1): du = .5*1*2 + .5*1*4 = 3 (a sum, not an average).
    assert core(model, e=1 / 6, cf=0.0)["du"] == pytest.approx(3.0)
    # e = cf = 1/6: four rules with product firing .5*.5 = .25: du = .25*2 + .25*4 = 1.5.
    assert core(model, e=1 / 6, cf=1 / 6)["du"] == pytest.approx(1.5)


def test_milling_chain_integrates_and_clips():
    model = milling_with_weights({("PB", "ZE"): 50.0})
    # force 0 N: e = clamp((300 - 0) * .0033) = clamp(.99) = .99 -> PB (.99 - 2/3) * 3 = .97,
    # PM .03; cf = 0 first sample. du = .97 * 50 = 48.5; feed = 0 + .1 * 48.5 = 4.85 mm/min.
    c = Controller(model, batch=1)
    out = c.step({"force": np.array([0.0])})
    assert out["feed"][0] == pytest.approx(4.85)
    for _ in range(20):  # keeps integrating up to U_max = 75 and stays there
        out = c.step({"force": np.array([0.0])})
    assert out["feed"][0] == 75.0


@pytest.fixture(scope="module")
def edm():
    return load(RULEBASES / "edm_sink_gap.fz")


def test_edm_short_circuit_retracts(edm):
    # e = -1 (NB 1), ce = -1 (N 1): table row NB col N = NB = -0.3 -> dv = -0.3.
    assert core(edm, e=-1.0, ce=-1.0)["dv"] == pytest.approx(-0.3)


def test_edm_between_terms(edm):
    # e = .25 (ZO .5, PS .5), ce = -.75 (N = lshoulder(-1, 0): .75; Z = tri(-1, 0, 1): .25):
    # (ZO, N) -> NS with .5, (ZO, Z) -> ZO with .25, (PS, N) -> ZO with .5, (PS, Z) -> PS with .25.
    # alpha: NS .5, ZO max(.25, .5) = .5, PS .25
    # dv = (.5*-.08 + .5*0 + .25*.08) / (.5 + .5 + .25) = -.02 / 1.25 = -0.016
    assert core(edm, e=0.25, ce=-0.75)["dv"] == pytest.approx(-0.016)


def test_edm_chain_open_gap_advances(edm):
    # 70 V: e = (70 - 50) / 20 = 1 (PB); first sample: lowpass passes 70 V, delta = 0, ce = 0 (Z):
    # row PB col Z = PB = .3; velocity = .3 * 2 = .6 mm/s.
    c = Controller(edm, batch=1)
    assert c.step({"gap_voltage": np.array([70.0])})["velocity"][0] == pytest.approx(0.6)
