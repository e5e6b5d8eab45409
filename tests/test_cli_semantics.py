"""`--semantics` on eval, simulate, verify, compile: the source tool's arithmetic where it
differs from fuzzyc's exact one, with hand-computed values (RAMP_FLL of
tests/test_formats_tool_dialects.py: one rule, `up` = Triangle 0 1 1 fired fully at x = 1)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.engine.chain import Controller
from fuzzyc.formats import read_fll
from test_formats_tool_dialects import RAMP_FLL

# WeightedAverage grouped by Maximum (fuzzyc's and pyfuzzylite's center of area; fuzzylite 6
# sums over the rules): two rules conclude `high`.
TWO_RULES_FLL = """Engine: two
InputVariable: x
  range: 0 1
  term: on Ramp 0 1
  term: off Ramp 1 0
OutputVariable: y
  range: 0 10
  default: 0
  aggregation: Maximum
  defuzzifier: WeightedAverage
  term: high Constant 10
  term: low Constant 0
RuleBlock: r
  implication: Minimum
  rule: if x is on then y is high
  rule: if x is off then y is high
  rule: if x is off then y is low
"""


def _eval(tmp_path, capsys, text, *args):
    path = tmp_path / "m.fll"
    path.write_text(text)
    assert main(["eval", str(path), *args, "--core", "--json"]) == 0
    return json.loads(capsys.readouterr().out)["outputs"]["y"]


def test_eval_follows_the_sampled_centroid_of_each_tool(tmp_path, capsys):
    # exact: int u*u / int u on [0, 1] = (1/3) / (1/2) = 2/3
    assert _eval(tmp_path, capsys, RAMP_FLL, "x=1") == pytest.approx(2 / 3, abs=1e-15)
    # fuzzylite at 3 midpoints 1/6, 1/2, 5/6: sum u^2 / sum u = (35/36) / (3/2) = 35/54
    assert _eval(tmp_path, capsys, RAMP_FLL, "x=1", "--semantics", "fuzzylite:3") == \
        pytest.approx(35 / 54, abs=1e-15)
    # Octave at 3 points 0, 1/2, 1, trapz: (1/8 + 1/4) / (1/4 + 1/4) = 0.75, with a second
    # rule (not firing at x = 1)
    two = RAMP_FLL + "  rule: if x is not on then y is up\n"
    assert _eval(tmp_path, capsys, two, "x=1", "--semantics", "octave:3") == \
        pytest.approx(0.75, abs=1e-15)
    # with RAMP_FLL's one rule the toolkit's AggMethod reduces that rule's row over the samples
    # (aggregate_output_mamdani.m): the set is max(0, 1/2, 1) = 1 at every sample, its
    # centroid the middle, 1/2
    assert _eval(tmp_path, capsys, RAMP_FLL, "x=1", "--semantics", "octave:3") == \
        pytest.approx(0.5, abs=1e-15)


def test_controller_under_fuzzylite_gives_its_numbers_and_nan_where_nothing_fires():
    model = read_fll(RAMP_FLL, "ramp.fll")
    controller = Controller(model, 2, "fuzzylite:3")
    controller.step({"x": np.array([1.0, 0.0])})
    # x = 1: 35/54 as above; x = 0 fires nothing: fuzzylite's `default: nan`
    y = controller.signals["y"]
    assert y[0] == pytest.approx(35 / 54, abs=1e-15) and np.isnan(y[1])
    exact = Controller(model, 2)
    exact.step({"x": np.array([1.0, 0.0])})
    # fuzzyc's own: 2/3, and the number the import took for the default (0, said in a note)
    np.testing.assert_allclose(exact.signals["y"], [2 / 3, 0.0], rtol=0, atol=1e-15)


def test_compile_and_verify_take_the_tools_weighted_average_or_refuse(tmp_path, capsys):
    path = tmp_path / "two.fll"
    path.write_text(TWO_RULES_FLL)
    # x = 0.5: rules 0.5 -> 10, 0.5 -> 10, 0.5 -> 0.  Grouped per term (pyfuzzylite, fuzzyc):
    # high = max(0.5, 0.5) = 0.5: (0.5*10 + 0.5*0) / 1 = 5; fuzzylite 6, over the rules:
    # (0.5*10 + 0.5*10 + 0.5*0) / 1.5 = 20/3
    assert _eval(tmp_path, capsys, TWO_RULES_FLL, "x=0.5") == pytest.approx(5, abs=1e-14)
    assert _eval(tmp_path, capsys, TWO_RULES_FLL, "x=0.5", "--semantics", "fuzzylite") == \
        pytest.approx(20 / 3, abs=1e-14)
    out = tmp_path / "c"
    assert main(["compile", str(path), "--semantics", "fuzzylite", "-o", str(out)]) == 0
    header = (out / "two.h").read_text()
    assert main(["compile", str(path), "-o", str(out)]) == 0
    assert (out / "two.h").read_text() != header     # the tool's defuzzifier, not fuzzyc's
    capsys.readouterr()
    ramp = tmp_path / "ramp.fll"
    ramp.write_text(RAMP_FLL)
    for command in (["compile", str(ramp), "-o", str(out)], ["verify", str(ramp)]):
        assert main([*command, "--semantics", "fuzzylite"]) == 2
        err = capsys.readouterr().err
        assert "fuzzylite samples the centroid" in err and "computes exactly" in err


def test_unknown_semantics_is_refused(tmp_path, capsys):
    path = tmp_path / "m.fll"
    path.write_text(RAMP_FLL)
    for bad in ("fuzzylight", "fuzzylite:1", "octave:x"):
        assert main(["eval", str(path), "x=1", "--core", "--semantics", bad]) == 2
        assert "--semantics" in capsys.readouterr().err
