"""The closed-loop checker on a toy gap plant (first order, known answer) around the shipped
EDM sinking servo: held when correct, and a sign error in the gain is caught, shrunk, plotted."""
import dataclasses

import pytest

from fuzzyc.language.parser import parse
from fuzzyc.verifier import Options, Status, verify_model
from toy_gap import scenario, toy_plant, toy_servo  # noqa: F401  (fixtures)
from conftest import ROOT


def test_correct_servo_holds_on_every_case(toy_plant, scenario):
    # From 80 V the servo advances at up to 2 mm/s (2000 um/s) against at most 20 um/s of
    # erosion: the gap reaches 50 um +- 5 long before 1.5 s, and never opens to 100 V.
    results = verify_model(toy_servo(scenario), Options(max_examples=12, seed=1))
    assert [r.status for r in results] == [Status.HELD, Status.HELD]
    assert all(r.evidence[0].cases == 12 for r in results)


def test_sign_error_in_the_gain_is_caught_and_shrunk(toy_plant, scenario, tmp_path):
    # Vmax = -2: the servo retracts when the gap is too wide, so the voltage runs to 120 V.
    report = tmp_path / "report"
    results = verify_model(toy_servo(scenario, vmax="-2 mm/s"),
                           Options(max_examples=12, seed=1, report_dir=str(report)))
    always, settles = results
    assert always.status == Status.VIOLATED and settles.status == Status.VIOLATED
    evidence = always.violation
    # every erosion rate fails, so the shrinker lands on the scenario's nominal 5 um/s
    assert evidence.trace["case"] == {"plant.erosion": 5.0}
    # it starts at 80 V and runs away: 100 V is crossed after the first few samples
    assert 0 < evidence.trace["violated_at"] < 0.1
    assert (report / evidence.trace["plot"].split("/")[-1]).exists()
    assert "--only 'always gap_voltage < 100'" in always.reproduce


def test_unknown_signal_is_undecided_not_a_pass(toy_plant, scenario):
    results = verify_model(toy_servo(scenario, checks="always spark_freq < 3\n"),
                           Options(max_examples=2))
    assert results[0].status == Status.UNDECIDED
    assert "spark_freq" in results[0].evidence[0].detail


def test_c_backend_gives_the_same_verdicts(toy_plant, scenario):
    pytest.importorskip("fuzzyc.backends.c.load")
    options = dict(max_examples=6, seed=2, shrink_rounds=1)
    for vmax in ("2 mm/s", "-2 mm/s"):
        numpy_side = verify_model(toy_servo(scenario, vmax=vmax), Options(**options))
        c_side = verify_model(toy_servo(scenario, vmax=vmax), Options(backend="c", **options))
        assert [r.status for r in c_side] == [r.status for r in numpy_side]
        assert [r.evidence[0].detail for r in c_side] == [r.evidence[0].detail for r in numpy_side]


def test_wedm_sign_error_in_the_error_gain_is_caught_in_closed_loop():
    # GE2 = -10 instead of 10: e2 > 0 now means "abnormal ratio too high", so the controller
    # slows the feed when it should speed up and the ratio never climbs from 25 % to Yr2.
    from fuzzyc.language.parser import load
    model = load(f"{ROOT}/rulebases/wedm_three_region.fz")
    loop = next(p for p in model.properties if p.kind == "closed_loop")
    check = next(c for c in loop.args["checks"] if c.kind == "eventually")
    model.properties = [dataclasses.replace(
        loop, args={**loop.args, "duration": 160.0, "checks": [check]})]
    correct = verify_model(model, Options(max_examples=4, seed=0, shrink_rounds=0))
    assert correct[0].status == Status.HELD
    model.params["GE2"].value = -10.0
    (result,) = verify_model(model, Options(max_examples=4, seed=0, shrink_rounds=0))
    assert result.status == Status.VIOLATED and result.finding is None
    assert "4 of 4 loops break it" in result.violation.detail


# ---------------------------------------------------------------- the corner controller
def _corner_loop_only(text=None):
    from fuzzyc.language.parser import load
    model = parse(text, f"{ROOT}/rulebases/wedm_corner.fz") if text else load(f"{ROOT}/rulebases/wedm_corner.fz")
    model.properties = [p for p in model.properties if p.kind == "closed_loop"]
    # the plant moves the wire exactly, so a 2 s period only coarsens the times (and halves
    # the test's run time)
    model.properties[0].args["set"]["period"] = 2.0
    return model


CORNER_FAST = dict(max_examples=3, seed=0, shrink_rounds=2)


def test_corner_sign_error_in_the_users_like_is_caught_against_normal_machining():
    # reduction = -y * like: the output saturates at 0 %, the feed is never cut, and the
    # summed corner error equals normal machining's (ratio 1, not < 0.5) on every drawn cut.
    text = open(f"{ROOT}/rulebases/wedm_corner.fz").read()
    model = _corner_loop_only(text.replace("= y * like", "= -y * like"))
    error, time_ = verify_model(model, Options(**CORNER_FAST))
    assert error.status == Status.VIOLATED and error.finding is None
    assert "normal_error_sum" in error.prop.text
    assert "3 of 3 loops break it" in error.violation.detail
    # every drawn cut fails, so the shrinker lands on the scenario's rough cut (160, 50 mm)
    assert error.violation.trace["case"] == {"plant.feed": 160.0, "plant.thickness": 50.0}
    # an `eventually` is broken at its deadline; the trace keeps the error sum beside normal
    # machining's at the same corners
    assert error.violation.trace["violated_at"] == 3400.0
    signals = error.violation.trace["signals"]
    assert signals["error_sum"][-1] == pytest.approx(signals["normal_error_sum"][-1])
    assert time_.status == Status.HELD          # no reduction costs no time


def test_corner_precision_like_costs_more_than_ten_percent_time():
    # like = 1.5 (the paper's "precision" setting): 60 % of y becomes 90 %, the wire crawls at
    # a tenth of its speed through the zones of the sharp corners: 14 zones x 0.62 mm at up to
    # 10x the time adds far more than 10 % to the 153.95 mm path.
    model = _corner_loop_only()
    loop = model.properties[0]
    loop.args["set"]["controller.params.like"] = 1.5
    *_, time_ = verify_model(model, Options(**CORNER_FAST))
    assert time_.status == Status.VIOLATED and "3 of 3 loops break it" in time_.violation.detail
    # nominal cut: normal machining takes 153.95 * 60 * 50 / 160 = 2886.6 s, the bound 3175 s
    assert time_.violation.trace["violated_at"] == pytest.approx(1.1 * 153.95 * 60 * 50 / 160,
                                                                 abs=2.0)


def test_corner_sign_error_in_the_lowpass_is_refused_by_the_compiler():
    # b = -0.2 (or a = -0.8) would make F_ave negative; the builder refuses it at its place
    from fuzzyc.errors import FuzzycError
    text = open(f"{ROOT}/rulebases/wedm_corner.fz").read()
    with pytest.raises(FuzzycError, match=r"wedm_corner.fz:\d+:\d+: error: lowpass\(x, a, b\) "
                                          r"needs 0 <= a < 1 and b > 0"):
        parse(text.replace("param b = 0.2", "param b = -0.2"), f"{ROOT}/rulebases/wedm_corner.fz")


def test_baseline_signals_need_a_scenario_with_a_baseline(toy_plant, scenario):
    results = verify_model(toy_servo(scenario, checks="always gap < 1.2 * baseline_gap\n"),
                           Options(max_examples=2))
    assert results[0].status == Status.UNDECIDED and "baseline" in results[0].evidence[0].detail


# ---------------------------------------------------------------- milling
@pytest.mark.parametrize("gain, value", [(None, None), ("GE", -0.0033), ("GU", -0.1)])
def test_milling_sign_error_in_a_gain_is_caught_after_learning(gain, value):
    # Shortened from the file's 15 cycles and 60 s to keep the suite fast: 3 learning cycles of
    # a 15 s scenario already hold the force at Fr = 300 N +- 15 within 10 s (the correct file,
    # the control case). With GE or GU negated the learning rule pushes the weights the wrong
    # way: the feed stays at its initial 75 mm/min and the force sits near 544 N.
    from fuzzyc.language.parser import load
    model = load(f"{ROOT}/rulebases/milling_neurofuzzy.fz")
    loop = next(p for p in model.properties if p.kind == "closed_loop")
    check = next(c for c in loop.args["checks"] if c.kind == "eventually")
    model.properties = [dataclasses.replace(loop, args={
        **loop.args, "duration": 15.0, "checks": [check],
        "set": {**loop.args["set"], "learn.cycles": 3, "duration": 15.0}})]
    if gain:
        model.params[gain].value = value
    (result,) = verify_model(model, Options(max_examples=3, seed=0, shrink_rounds=1))
    if gain is None:
        assert result.status == Status.HELD
        return
    assert result.status == Status.VIOLATED and result.finding is None
    assert "3 of 3 loops break it" in result.violation.detail
    trace = result.violation.trace
    assert trace["violated_at"] == 10.0                  # the deadline of `eventually within`
    force = trace["signals"]["force"]
    assert abs(force[-1] - 300.0) > 200.0                # nowhere near Fr at the end


def test_edm_sign_error_in_vmax_is_caught_on_the_sinking_scenario():
    # Vmax = -2 mm/s on the real edm_sink plant (not the toy): the servo retracts when it
    # should advance, so the mean voltage never settles to Vset (every loop, at the `by` time)
    from fuzzyc.language.parser import load
    model = load(f"{ROOT}/rulebases/edm_sink_gap.fz")
    model.properties = [p for p in model.properties if p.kind == "closed_loop"]
    model.params["Vmax"].value = -2.0
    results = verify_model(model, Options(max_examples=3, seed=0, shrink_rounds=1))
    settles = next(r for r in results if r.prop.kind == "settles")
    assert settles.status == Status.VIOLATED and settles.finding is None
    assert "3 of 3 loops break it" in settles.violation.detail
    # every gap fails, so one shrinking round lands on the scenario's nominal 0.08 mm
    assert settles.violation.trace["case"] == {"plant.gap0": 0.08}
    assert settles.violation.trace["violated_at"] == pytest.approx(1.0)


def test_c_backend_runs_a_scenario_that_schedules_a_set_point():
    # fopdt_step schedules the fuzzy PI's param r (the set point); the C header compiles params
    # in, so r becomes an input of the C controller fed from the schedule: the verdicts and
    # their details are the numpy engine's (it refused before: issue 30)
    pytest.importorskip("fuzzyc.backends.c.load")
    from fuzzyc.language.parser import load
    model = load(f"{ROOT}/rulebases/fopdt_pi.fz")
    options = dict(max_examples=4, seed=0, shrink_rounds=1, only="closed_loop")
    numpy_side = verify_model(model, Options(**options))
    c_side = verify_model(model, Options(backend="c", **options))
    assert [r.status for r in c_side] == [r.status for r in numpy_side] != []
    assert all(r.status != Status.UNDECIDED for r in c_side)
    assert [r.evidence[0].detail for r in c_side] == [r.evidence[0].detail for r in numpy_side]
