"""Closed-loop proofs (fuzzyc.verifier.reach): the sets hold every sampled run, and a controller
with its sign flipped is never proved."""
import copy

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st, HealthCheck

from fuzzyc.engine import inference as engine
from fuzzyc.semantics.model import Aggregation, Defuzzifier, TNorm, set_entries
from fuzzyc.language.parser import load
from fuzzyc.plants import scenario as scenarios
from fuzzyc.verifier.closed_loop import _Loop
from fuzzyc.verifier.reach import rulebase as set_rulebase
from fuzzyc.verifier.reach.affine import Affine, Symbols, join
from fuzzyc.verifier.reach.decide import Settings, prove
from fuzzyc.verifier.reach.loop import SetLoop
from fuzzyc.verifier.result import Status
from conftest import ROOT

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
    base = load(f"{ROOT}/rulebases/{name}.fz").rulebase
    rb = _random_rulebase(base, data) if data.draw(st.booleans()) else base
    lo = np.array([[data.draw(st.floats(v.lo, v.hi)) for v in rb.inputs]])
    width = np.array([[data.draw(st.floats(0, (v.hi - v.lo) / 3)) for v in rb.inputs]])
    y_lo, y_hi = set_rulebase.evaluate(rb, lo, lo + width)
    x = lo + width * np.random.default_rng(0).uniform(size=(400, len(rb.inputs)))
    y = engine.evaluate(rb, np.vstack([x, lo, lo + width]))
    tol = 1e-9 * (1 + np.abs(y))
    assert np.all(y >= y_lo - tol) and np.all(y <= y_hi + tol)


def _edm(mutate=None, which: int = 0):
    model = load(f"{ROOT}/rulebases/edm_sink_gap.fz")
    if mutate:
        mutate(model)
    prop = [p for p in model.properties if p.kind == "closed_loop"][which]
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
    out = model.rulebase.outputs[0]
    set_entries(out, "params", np.s_[:, 0], -out.params[:, 0])


def _always_advance(model):
    """Every rule concludes the fastest advance (0.3 mm/s): from the second loop's 81 um the
    gap is below 5 um by t = 0.136 s (a plain run at any set point)."""
    rb = model.rulebase
    rb.consequents[...] = int(np.argmax(rb.outputs[0].params[:, 0]))


@pytest.mark.parametrize("mutate, which", [(_flip_sign, 0), (_always_advance, 1)])
def test_a_broken_servo_is_never_proved(mutate, which):
    """The mutation tests' faults on the closed loops: over 0.3 s the search finds a loop
    whose gap closes (the shrunk case replayed alone breaks it too) and the sets do not prove
    `always gap > 5`. The first loop (gap0 varied) with the sign flipped (broken at t = 0.19
    s); the second (the set point stepped once: two copies per box) always advancing."""
    from fuzzyc.verifier import Options, verify_model
    model, prop = _edm(mutate, which)
    prop.args["duration"] = 0.3
    prop.args["checks"] = prop.args["checks"][:1]        # always gap > 5
    model.properties = [prop]
    (result,) = verify_model(model, Options(max_examples=10, prove=True, prove_boxes=4))
    reach, search = result.evidence
    assert search.status == Status.VIOLATED and "replayed alone: violated at" in search.detail
    assert reach.method == "reach" and reach.status == Status.UNDECIDED, reach.detail
    assert "unknown" in reach.detail and result.status == Status.VIOLATED


def test_join_of_two_forms_by_hand():
    """Girard's hull of a = 1 + 2 e0 ([-1, 3]) and b = 4 + e0 ([3, 5]), with c = e0 paired
    with itself: mid (a + b)/2 = 2.5 + 1.5 e0, the centres' half difference (1 - 4)/2 = -1.5
    on the new symbol s, the generators' (2 - 1)/2 = 0.5 on the new d0; c stays e0. So a's
    join spans 2.5 +- (1.5 + 1.5 + 0.5) = [-1, 6], and s = 1, d0 = e0 gives a (1 + 2 e0),
    s = -1, d0 = -e0 gives b (4 + e0), for both pairs at once."""
    sym = Symbols(1)
    e0 = Affine.interval(sym, -1.0, 1.0)
    a, b, c = 1 + e0.scale(2.0), 4 + e0, e0
    ja, jc = join([(a, b), (c, c)])
    assert sym.count == 3                                  # e0, s, d0
    np.testing.assert_allclose(ja.g, [[1.5, -1.5, 0.5]])
    np.testing.assert_allclose(ja.c, [2.5])
    np.testing.assert_allclose(np.ravel(ja.bounds()), [-1.0, 6.0])
    np.testing.assert_allclose(jc._padded(3), [[1.0, 0.0, 0.0]])
    for e in np.linspace(-1, 1, 9):
        assert np.isclose(ja.c[0] + ja.g[0] @ [e, 1.0, e], 1 + 2 * e)
        assert np.isclose(ja.c[0] + ja.g[0] @ [e, -1.0, -e], 4 + e)
        assert np.isclose(jc.c[0] + jc._padded(3)[0] @ [e, 1.0, e], e)


def test_unsupported_pieces_are_refused_by_name():
    model = load(f"{ROOT}/rulebases/edm_sink_gap.fz")
    faults = [p for p in model.properties if p.kind == "closed_loop"][2]
    scen = scenarios.load(faults.args["scenario"], {})
    (evidence,) = prove(model, faults, faults.args["checks"], scen)
    assert evidence.status == Status.UNDECIDED
    assert "sensor faults" in evidence.detail
    # the baseline's signals (a second loop beside the first) have no set-valued twin
    from fuzzyc.language.parser import parse
    text = open(f"{ROOT}/rulebases/wedm_corner.fz").read().replace(
        "error_sum < 0.5 * normal_error_sum", "error_sum < 0.5 * baseline_error_sum")
    corner = parse(text, f"{ROOT}/rulebases/wedm_corner.fz")
    prop = next(p for p in corner.properties if p.kind == "closed_loop")
    scen = scenarios.load(prop.args["scenario"], {})
    evidence = prove(corner, prop, prop.args["checks"], scen)
    assert all("no signal `baseline_error_sum` in the set-valued loop" in e.detail
               for e in evidence)


def test_nested_conditions_are_refused_by_name():
    from fuzzyc.language.parser import parse
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
    text = open(f"{ROOT}/rulebases/edm_sink_gap.fz").read().replace("for 3 s", "for 0.05 s")
    path = tmp_path / "edm_sink_gap.fz"
    path.write_text(text)
    status = main(["verify", str(path), "--prove", "--prove-boxes", "4", "--only", "gap > 5",
                   "--max-examples", "5"])
    out = capsys.readouterr().out
    assert status == 0, out
    first = out.split("PROVED", 1)[1]
    assert "reach: proved" in first and "gap >= " in first and "over 0.05 s" in first
    assert "Gaussian plant noise not covered" in first


@SLOW
@example(v0=58.0, v1=45.0, width=0.0, at=0.005, at_width=0.03, seed=0)
@given(v0=st.floats(45, 60), v1=st.floats(45, 60), width=st.floats(0.0, 2.0),
       at=st.floats(0.0, 0.04), at_width=st.floats(0.0, 0.02), seed=st.integers(0, 2 ** 16))
def test_every_sampled_set_point_step_lies_in_the_reachable_set(v0, v1, width, at, at_width,
                                                                seed):
    """The second EDM loop (`vary controller.Vset ... steps before`): random boxes of the start
    value, the value it steps to and the step time; 12 plain simulations with a step drawn in
    the box (the search's case format) stay inside the sets at every period, in the copy that
    holds them (U before the step, S after) and in C. The example (a step of 13 V at any time
    in 30 ms) fails if the loops stepping in a period are left out of S (no join)."""
    rng = np.random.default_rng(seed)
    model, _ = _edm()
    prop = [p for p in model.properties if p.kind == "closed_loop"][1]
    args = {**prop.args, "duration": 0.06}
    scen = scenarios.load(args["scenario"], {"plant.spark_noise": "0"})
    box = {"controller.Vset": (np.array([v0]), np.array([v0 + width])),
           "step:controller.Vset:value": (np.array([v1]), np.array([v1 + width])),
           "step:controller.Vset:time": (np.array([at]), np.array([at + at_width]))}
    set_loop = SetLoop(model, scen, args, box, 0.0)
    sets = list(set_loop.run(["gap", "mean_voltage", "velocity"]))
    assert set_loop.copies == 3                      # the step taken once: U, S and C
    loop = _Loop(model, scen, args["duration"], "numpy", seed)
    cases = [{"controller.Vset": rng.uniform(v0, v0 + width), "fault": None,
              "step": ("controller.Vset", rng.uniform(at, at + at_width),
                       rng.uniform(v1, v1 + width))} for _ in range(12)]
    time, signals = loop.run(cases)
    assert len(time) == len(sets)
    for k, (_, forms) in enumerate(sets):
        for row in (stepped_row(cases, k * scen.period), 2):
            for name in ("gap", "mean_voltage", "velocity"):
                f_lo, f_hi = forms[name].bounds()
                got = signals[name][k]
                slack = 1e-7 * (1 + np.abs(got))
                assert np.all(got >= f_lo[row] - slack) and np.all(got <= f_hi[row] + slack), \
                    (name, k, row)


def stepped_row(cases, t: float) -> np.ndarray:
    """The row of the one box's sets that holds each case in the period at t: 0 (U, the
    loops not stepped yet) before its step time, 1 (S, stepped) from it on, as the runtime
    steps; row 2 (C, the per-period choice) holds every case."""
    return np.array([int(t >= c["step"][1]) for c in cases])


@settings(max_examples=30, deadline=None, suppress_health_check=list(HealthCheck))
@given(x=st.floats(-8.0, 45.0), width=st.floats(0.0, 3.0), ft=st.floats(0.0, 0.08),
       ft_width=st.floats(0.0, 0.02))
def test_milling_peak_force_bounds_hold_every_sampled_point(x, width, ft, ft_width):
    """peak_force_box over a box of tool centres (across the air/6 mm/12 mm edges of the
    step cut) and feeds per tooth holds the plant's peak force at 200 points and the corners."""
    from fuzzyc.plants import milling
    params = milling.MillingParams(ks=1.0)
    lo, hi = milling.peak_force_box(params, np.array([x]), np.array([x + width]),
                                    np.array([ft]), np.array([ft + ft_width]))
    u = np.random.default_rng(0).uniform(size=(2, 200))
    xs = np.concatenate([x + width * u[0], [x, x + width, x, x + width]])
    fs = np.concatenate([ft + ft_width * u[1], [ft, ft, ft + ft_width, ft + ft_width]])
    force = milling.peak_force(params, xs, fs)
    assert np.all(force >= lo[0] * (1 - 1e-12)) and np.all(force <= hi[0] * (1 + 1e-12))


def _milling():
    model = load(f"{ROOT}/rulebases/milling_neurofuzzy_learned.fz")
    return model, next(p for p in model.properties if p.kind == "closed_loop")


@SLOW
@given(lo=st.floats(1350, 1640), width=st.floats(0.0, 10.0), seed=st.integers(0, 2 ** 16))
def test_every_sampled_milling_trace_lies_in_the_reachable_set(lo, width, seed):
    """Random boxes of ks on the milling step cut over 3 s (the entry into the workpiece at
    about 1.9 s included): 12 plain simulations with ks drawn in the box stay inside the sets
    (force, feed, actual feed, position) at every period."""
    model, prop = _milling()
    args = {**prop.args, "duration": 3.0}
    scen = scenarios.load(args["scenario"], {})
    names = ["force", "feed", "feed_actual", "position"]
    box = {"plant.ks": (np.array([lo]), np.array([lo + width]))}
    sets = list(SetLoop(model, scen, args, box, 0.0).run(names))
    loop = _Loop(model, scen, args["duration"], "numpy", seed)
    cases = [{"plant.ks": k, "step": None, "fault": None}
             for k in np.random.default_rng(seed).uniform(lo, lo + width, 12)]
    time, signals = loop.run(cases)
    assert len(time) == len(sets) and signals["force"].max() > 400   # the entry is in it
    for k, (_, forms) in enumerate(sets):
        for name in names:
            f_lo, f_hi = forms[name].bounds() if hasattr(forms[name], "bounds") else \
                (forms[name], forms[name])
            got = signals[name][k]
            slack = 1e-7 * (1 + np.abs(got))
            assert np.all(got >= f_lo - slack) and np.all(got <= f_hi + slack), (name, k)


def test_milling_loop_proved_over_its_entry_and_a_runaway_feed_never():
    """The learned milling controller over 3 s (through the entry into the 6 mm cut): the
    force limit and the overshoot are proved with their bounds; with every learned weight 8
    and no feed limit (the mutation tests' runaway feed) the search breaks the force limit
    (replayed alone) and the sets do not prove it."""
    from fuzzyc.verifier import Options, verify_model
    model, prop = _milling()
    prop.args["duration"] = 3.0
    scen = scenarios.load(prop.args["scenario"], {})
    checks = prop.args["checks"][:2]                 # always force < 700, overshoot below 350
    limit, overshoot = prove(model, prop, checks, scen, Settings(max_boxes=4))
    assert limit.status == overshoot.status == Status.PROVED, (limit.detail, overshoot.detail)
    bound = float(limit.detail.split("force <= ")[1].split()[0])
    loop = _Loop(model, scen, 3.0, "numpy", 0)
    _, signals = loop.run([{"plant.ks": 1650.0, "step": None, "fault": None}])
    assert signals["force"].max() <= bound < 700     # the stiffest material's entry is inside
    # its overshoot as temporal.py measures it (peak less the mean of the last 10 % of the
    # 20 periods) lies under the proved one, and that under the check's 350
    force = signals["force"][:, 0]
    shown = float(overshoot.detail.split("force - final <= ")[1].split()[0])
    assert force.max() - force[-2:].mean() <= shown <= 350
    set_entries(model.rulebase.outputs[0], "params", np.s_[:, 0], 8.0)
    model.outputs[0].hi = np.inf
    prop.args["duration"] = 4.0
    prop.args["checks"] = checks[:1]
    model.properties = [prop]
    (result,) = verify_model(model, Options(max_examples=10, prove=True, prove_boxes=4))
    reach, search = result.evidence
    assert search.status == Status.VIOLATED and "replayed alone: violated at" in search.detail
    assert reach.status == Status.UNDECIDED and result.status == Status.VIOLATED
