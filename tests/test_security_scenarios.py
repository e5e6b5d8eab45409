"""A scenario is data (docs/security.md, "Scenarios are data"; docs/limits.md, "Scenario files").

- Nothing is imported because a YAML file names it: plants, baselines and observers come from
  fuzzyc.plants.registry; a Gymnasium `env: module:Class` (or gymnasium's `module:Id-v0`) only
  with --allow-import / allow_import. A payload module that writes a marker file when imported
  proves it: refused -> no marker, not in sys.modules; allowed -> imported.
- A billion-laughs scenario is refused within a small time and memory bound.
- Hostile shapes that used to be tracebacks (exit 70) are exit 2 with a message at the key.
"""
import subprocess
import sys
import time
import tracemalloc

import pytest
from conftest import ROOT

import fuzzyc
from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.plants import registry, scenario_yaml
from fuzzyc.plants import scenario as scenarios

RULES = ROOT / "rulebases" / "fopdt_pi.fz"
HEAD = f"plant: {{model: fopdt}}\ncontroller: {{rulebase: {RULES}}}\nduration: 1\n"


FILL = """controller fill {
  period 100 ms
  input level in [0, 20]
  let e in [0, 20] = level
  terms e : uniform L H
  var v in [0, 1] default 0
  terms v : singletons Z=0 O=1
  rule r1: if e is L then v is O
  rule r2: if e is H then v is O
  output inflow in [-10, 10] = 5 * v
}
"""


def gym_scenario(env: str, folder) -> str:
    """A Gymnasium scenario naming `env`, with a rule file that fits its signals."""
    (folder / "fill.fz").write_text(FILL)
    return (f"plant:\n  model: gymnasium\n  env: \"{env}\"\n  observations: [level]\n"
            f"  action: inflow\ncontroller: {{rulebase: {folder / 'fill.fz'}}}\n")


@pytest.fixture
def payload(tmp_path, monkeypatch):
    """A module `payload` on sys.path that creates a marker file when it is imported."""
    marker = tmp_path / "IMPORTED"
    (tmp_path / "payload.py").write_text(f"open({str(marker)!r}, 'w').close()\n"
                                         "class Env:\n    pass\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "payload", raising=False)
    return marker


def refusal(path, **kwargs) -> str:
    with pytest.raises(FuzzycError) as info:
        fuzzyc.simulate(path, **kwargs)
    return info.value.diagnostics[0].format()


# --- 1. nothing imported because a file names it ------------------------------------------

@pytest.mark.parametrize("env", ["payload:Env", "payload:Env-v0", "payload.sub:Env"])
def test_a_module_named_by_the_file_is_never_imported(tmp_path, payload, env):
    # `payload:Env-v0` is gymnasium's own "import this module, then look the id up" syntax
    path = tmp_path / "evil.yaml"
    path.write_text(gym_scenario(env, tmp_path))
    message = refusal(path)
    assert "evil.yaml:3:8: error: `plant.env`" in message          # at the value
    assert "--allow-import" in message and "allow_import" in message
    assert "CartPole-v1" in message                  # what a file may name instead
    assert not payload.exists() and "payload" not in sys.modules


def test_unittest_main_and_this_are_not_imported(tmp_path):
    # `unittest.__main__:X` ran unittest discovery (importing test_payload.py beside the
    # scenario) and then sys.exit(0); `this:X` printed the Zen of Python
    marker = tmp_path / "DISCOVERED"
    (tmp_path / "test_payload.py").write_text(f"open({str(marker)!r}, 'w').close()\n")
    for env, module in [("unittest.__main__:NotAnEnv", "unittest.__main__"), ("this:X", "this")]:
        before = module in sys.modules
        path = tmp_path / "evil.yaml"
        path.write_text(gym_scenario(env, tmp_path))
        message = refusal(path)
        assert f"would import the module `{module}`" in message
        assert not marker.exists()
        assert before or module not in sys.modules


def test_an_allowed_module_is_imported(tmp_path, payload):
    pytest.importorskip("gymnasium")
    path = tmp_path / "mine.yaml"
    path.write_text(gym_scenario("payload:Env", tmp_path))
    # imported now: the class is then checked (not a gymnasium.Env, so still refused)
    message = refusal(path, allow_import=["payload"])
    assert payload.exists() and "payload" in sys.modules
    assert "not a gymnasium.Env subclass" in message


def test_the_command_line_allows_a_module(tmp_path, payload, capsys):
    pytest.importorskip("gymnasium")
    path = tmp_path / "mine.yaml"
    path.write_text(gym_scenario("payload:Env", tmp_path))
    out = str(tmp_path / "out")
    assert main(["simulate", "--scenario", str(path), "-o", out]) == 2
    assert not payload.exists() and "--allow-import" in capsys.readouterr().err
    assert main(["simulate", "--scenario", str(path), "-o", out,
                 "--allow-import", "payload"]) == 2
    assert payload.exists()
    assert "not a gymnasium.Env subclass" in capsys.readouterr().err


def test_verify_takes_the_option_too(capsys):
    with pytest.raises(SystemExit):
        main(["verify", "--help"])
    assert "--allow-import MODULE" in capsys.readouterr().out


def test_make_names_only_what_the_registry_lists(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOPSECRET 1 2 3\n")
    cases = {"corner_validation.read_measured": f", params: {{path: {secret}}}",
             "scenario.Path": "", "wedm_corner.fit_table2": "", "corner_table.main": "",
             "scenario_yaml.load": "", "fopdt.step": "", "height_estimator.HeightEstimator": ""}
    for make, params in cases.items():
        path = tmp_path / "make.yaml"
        path.write_text(HEAD + f"baseline: {{make: {make}{params}}}\n")
        message = refusal(path)
        assert f"make.yaml:4:18: error: `baseline.make`: `{make}` is not a baseline" in message
        assert "wedm_gap.VoltageP" in message and "TOPSECRET" not in message
    path.write_text(HEAD + "observers: [{make: wedm_gap.VoltageP}]\n")
    assert "`observers.0.make`: `wedm_gap.VoltageP` is not an observer" in refusal(path)


def test_a_refused_name_imports_no_module_of_fuzzyc_plants(tmp_path):
    # in a fresh interpreter, so no other test has imported the modules already
    path = tmp_path / "make.yaml"
    path.write_text(HEAD + "baseline: {make: corner_table.main}\n"
                    "observers: [{make: corner_validation.read_measured}]\n")
    code = ("import sys, fuzzyc\n"
            "from fuzzyc.plants import scenario\n"
            "try:\n"
            f"    scenario.load({str(path)!r})\n"
            "except fuzzyc.FuzzycError as e:\n"
            "    print(e)\n"
            "print(sorted(m for m in sys.modules if m.startswith('fuzzyc.plants.')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60, cwd=tmp_path).stdout
    assert "`baseline.make`" in out
    assert "corner_table" not in out.splitlines()[-1]
    assert "corner_validation" not in out.splitlines()[-1]


def test_every_registered_name_is_there():
    for name in registry.PLANTS:
        assert hasattr(registry.plant_module(name), "step")
    for kind, names in registry.FACTORIES.items():
        for name in names:
            assert callable(registry.factory(kind, name))
    assert registry.allowed_module("pkg.envs", ["pkg"])
    assert not registry.allowed_module("pkgx", ["pkg"])
    assert not registry.allowed_module("pkg", [])


def test_the_shipped_scenarios_still_load():
    for name in scenarios.available():
        scenarios.load(name)


# --- 2. billion laughs -----------------------------------------------------------------------

LOL = ('a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]\n'
       + "".join(f"{c}: &{c} [*{p},*{p},*{p},*{p},*{p},*{p},*{p},*{p},*{p}]\n"
                 for p, c in zip("abcdefgh", "bcdefghi")))


@pytest.mark.parametrize("key", ["title", "initial"])
def test_billion_laughs_is_refused_quickly_in_little_memory(tmp_path, key):
    path = tmp_path / "laughs.yaml"
    path.write_text(LOL + f"{key}: *i\n")       # 9**9 "lol"s, about 400 bytes
    assert path.stat().st_size < 450
    tracemalloc.start()
    start = time.perf_counter()
    try:
        message = refusal(path)
        elapsed = time.perf_counter() - start
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert elapsed < 5 and peak < 200e6, (elapsed, peak)
    assert "laughs.yaml:6:" in message and "more than 200,000 values" in message
    assert len(message) < 500


def test_a_big_value_under_the_limits_is_shown_in_80_characters(tmp_path):
    path = tmp_path / "big.yaml"
    path.write_text(HEAD + "title:\n  - &a [" + ", ".join(["123456789"] * 300) + "]\n"
                    "  - [" + ", ".join(["*a"] * 300) + "]\n")    # 90,000 values
    start = time.perf_counter()
    message = refusal(path)
    assert time.perf_counter() - start < 5
    assert "`title`: must be text, got [[123456789" in message
    shown = message.split("got ", 1)[1].split("\n")[0]
    assert len(shown) <= 80 and shown.endswith("...")


def test_the_limits_themselves():
    assert scenario_yaml.load("[" * 32 + "]" * 32) is not None
    for text, what in [("[" * 33 + "]" * 33, "nested deeper than 32"),
                       ("a: &a [*a]", "inside its own anchor"),
                       ("a: 1" + "0" * 1000, "more than 1000 characters")]:
        with pytest.raises(Exception, match=what):
            scenario_yaml.load(text)


# --- 3. no tracebacks --------------------------------------------------------------------

CLI_CASES = {
    "deep": (HEAD + "title: " + "[" * 1000 + "]" * 1000 + "\n", "deep.yaml:4:", "title"),
    "path": (HEAD + "baseline: {make: scenario.Path}\n", "deep.yaml:4:18", "`baseline.make`"),
    "fit": (HEAD + "baseline: {make: wedm_corner.fit_table2}\n", "deep.yaml:4:18",
            "`baseline.make`"),
    "main": (HEAD + "baseline: {make: corner_table.main}\n", "deep.yaml:4:18",
             "`baseline.make`"),
    "observer": (HEAD + "observers: [{make: filters.lowpass, params: {input_name: 1.0e-300, "
                 "output_name: yf, order: 2, cutoff_hz: 1, fs: 10}}]\n", "deep.yaml:4:58",
                 "`observers.0.params.input_name`: must be a name"),
    "digits": (HEAD + "period: 1" + "0" * 5000 + "\n", "deep.yaml:4:9",
               "more than 1000 characters"),
    "cycle": (HEAD + "initial: &x {a: *x}\n", "deep.yaml:4:17", "inside its own anchor"),
    "laughs": (LOL + HEAD + "title: *i\n", "deep.yaml:6:", "more than 200,000 values"),
}


@pytest.mark.parametrize("case", sorted(CLI_CASES))
def test_hostile_scenarios_are_exit_2_at_the_key(tmp_path, capsys, case):
    text, where, what = CLI_CASES[case]
    path = tmp_path / "deep.yaml"
    path.write_text(text)
    assert main(["simulate", "--scenario", str(path), "-o", str(tmp_path / "out")]) == 2
    out, err = capsys.readouterr()
    assert where in err and what in err, err[:2000]
    assert "Traceback" not in err and "usage" not in out.lower()


def test_a_deep_set_value_is_exit_2_naming_the_setting(tmp_path, capsys):
    code = main(["simulate", "--scenario", "fopdt_step", "--set", "title=" + "[" * 1000,
                 "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    assert "--set title=[[[" in err and "nested deeper than 32" in err
    assert len(err) < 400                      # the value is shown cut, not 1,000 brackets
