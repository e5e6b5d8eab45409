"""Closed-loop proofs (fuzzyc.verifier.reach): the sets hold every sampled run, and a controller
with its sign flipped is never proved."""
import copy

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st, HealthCheck

from fuzzyc import engine
from fuzzyc.model import Aggregation, Defuzzifier, TNorm
from fuzzyc.parser import load
from fuzzyc.plants import scenario as scenarios
from fuzzyc.verifier.closed_loop import _Loop
from fuzzyc.verifier.reach import rulebase as set_rulebase
from fuzzyc.verifier.reach.affine import Affine, Symbols
from fuzzyc.verifier.reach.decide import Settings, prove
from fuzzyc.verifier.reach.loop import SetLoop
from fuzzyc.verifier.result import Status

SLOW = settings(max_examples=4, deadline=None, derandomize=True,
                suppress_health_check=list(HealthCheck))


def test_ratio_bounds_by_hand():
    # w1 in [0, 1], w2 = 1, values z = (0, 1): the ratio w2 / (w1 + w2) is largest with w1 = 0
    # (1 / 1 = 1) and least with w1 = 1 (1 / 2 = 0.5)
    low, high = set_rulebase.ratio_bounds(np.array([[0.0, 1.0]]), np.array([[1.0, 1.0]]),
                                          np.array([0.0, 1.0]), default=7.0)
    assert (low[0], high[0]) == (0.5, 1.0)
    # both weights may be 0: nothing fires there, so the default 7 joins [0, 1]
    low, high = set_rulebase.ratio_bounds(np.zeros((1, 2)), np.ones((1, 2)),
                                          np.array([0.0, 1.0]), default=7.0)
    assert (low[0], high[0]) == (0.0, 7.0)


def test_affine_forms_cancel_and_clip_by_hand():
    sym = Symbols(1)
    x = Affine.interval(sym, [1.0], [3.0])          # 2 + eps
    assert (x - x).bounds() == (0.0, 0.0)           # the same symbol: exactly 0
    assert (x * 2.0 - x).bounds() == (1.0, 3.0)     # 2 + eps again
    # clip(x, 0, 2.5) on [1, 3]: secant slope (2.5 - 1) / 2 = 0.75; clip(x) - 0.75 x is 0.25
    # at x = 1 and 3 and 0.625 at 2.5, and each of the 24 pieces adds 0.75 * 2/24 = 0.0625 on
    # either side: 0.75 x + [0.1875, 0.6875] over x in [1, 3] spans [0.9375, 2.9375]
    lo, hi = x.clip(0.0, 2.5).bounds()
    assert lo[0] == pytest.approx(0.9375) and hi[0] == pytest.approx(2.9375)


def _random_rulebase(base, data):
    rb = copy.deepcopy(base)
    rb.consequents = np.stack([np.array(data.draw(st.lists(
        st.integers(-1, v.n_terms - 1), min_size=rb.n_rules, max_size=rb.n_rules)))
        for v in rb.outputs], axis=1)
    rb.inference.and_ = data.draw(st.sampled_from([TNorm.MIN, TNorm.PRODUCT,
                                                   TNorm.EINSTEIN_PRODUCT]))
    rb.inference.aggregation = data.draw(st.sampled_from(list(Aggregation)))
    rb.inference.defuzzifier = data.draw(st.sampled_from([
        Defuzzifier.CENTER_OF_AREA, Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM,
        Defuzzifier.CENTROID, Defuzzifier.MEAN_OF_MAXIMUM]))
    rb.weights = np.array(data.draw(st.lists(st.floats(0.0, 1.0), min_size=rb.n_rules,
                                             max_size=rb.n_rules)))
    return rb


@pytest.mark.parametrize("name", ["edm_sink_gap", "wedm_three_region", "wedm_corner",
                                  "milling_neurofuzzy_learned"])
@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_rule_base_bounds_hold_every_sampled_input(name, data):
    base = load(f"rulebases/{name}.fz").rulebase
    rb = _random_rulebase(base, data) if data.draw(st.booleans()) else base
    lo = np.array([[data.draw(st.floats(v.lo, v.hi)) for v in rb.inputs]])
    width = np.array([[data.draw(st.floats(0, (v.hi - v.lo) / 3)) for v in rb.inputs]])
    y_lo, y_hi = set_rulebase.evaluate(rb, lo, lo + width)
    x = lo + width * np.random.default_rng(0).uniform(size=(400, len(rb.inputs)))
    y = engine.evaluate(rb, np.vstack([x, lo, lo + width]))
    tol = 1e-9 * (1 + np.abs(y))
    assert np.all(y >= y_lo - tol) and np.all(y <= y_hi + tol)


def _edm(mutate=None):
    model = load("rulebases/edm_sink_gap.fz")
    if mutate:
        mutate(model)
    prop = next(p for p in model.properties if p.kind == "closed_loop")
    return model, prop


@SLOW
@given(lo=st.floats(0.03, 0.095), width=st.floats(0.0, 0.005), seed=st.integers(0, 2 ** 16),
       shuffle=st.booleans())
def test_every_sampled_edm_trace_lies_in_the_reachable_set(lo, width, seed, shuffle):
    """Random boxes of gap0 (and a randomly rewritten table): 12 plain simulations with gap0
    drawn in the box and the mains/harmonic phases drawn at random (spark noise off: the
    proof covers it only with --noise-sigmas) stay inside the sets at every period."""
    rng = np.random.default_rng(seed)

    def table(model):
        if shuffle:
            rb = model.rulebase
            rb.consequents = rng.integers(0, rb.outputs[0].n_terms, size=rb.consequents.shape)
    model, prop = _edm(table)
    args = {**prop.args, "duration": 0.04}
    scen = scenarios.load(args["scenario"], {"plant.spark_noise": "0"})
    box = {"plant.gap0": (np.array([lo]), np.array([lo + width]))}
    names = ["gap", "gap_voltage", "velocity", "mean_voltage", "e", "ce"]
    sets = list(SetLoop(model, scen, args, box, 0.0).run(names))
    loop = _Loop(model, scen, args["duration"], "numpy", seed)
    cases = [{"plant.gap0": g, "step": None, "fault": None}
             for g in rng.uniform(lo, lo + width, 12)]
    loop.model = model
    time, signals = loop.run(cases)
    assert len(time) == len(sets)
    for k, (_, forms) in enumerate(sets):
        for name in ("gap", "gap_voltage", "velocity", "mean_voltage"):
            f_lo, f_hi = forms[name].bounds()
            got = signals[name][k]
            slack = 1e-7 * (1 + np.abs(got))
            assert np.all(got >= f_lo - slack) and np.all(got <= f_hi + slack), (name, k)


def _flip_sign(model):
    """The controller pushes the wrong way: every output singleton negated."""
    model.rulebase.outputs[0].params[:, 0] *= -1


def test_a_sign_flipped_servo_is_never_proved():
    model, prop = _edm(_flip_sign)
    prop.args["duration"] = 0.3
    checks = prop.args["checks"][:1]                     # always gap > 5
    scen = scenarios.load(prop.args["scenario"], {})
    (evidence,) = prove(model, prop, checks, scen, Settings(max_boxes=4))
    assert evidence.status == Status.UNDECIDED, evidence.detail
    assert "unknown" in evidence.detail


def test_unsupported_pieces_are_refused_by_name():
    model = load("rulebases/edm_sink_gap.fz")
    faults = [p for p in model.properties if p.kind == "closed_loop"][2]
    scen = scenarios.load(faults.args["scenario"], {})
    (evidence,) = prove(model, faults, faults.args["checks"], scen)
    assert evidence.status == Status.UNDECIDED
    assert "sensor faults" in evidence.detail
    wedm = load("rulebases/wedm_three_region.fz")
    prop = next(p for p in wedm.properties if p.kind == "closed_loop")
    scen = scenarios.load(prop.args["scenario"], {})
    evidence = prove(wedm, prop, prop.args["checks"], scen)
    assert all("wedm_gap` has no set-valued step" in e.detail for e in evidence)


def test_nested_conditions_are_refused_by_name():
    from fuzzyc.parser import parse
    from fuzzyc.verifier.reach.chain import SetController, Unsupported
    text = """controller nested {
      input a in [0, 1]
      input b in [0, 1]
      terms a, b : L = tri(-1, 0, 1), H = tri(0, 1, 2)
      var y in [0, 10]
      terms y : singletons lo = 0 hi = 10
      inference and = min, or = max, defuzzify = coa
      rule if not (a is H or b is H) then y is lo
      rule if a is H and b is H then y is hi
      output u in [0, 10] = y
    }"""
    model = parse(text, "nested.fz")
    with pytest.raises(Unsupported, match=r"nested conditions \(rule 1 `if not \(a is H or b"):
        SetController(model, Symbols(1), model.symbol_values())


def test_verify_prove_on_the_command_line(capsys, tmp_path):
    """`fuzzyc verify --prove` on the EDM file cut to 50 ms: the sets prove `always gap > 5`
    beside the search's held cases, and say which assumption they rest on."""
    from fuzzyc.cli.main import main
    text = open("rulebases/edm_sink_gap.fz").read().replace("for 3 s", "for 0.05 s")
    path = tmp_path / "edm_sink_gap.fz"
    path.write_text(text)
    status = main(["verify", str(path), "--prove", "--prove-boxes", "4", "--only", "gap > 5",
                   "--max-examples", "5"])
    out = capsys.readouterr().out
    assert status == 0, out
    first = out.split("PROVED", 1)[1]
    assert "reach: proved" in first and "gap >= " in first and "over 0.05 s" in first
    assert "Gaussian plant noise not covered" in first
