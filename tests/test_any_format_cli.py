"""`fuzzyc verify`, `simulate` and `learn` read every rule-file format (fuzzyc.formats.load_any);
a file without properties is verified on the structural defaults (fuzzyc.verifier docstring)."""
import math
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.engine.inference import activations
from fuzzyc.formats import load_any
from fuzzyc.language.parser import load
from fuzzyc.plants import scenario as scenarios
from fuzzyc.runtime.simulate import simulate
from fuzzyc.verifier import Options, verify_file, verify_model
from fuzzyc.verifier.runner import default_properties
from conftest import ROOT

CORPUS = ROOT / "tests/format_corpus"
FAST = Options(max_examples=5, grid_budget=2000)


def _verdicts(path) -> dict[str, str]:
    return {r.prop.text: r.status.value for r in verify_file(str(path), FAST)}


def _best_firing(path, service: float, food: float) -> float:
    rb = load_any(path).rulebase
    return float(activations(rb, np.array([[service, food]])).max())


# ------------------------------------------------------------------ verify: the defaults
def test_verify_reads_fll_and_checks_the_defaults_with_the_hand_verdicts(capsys):
    status = main(["verify", str(CORPUS / "tipper.fll"), "--max-examples", "5"])
    out = capsys.readouterr().out
    assert status == 1                                   # violations, not bad input (was 2)
    assert ("tipper.fll: declares no properties; checking the structural defaults: consistent; "
            "complete; covers service, food at least 0.5; bounded tip in [0, 30]") in out
    assert "PROVED   tipper.fll::default: consistent" in out
    # complete: 4 x 4 = 16 cells (service poor/good/excellent/perfect x food
    # rancid/fine/delicious/fresh). Rule 1 (poor OR rancid) covers the poor row and the rancid
    # column, rule 3 (excellent OR delicious) that row and column: left are service in
    # {good, perfect} x food in {fine, fresh}, of which rule 2 takes (good, fine) and rule 4
    # (perfect, fresh): (good, fresh) and (perfect, fine) have no rule.
    assert "VIOLATED tipper.fll::default: complete" in out
    assert "(service is good and food is fresh)" in out
    assert "(service is perfect and food is fine)" in out
    assert "VIOLATED tipper.fll::default: covers service, food at least 0.5" in out
    assert "PROVED   tipper.fll::default: bounded tip in [0, 30]" in out
    assert "4 properties: 2 proved, 0 held, 2 violated" in out


def test_the_fll_tipper_does_not_cover_at_one_half_by_hand():
    # at service = 3, food = 3 (min for and, max for or):
    # rule 1: max(poor = (4-3)/4 = 0.25, rancid = 1/(1+e^(3*(3-2))) = 0.0474) = 0.25
    # rule 2: min(good = (3-2)/3 = 1/3, fine = exp(-(3-5)^2/(2*1.5^2)) = 0.411) = 1/3
    # rule 3: max(excellent = 0, delicious = 1/(1+|(3-9)/1.5|^4) = 1/257) = 1/257
    # rule 4: min(perfect = 0, fresh = 0) = 0         -> best 1/3 < 0.5
    assert _best_firing(CORPUS / "tipper.fll", 3.0, 3.0) == pytest.approx(1 / 3, abs=1e-12)
    assert _verdicts(CORPUS / "tipper.fll")["covers service, food at least 0.5"] == "violated"


def test_the_fcl_and_fis_tippers_are_complete_but_do_not_cover_at_one_half():
    # FCL: 3 x 3 cells; rule 1 poor row + rancid column (5), rule 2 (good, tasty), rule 3
    # excellent and not rancid (excellent: tasty, delicious), rule 4 not poor and delicious
    # (good, delicious): all 9. At service 2.5, food 2.25: poor = 1-2.5/4 = 0.375,
    # good = (2.5-1)/3 = 0.5, rancid = (3-2.25)/2 = 0.375, tasty = exp(-3.75^2/4.5) = 0.044:
    # rule 1 = 0.375, rule 2 = 0.044, rules 3, 4 = 0 (excellent = delicious = 0)
    assert _best_firing(CORPUS / "tipper.fcl", 2.5, 2.25) == pytest.approx(0.375, abs=1e-12)
    # FIS: 3 x 2 cells; rule 1 poor row + rancid column, rule 2 the good row (food any), rule
    # 3 excellent row + delicious column: all 6. At service 2.5, food 5: gaussians of sigma
    # 1.5 at 0 and 5 both give exp(-2.5^2/(2*1.5^2)) = exp(-25/18) = 0.249; rancid (0 0 1 3)
    # and delicious (7 9 10 10) are 0: the best rule fires 0.249
    assert _best_firing(CORPUS / "tipper.fis", 2.5, 5.0) == pytest.approx(math.exp(-25 / 18),
                                                                         abs=1e-12)
    expected = {"consistent": "proved", "complete": "proved",
                "covers service, food at least 0.5": "violated",
                "bounded tip in [0, 30]": "proved"}
    assert _verdicts(CORPUS / "tipper.fcl") == expected
    assert _verdicts(CORPUS / "tipper.fis") == expected


def test_a_fz_without_verify_gets_the_same_defaults(tmp_path, capsys):
    fz = tmp_path / "tipper.fz"
    assert main(["convert", str(CORPUS / "tipper.fll"), str(fz)]) == 0
    assert "verify" not in fz.read_text()
    assert _verdicts(fz) == _verdicts(CORPUS / "tipper.fll") == {
        "consistent": "proved", "complete": "violated",
        "covers service, food at least 0.5": "violated", "bounded tip in [0, 30]": "proved"}


def test_a_fz_with_verify_runs_only_its_own_properties(capsys):
    model = load(f"{ROOT}/rulebases/edm_sink_gap.fz")
    results = verify_model(model, Options(max_examples=5, only="co"))   # covers, consistent...
    assert [r.prop for r in results] == [p for p in model.properties if "co" in p.text]
    assert all("default:" not in r.name and r.prop.loc is not None for r in results)
    status = main(["verify", f"{ROOT}/rulebases/edm_sink_gap.fz", "--only", "consistent"])
    out = capsys.readouterr().out
    assert status == 0 and "declares no properties" not in out
    assert "PROVED   edm_sink_gap.fz::consistent" in out


def test_the_coverage_level_is_the_and_of_one_half_over_the_inputs(tmp_path, capsys):
    fz = tmp_path / "tipper.fz"
    main(["convert", str(CORPUS / "tipper.fll"), str(fz)])
    text = fz.read_text()
    # product of two inputs each at 0.5: 0.5 * 0.5 = 0.25
    fz.write_text(text.replace("and = min", "and = product"))
    assert "covers service, food at least 0.25" in [p.text for p in default_properties(load(fz))]
    # bounded difference: max(0, 0.5 + 0.5 - 1) = 0, no level can be asked: left out, said so
    fz.write_text(text.replace("and = min", "and = bounded_difference"))
    assert [p.kind for p in default_properties(load(fz))] == ["consistent", "complete", "bounded"]
    capsys.readouterr()
    main(["verify", str(fz), "--max-examples", "5"])
    assert "no `covers`: with and = bounded_difference" in capsys.readouterr().out


def test_verify_of_a_missing_block_is_bad_input(capsys):
    status = main(["verify", str(CORPUS / "blocks_tipper_fan.fcl::nosuch")])
    assert status == 2 and "nosuch" in capsys.readouterr().err


# ------------------------------------------------------------------ simulate
FEEDER = """controller feeder "static feed from the cutting force" {
  period 150 ms
  input force in [0, 600]
  terms force : low = lshoulder(100, 300), ok = tri(100, 300, 500), high = rshoulder(300, 500)
  var f in [0, 75] default 0
  terms f : slow = tri(0, 10, 20), medium = tri(15, 30, 45), fast = tri(40, 60, 75)
  inference and = min, implication = min, aggregation = max, defuzzify = centroid
  rule if force is low then f is fast
  rule if force is ok then f is medium
  rule if force is high then f is slow
  output feed in [0, 75] = f
}
"""


@pytest.fixture
def feeder(tmp_path, capsys):
    """feeder.fz, its FLL translation by `fuzzyc convert` with the output variable named like
    the plant input (feed.fll), and the translation as written (output `f`: feeder.fll)."""
    fz = tmp_path / "feeder.fz"
    fz.write_text(FEEDER)
    assert main(["convert", str(fz), str(tmp_path / "feeder.fll")]) == 0
    fll = (tmp_path / "feeder.fll").read_text()
    renamed = fll.replace("OutputVariable: f\n", "OutputVariable: feed\n") \
                 .replace("then f is", "then feed is")
    assert renamed.count("then feed is") == 3 and "OutputVariable: feed\n" in renamed
    (tmp_path / "feed.fll").write_text(renamed)
    capsys.readouterr()
    return tmp_path


def _trace(path: Path, **extra):
    scenario = scenarios.load("milling_step", {"controller.rulebase": str(path),
                                               "duration": "6", **extra})
    return simulate(scenario)


def test_an_imported_model_whose_names_match_runs_the_same_loop_as_the_fz(feeder, capsys):
    ours, theirs = _trace(feeder / "feeder.fz"), _trace(feeder / "feed.fll")
    assert set(ours.signals) == set(theirs.signals)
    for name in ours.signals:
        np.testing.assert_allclose(theirs[name], ours[name], rtol=0, atol=1e-12)
    assert float(np.ptp(ours["feed"])) > 1.0             # the force changed the feed: a real loop
    out = feeder / "out"
    status = main(["simulate", str(feeder / "feed.fll"), "--scenario", "milling_step",
                   "--set", "duration=3", "-o", str(out)])
    assert status == 0 and "feed.fll" in capsys.readouterr().out
    assert (out / "trace.csv").exists()


def test_an_imported_model_runs_on_the_c_back_end_too(feeder):
    # the bus names are the wrapper's, the model keeps `feed_out` (C would refuse an output
    # named like the rule-base variable); C computes in float: 38.7 mm/min of swing agree to
    # about 1.5e-5
    numpy_feed = _trace(feeder / "feed.fll")["feed"]
    scenario = scenarios.load("milling_step", {"controller.rulebase": str(feeder / "feed.fll"),
                                               "duration": "6"})
    np.testing.assert_allclose(simulate(scenario, backend="c")["feed"], numpy_feed,
                               rtol=0, atol=1e-4)


def test_an_fcl_block_is_chosen_with_double_colon(feeder, capsys):
    assert main(["convert", str(feeder / "feed.fll"), str(feeder / "one.fcl")]) == 0
    block = (feeder / "one.fcl").read_text()
    other = block.replace("FUNCTION_BLOCK feeder", "FUNCTION_BLOCK other")
    (feeder / "two.fcl").write_text(block + "\n" + other)
    ref = f"{feeder / 'two.fcl'}::feeder"
    np.testing.assert_allclose(_trace(ref)["feed"], _trace(feeder / "feeder.fz")["feed"],
                               rtol=0, atol=1e-12)
    status = main(["simulate", ref, "--scenario", "milling_step", "--set", "duration=1",
                   "-o", str(feeder / "out")])
    assert status == 0 and "two.fcl::feeder" in capsys.readouterr().out


def test_names_that_do_not_match_are_an_error_naming_them(feeder, capsys):
    # the translation as written: output variable `f`, which the milling plant does not read
    status = main(["simulate", str(feeder / "feeder.fll"), "--scenario", "milling_step",
                   "-o", str(feeder / "out")])
    err = capsys.readouterr().err
    assert status == 2
    assert "feeder.fll:10:17: error: output `f` drives nothing in scenario `milling_step` " \
           "(plant milling); it reads: feed" in err
    assert "Traceback" not in err
    # the same for a .fz, on its inputs: (was a KeyError from the loop's first period)
    (feeder / "typo.fz").write_text(FEEDER.replace("force", "forse"))
    status = main(["simulate", str(feeder / "typo.fz"), "--scenario", "milling_step",
                   "-o", str(feeder / "out")])
    err = capsys.readouterr().err
    assert status == 2
    assert ("typo.fz:3:9: error: input `forse` is not a signal of scenario `milling_step` "
            "(plant milling); it has: cutting, done, feed, feed_actual, force, position") in err


def test_a_scenario_param_an_imported_model_lacks_keeps_its_error(feeder, capsys):
    status = main(["simulate", str(feeder / "feed.fll"), "--scenario", "milling_step",
                   "--set", "controller.params.Vset=50", "-o", str(feeder / "out")])
    assert status == 2
    assert "`controller.params.Vset`: the rule base has no param `Vset`" in \
        capsys.readouterr().err


# ------------------------------------------------------------------ learn
def test_learn_on_an_imported_model_says_it_has_no_learnable_terms(tmp_path, capsys):
    status = main(["learn", str(CORPUS / "tipper.fll"), "--scenario", "milling_step",
                   "-o", str(tmp_path / "out.fz"), "--cycles", "1"])
    err = capsys.readouterr().err
    assert status == 2
    assert "tipper.fll: the model has no learnable terms" in err
    assert "`fuzzyc convert` it to .fz" in err
    assert not (tmp_path / "out.fz").exists()


def test_learn_names_the_learnable_outputs_when_table_is_wrong(tmp_path, capsys):
    status = main(["learn", f"{ROOT}/rulebases/milling_neurofuzzy.fz", "--scenario", "milling_step",
                   "-o", str(tmp_path / "out.fz"), "--table", "feed"])
    assert status == 2
    assert "output `feed` has no learnable terms (choose one of du with --table)" in \
        capsys.readouterr().err
