"""`fuzzyc learn`: a trained rule file that parses, with the learned weights, and a PI plot."""
from pathlib import Path

import numpy as np

from fuzzyc.cli import main
from fuzzyc.language.parser import load

RULES = Path(__file__).resolve().parents[1] / "rulebases"


def test_learn_writes_a_valid_trained_file_and_plot(tmp_path, capsys):
    out = tmp_path / "trained.fz"
    status = main(["learn", str(RULES / "milling_neurofuzzy.fz"), "--scenario", "milling_step",
                   "-o", str(out), "--cycles", "1"])
    assert status == 0
    printed = capsys.readouterr().out
    assert [line.split(":")[0] for line in printed.splitlines()][:1] == ["cycle   1"]
    trained = load(out)
    weights = trained.rulebase.outputs[0].params[:, 0]
    assert np.count_nonzero(weights) > 0                       # it learned something
    assert weights.min() >= -50 and weights.max() <= 50        # within the declared range
    assert (tmp_path / "trained_pi.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temp left


def test_learn_refuses_a_rule_base_that_is_not_a_weighted_sum(tmp_path, capsys):
    averaged = tmp_path / "averaged.fz"
    text = (RULES / "milling_neurofuzzy.fz").read_text()
    averaged.write_text(text.replace("defuzzify = weighted_sum", "defuzzify = weighted_average"))
    status = main(["learn", str(averaged), "--scenario", "milling_step",
                   "-o", str(tmp_path / "x.fz"), "--cycles", "1"])
    assert status == 2
    assert "weighted_sum" in capsys.readouterr().err
    assert not (tmp_path / "x.fz").exists()
