"""The YAML scenario format: loading, overrides, and clear messages for malformed files."""
import json

import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.plants import scenario as S


def test_every_shipped_wedm_scenario_loads_and_builds_its_plant():
    for name in ("wedm_finish", "wedm_setpoint", "wedm_rough", "wedm_step_up",
                 "wedm_step_down"):
        sc = S.load(name)
        assert sc.plant_params().height > 0
        assert sc.rulebase_path().name == "wedm_three_region.fz"


def test_overrides_reach_into_plant_params_and_parse_as_yaml_scalars():
    sc = S.load("wedm_finish", {"plant.tension": "600", "duration": "12.5",
                                "controller.params.Yr2": "0.45"})
    assert sc.plant_params().tension == 600
    assert sc.duration == 12.5
    assert sc.controller["params"]["Yr2"] == 0.45


def test_randomized_params_are_arrays_around_the_value():
    import numpy as np
    sc = S.load("wedm_finish")
    p = sc.plant_params(batch=1000, rng=np.random.default_rng(3), randomize=True)
    assert p.td_ref.shape == (1000,)
    assert np.mean(p.td_ref) == pytest.approx(4.0, rel=0.02)      # 10 % spread, n = 1000
    assert p.height == 30                                          # not randomized


def write(tmp_path, text):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    return path


def message(tmp_path, text, overrides=None):
    with pytest.raises(FuzzycError) as info:
        sc = S.load(write(tmp_path, text), overrides)
        sc.plant_params()
    return info.value.diagnostics[0].format()


def test_unknown_plant_param_names_file_line_and_suggests(tmp_path):
    text = "plant:\n  model: wedm_gap\n  params:\n    tensoin: 800\n"
    msg = message(tmp_path, text)
    assert "bad.yaml:4:" in msg and "tensoin" in msg and "did you mean `tension`" in msg


def test_unknown_top_key_and_bad_schedule_are_located(tmp_path):
    assert "bad.yaml:3:" in message(tmp_path, "plant: {model: wedm_gap}\nduration: 5\nperiode: 1\n")
    msg = message(tmp_path, "plant: {model: wedm_gap}\nschedules:\n  Yr2: [0, 0.4]\n")
    assert "bad.yaml:3:" in msg and "[time, value] pairs" in msg


def test_yaml_syntax_error_and_missing_plant(tmp_path):
    assert "bad.yaml:2:" in message(tmp_path, "plant:\n\tmodel: wedm_gap\n")
    assert "needs `plant:`" in message(tmp_path, "duration: 5\n")
    assert "no plant module `nosuch`" in message(tmp_path, "plant: {model: nosuch}\n")


def test_unknown_scenario_name_suggests_a_shipped_one():
    with pytest.raises(FuzzycError, match="did you mean `wedm_finish`"):
        S.load("wedm_finsh")


def test_cli_simulate_writes_csv_png_and_json(tmp_path):
    from fuzzyc.cli import main
    out = tmp_path / "run"
    status = main(["simulate", "--scenario", "wedm_finish", "--set", "duration=4",
                   "--batch", "3", "--randomize", "-o", str(out)])
    assert status == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["batch"] == 3 and "wire ruptures" in summary["metrics"]
    header = (out / "trace.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "t" and "abnormal_ratio[2]" in header
    assert (out / "trace.png").stat().st_size > 1000


def test_cli_bad_set_is_a_clear_error(tmp_path, capsys):
    from fuzzyc.cli import main
    status = main(["simulate", "--scenario", "wedm_finish", "--set", "noequals", "-o",
                   str(tmp_path)])
    assert status == 2 and "write KEY=VALUE" in capsys.readouterr().err
