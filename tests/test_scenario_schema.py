"""Scenario files whose values have the wrong type: a located message (file:line:col of the
offending value or key), never a traceback. The first five are the tracebacks of issue 13
(plots, metrics and keys of the wrong type); the columns are counted by hand below."""
import re
from pathlib import Path

import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.plants import scenario as S

HEAD = "plant: {model: wedm_gap}\ncontroller: {rulebase: wedm_three_region.fz}\n"   # lines 1-2
METRIC = "  - {name: overshoot, signal: abnormal_ratio, target: Yr2}\n"


@pytest.mark.parametrize("tail, line, col, words", [
    # `plots: 3` -- the value 3 starts in column 8 ("plots: " is 7 characters)
    ("plots: 3\n", 3, 8, "`plots`: must be a list of signal names, got 3"),
    # `plots: [[a]]` -- the inner list starts at column 9, just after "plots: ["
    ("plots: [[a]]\n", 3, 9, "`plots.0`: must be a signal name"),
    # `metrics: {a: 1}` -- a mapping where a list belongs, at column 10
    ("metrics: {a: 1}\n", 3, 10, "`metrics`: must be a list"),
    # a metric that is a number: "  - " is 4 characters, the 7 is in column 5
    ("metrics:\n  - 7\n", 4, 5, "`metrics.0`: must be a mapping"),
    # a key that is a number is an unknown key, reported at the key (column 1)
    ("1: 2\n", 3, 1, "`1`: unknown key"),
    # a section that is a number: "baseline: " is 10 characters
    ("baseline: 3\n", 3, 11, "`baseline`: must be a mapping, got 3"),
    # name: [1] -- "  - {name: " is 11 characters, the [ is in column 12
    ("metrics:\n  - {name: [1], signal: x}\n", 4, 12, "unknown metric [1]"),
    # settling_time without its band: reported at the metric's mapping (column 5)
    ("metrics:\n  - {name: settling_time, signal: x}\n", 4, 5, "settling_time needs `band:`"),
    # tail: 0 -- "  - {name: mean, signal: x, tail: " is 34 characters
    ("metrics:\n  - {name: mean, signal: x, tail: 0}\n", 4, 35, "a fraction in (0, 1]"),
    # duration: .inf (YAML infinity) at column 11
    ("duration: .inf\n", 3, 11, "`duration`: must be a positive number of seconds, got inf"),
    # 1 s of 1e-9 s periods is 1e9 periods, over the 1e7 limit: at the duration's value
    ("duration: 1\nperiod: 1.0e-9\n", 3, 11, "more than 10,000,000 periods"),
    # "initial: {feed: " is 16 characters
    ("initial: {feed: x}\n", 3, 17, "`initial.feed`: must be a finite number, got 'x'"),
    ("schedules: {Yr2: [[0, .nan]]}\n", 3, 18, "a list of [time, value] pairs"),
    ("baseline: {make: 3}\n", 3, 18, "`baseline.make`: must be module.Callable"),
    ("observers: [{make: a.b, parms: {}}]\n", 3, 25, "`observers.0.parms`: unknown key"),
    ("title: {a: 1}\n", 3, 8, "`title`: must be text"),
    # "  - {name: mean, signal: x, scale: " is 35 characters
    ("metrics:\n  - {name: mean, signal: x, scale: x}\n", 4, 36, "`metrics.0.scale`: must be a"),
    ("metrics:\n  - {name: mean, signal: x, where: 3}\n", 4, 36, "`metrics.0.where`: must be the"),
])
def test_wrong_types_are_located(tmp_path, tail, line, col, words):
    path = tmp_path / "bad.yaml"
    path.write_text(HEAD + tail, encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        S.load(path)
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (line, col), diagnostic.format()
    assert words in diagnostic.message


def test_plant_param_of_the_wrong_type_is_located_at_its_value(tmp_path):
    # "    height: " is 12 characters: the value starts in column 13 of line 4
    path = tmp_path / "bad.yaml"
    path.write_text("plant:\n  model: wedm_gap\n  params:\n    height: thirty\n", encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        S.load(path).plant_params()
    diagnostic = info.value.diagnostics[0]
    assert str(diagnostic.loc).endswith("bad.yaml:4:13")
    assert "must be a finite number, got 'thirty'" in diagnostic.message


def test_text_that_is_not_utf8_or_not_yaml_is_located(tmp_path):
    path = tmp_path / "bad.yaml"
    # the byte 0xff follows "plant: " (7 bytes) on line 2: column 8
    path.write_bytes(b"title: x\nplant: \xff\n")
    with pytest.raises(FuzzycError) as info:
        S.load(path)
    assert str(info.value.diagnostics[0].loc).endswith("bad.yaml:2:8")
    # a form feed is not allowed in YAML: the reader stops at it, line 2 column 3
    path.write_text("title: x\nab\f\n", encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        S.load(path)
    assert str(info.value.diagnostics[0].loc).endswith("bad.yaml:2:3")
    assert "not valid YAML" in info.value.diagnostics[0].message


def test_alias_bomb_is_refused_where_it_passes_the_limit(tmp_path):
    # 9 levels of 9 aliases: 9**9 values written out; refused at the alias that passes
    # scenario_yaml.MAX_NODES (a6: 2 * 9**6 > 200,000), before anything walks it
    lines = ["a0: &a0 [x]"] + [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]"
                               for i in range(1, 10)]
    path = tmp_path / "bomb.yaml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(FuzzycError, match=r"bomb.yaml:7:\d+: error: .*more than 200,000 values"):
        S.load(path)


@pytest.mark.parametrize("name, message", [("a" * 300, "no scenario"),
                                           ("a" * 300 + ".yaml", "no such file"),
                                           ("x\0.yaml", "no such file")])
def test_a_name_the_system_refuses_is_no_scenario(name, message):
    # found by the fuzzer: a 300-character name made Path.exists() raise ENAMETOOLONG
    with pytest.raises(FuzzycError, match=message):
        S.resolve(name)


@pytest.mark.parametrize("name", ["examples/gymnasium/cartpole.yaml", "mine.yml", "sub/wedm_finish"])
def test_a_missing_scenario_file_is_no_such_file(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)        # relative to an empty folder (the root has examples/)
    with pytest.raises(FuzzycError, match=re.escape(f"no such file: {name} (")):
        S.resolve(name)
    assert S.resolve("wedm_finish") == S.SCENARIO_DIR / "wedm_finish.yaml"    # names still work


EXAMPLES = sorted(str(p) for p in (Path(__file__).parents[1] / "examples").rglob("*.yaml"))


@pytest.mark.parametrize("name", S.available() + EXAMPLES)
def test_every_shipped_scenario_passes_the_schema(name):
    # notes may be one text or a list of texts (edm_sink, milling_* have lists); the
    # Gymnasium examples' plant keys are gym_env's (checked without importing Gymnasium)
    assert S.load(name).data["plant"]["model"]


def test_notes_of_the_wrong_type_are_located(tmp_path):
    path = tmp_path / "bad.yaml"
    # "notes: [a, " is 11 characters: the {b: 1} starts in column 12
    path.write_text(HEAD + "notes: [a, {b: 1}]\n", encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        S.load(path)
    assert str(info.value.diagnostics[0].loc).endswith("bad.yaml:3:12")
    assert "`notes.1`: must be text" in info.value.diagnostics[0].message


@pytest.mark.parametrize("baseline", [False, True])
def test_an_observer_reading_a_signal_nobody_writes_is_located(tmp_path, baseline):
    # found by the fuzzer: edm_sink's filter (measured_voltage -> gap_voltage) with the plant
    # spliced to wedm_gap, which writes no measured_voltage: a KeyError in the filter's step.
    # "  - " is 4 characters: the observer's mapping starts in column 5 of line 5
    from fuzzyc.runtime.simulate import simulate
    path = tmp_path / "bad.yaml"
    path.write_text(HEAD + "baseline: {make: wedm_gap.VoltageP}\nobservers:\n"
                    "  - make: filters.lowpass_bandstop\n"
                    "    params: {input_name: measured_voltage, output_name: v, fs: 1000}\n"
                    "duration: 0.2\n", encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        simulate(S.load(path), baseline=baseline)
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (5, 5), diagnostic.format()
    assert "`observers.0`: reads `measured_voltage`, which is not on the bus" in \
        diagnostic.message


def test_a_baseline_that_drives_none_of_the_plants_inputs_is_located(tmp_path):
    # found by the fuzzer: the milling plant spliced with the corner scenario's baseline
    # (which gives `reduction`, not `feed`): a KeyError in the plant's first step.
    # `model` follows "plant: {" (8 characters) on line 1: column 9
    from fuzzyc.runtime.simulate import simulate
    path = tmp_path / "bad.yaml"
    path.write_text("plant: {model: milling}\n"
                    "baseline: {make: wedm_corner.NoCornerControl}\nduration: 2\n",
                    encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        simulate(S.load(path), baseline=True)
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (1, 9), diagnostic.format()
    assert diagnostic.message == ("`plant.model`: the plant needs `feed` from the controller, "
                                  "a schedule or `initial`; the controller gives reduction")


@pytest.mark.parametrize("params, col, words", [
    # found by the fuzzer: a text for the estimator's gamma (a required param, no default to
    # compare with) reached its first step, a TypeError in a division. On line 4,
    # "  - {" is 5 characters, "make: height_estimator.HeightEstimator, " 40: `params` starts
    # in column 46, "params: {gamma: " is 16 more: the value in column 62.
    ("{gamma: x1, ratio_ref: 0.389}", 62, "`observers.0.params.gamma`: must be a finite number"),
    ("{gamma: 2.0e-5, ratio_ref: abc}", 46, "`ratio_ref` must be a finite number, got 'abc'"),
])
def test_an_observer_param_of_the_wrong_type_is_located(tmp_path, params, col, words):
    from fuzzyc.runtime.simulate import simulate
    path = tmp_path / "bad.yaml"
    path.write_text(HEAD + "observers:\n"
                    f"  - {{make: height_estimator.HeightEstimator, params: {params}}}\n"
                    "duration: 0.2\n", encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        simulate(S.load(path))
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (4, col), diagnostic.format()
    assert words in diagnostic.message


def test_a_section_left_empty_that_file_sets_a_key_in_is_located(tmp_path):
    # found by the fuzzer: `controller:` with no value, and FILE given on the command line
    # (it sets controller.rulebase): an error with no place before
    from fuzzyc import api
    path = tmp_path / "bad.yaml"
    path.write_text("plant: {model: wedm_gap}\ncontroller:\nduration: 0.2\n", encoding="utf-8")
    rules = Path(__file__).parents[1] / "rulebases" / "wedm_three_region.fz"
    with pytest.raises(FuzzycError) as info:
        api.simulate(path, rules)
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (2, 1), diagnostic.format()
    assert diagnostic.message == ("`controller`: must be a mapping: `controller.rulebase` is "
                                  "set inside it (by FILE or --set)")


@pytest.mark.parametrize("params, line, col, words", [
    # found by the fuzzer: a list for the milling workpiece reached the first step
    # (AttributeError), a mapping without pieces a KeyError: reported at `params` (line 3,
    # column 3); a number as a param name made the suggestion of a close name raise
    # TypeError: reported at the key (line 4, column 5).
    ("    workpiece: [[20, 6, 6]]\n", 3, 3, "workpiece must be a mapping {start: mm, pieces: "),
    ("    workpiece: {start: 1.0}\n", 3, 3, "workpiece needs `pieces: "),
    ("    0.3: feed\n", 4, 5, "`plant.params.0.3`: MillingParams has no field `0.3`"),
])
def test_plant_params_of_the_wrong_shape_are_located(tmp_path, params, line, col, words):
    from fuzzyc.runtime.simulate import simulate
    path = tmp_path / "bad.yaml"
    path.write_text("plant:\n  model: milling\n  params:\n" + params
                    + "controller: {rulebase: milling_neurofuzzy_learned.fz}\nduration: 1\n",
                    encoding="utf-8")
    with pytest.raises(FuzzycError) as info:
        simulate(S.load(path))
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (line, col), diagnostic.format()
    assert words in diagnostic.message
