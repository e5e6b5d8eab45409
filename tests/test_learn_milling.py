"""Neuro-fuzzy learning on the milling plant, held to the chapter (Tarng, Hua, Huang, ch. 6).

One module-scoped run learns 15 cycles on the step cut (about 20 s); the tests share it.
"""
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.learning import Learner, learn_scenario, provenance, run_cycle, trained_text
from fuzzyc.language.parser import load, parse
from fuzzyc.plants import milling, scenario
from fuzzyc.runtime.simulate import load_controller

ROOT = Path(__file__).resolve().parents[1]
RULES = ROOT / "rulebases" / "milling_neurofuzzy.fz"


@pytest.fixture(scope="module")
def learned():
    """15 cycles from the untrained file (the scenario itself runs the learned one)."""
    step = scenario.load("milling_step", {"controller.rulebase": str(RULES)})
    controller, result = learn_scenario(step, cycles=15)
    return controller.model, result


def test_shipped_learned_rule_base_is_what_fuzzyc_learn_writes(learned):
    """rulebases/milling_neurofuzzy_learned.fz is a result, not hand-tuned: its first line
    names the command (`fuzzyc learn` runs learn_scenario and trained_text as this fixture
    does, with the defaults 15 cycles, eta 0.25, rho 6), and the same learning writes it again
    byte for byte, performance indices included."""
    model, result = learned
    shipped = (ROOT / "rulebases" / "milling_neurofuzzy_learned.fz").read_text()
    made = provenance("milling_neurofuzzy.fz", "milling_step", 15, 0.25, 6.0, result.pi)
    assert trained_text(model, result.weights, provenance=made) == shipped
    assert "set learn.cycles" not in shipped.replace("# set learn.cycles", "")


def test_learning_rule_hand_computed():
    model = load(RULES)
    learner = Learner(model)
    # e = 0.4: mu_PS = (2/3 - 0.4)/(1/3) = 0.8 beats mu_PM = 0.2; cf = 0 is ZE: the winner is
    # cell (PS, ZE) = term 4*7+3 = 31, dw = 0.25 * 0.4 = 0.1; PI term = 0.5*0.4^2 = 0.08
    pi = learner.update({"e": np.array([0.4]), "cf": np.array([0.0])})
    assert pi[0] == pytest.approx(0.08)
    expected = np.zeros(49)
    expected[31] = 0.1
    np.testing.assert_allclose(learner.weights, expected)
    # e = 0, cf = 0.1: winner (ZE, ZE) = term 24, dw = 0.25*(0 - 6*(0.0017/0.0033)*0.1)
    learner.update({"e": np.array([0.0]), "cf": np.array([0.1])})
    assert learner.weights[24] == pytest.approx(-0.25 * 6 * 0.0017 / 0.0033 * 0.1)


def test_learning_needs_a_weighted_sum_rule_base():
    with pytest.raises(ValueError, match="weighted_sum"):
        Learner(load(ROOT / "rulebases" / "wedm_corner.fz"), output="y")


def test_pi_falls_to_under_half_in_15_cycles(learned):
    _, result = learned
    assert len(result.pi) == 15
    assert all(c.finished for c in result.cycles)
    assert result.pi[-1] < 0.5 * result.pi[0]
    # fast first, then slow (Fig. 6.5): the first cycle's gain exceeds the last five together
    assert result.pi[0] - result.pi[1] > result.pi[-6] - result.pi[-1] > 0


def test_force_held_at_300_N_at_both_depths(learned):
    _, result = learned
    trace = result.cycles[-1].trace
    x, force = trace["position"], trace["force"]
    # tool centre windows where every engaged tooth tip (x .. x + R) is in one depth, after
    # the entry transient: b = 6 mm over tips 2..22 mm, b = 12 mm over tips 22..42 mm
    for lo, hi in [(8.0, 16.0), (28.0, 36.0)]:
        steady = force[(x > lo) & (x < hi)]
        assert steady.size > 20
        assert np.all(np.abs(steady - 300.0) <= 30.0)
    # the entry overshoot the chapter describes, then the force comes back
    assert force.max() > 330.0


def test_pocket_is_faster_than_the_constant_feed_at_the_same_force_limit(learned):
    model, result = learned
    pocket = scenario.load("milling_pocket")
    params = pocket.plant_params()
    controller = load_controller(pocket, 1)          # the pocket's settings, learned weights
    controller.set_consequent_values("du", result.weights)
    adaptive = run_cycle(controller, milling, params, Learner(controller.model), False,
                         pocket.duration, pocket.period)
    feed = pocket.baseline["params"]["feed"]   # largest within 330 N (tests/test_milling.py)
    constant = milling.run_constant_feed(params, np.array([feed]), pocket.duration * 2)
    assert adaptive.finished
    assert constant["peak_force"][0] <= 330.0
    assert adaptive.time <= 0.85 * constant["time"][0]


def test_trained_file_keeps_the_text_and_reads_back(learned):
    model, result = learned
    text = trained_text(model, result.weights)
    source = model.source_text
    head = source.index("learnable {")
    assert text[:head] == source[:head]
    assert text[text.index("}", head):] == source[source.index("}", head):]   # after the table
    assert text != source
    again = parse(text, "trained.fz")
    got = again.rulebase.outputs[0].params[:, 0]
    np.testing.assert_allclose(got, result.weights, rtol=1e-5, atol=1e-5)


def test_trained_text_leaves_numbers_in_comments_alone():
    source = RULES.read_text().replace("    0 0 0 0 0 0 0\n", "    0 0 0 0 0 0 0   # 7 cells\n", 1)
    model = parse(source, "commented.fz")
    weights = np.linspace(-12.5, 40.0, 49)
    text = trained_text(model, weights)
    assert "# 7 cells" in text
    got = parse(text, "trained.fz").rulebase.outputs[0].params[:, 0]
    np.testing.assert_allclose(got, weights, rtol=1e-5)
