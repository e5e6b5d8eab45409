"""`fuzzyc tune` on the command line: the tuned file, its provenance, reproducibility by seed
(two runs byte-identical), and located refusals."""
from __future__ import annotations

import hashlib

import numpy as np
import pytest

from fuzzyc.cli.main import main
from fuzzyc.language.parser import load
from fuzzyc.tune.space import Space

from test_tune_fit import TWO_SINGLETONS


@pytest.fixture
def files(tmp_path):
    rule = tmp_path / "hand.fz"
    rule.write_text(TWO_SINGLETONS % ("weighted_average", 10))
    train = tmp_path / "train.csv"
    train.write_text("x,y,note\n0,-1,7\n0.5,2,7\n1,4,7\n")    # the hand-computed fit's data
    check = tmp_path / "check.csv"
    check.write_text("y,x\n0,0.25\n")
    return rule, train, check


def test_tune_writes_the_tuned_file(files, tmp_path, capsys):
    rule, train, check = files
    out = tmp_path / "tuned.fz"
    assert main(["tune", str(rule), "--data", str(train), "--validate", str(check),
                 "--seed", "3", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "2 numbers tuned by ANFIS hybrid" in printed
    # RMSE before: y = x, errors 1, 1.5, 3; after: sqrt(1/18) (test_tune_fit)
    assert f"RMSE on {train}: {np.sqrt(12.25 / 3):.6g} before, {np.sqrt(1 / 18):.6g} after" \
        in printed
    text = out.read_text()
    sha = hashlib.sha256(train.read_bytes()).hexdigest()
    assert text.startswith("# ---- fuzzyc tune: provenance\n# tuned from hand.fz (sha256 ")
    assert f"# data train.csv sha256 {sha}, 3 rows\n" in text
    assert "# seed 3, passes 20" in text
    assert f"RMSE before 0.25, after {5 / 12:.6g}" in text      # at x = 0.25: 5/12
    assert Space(load(out)).x0 == pytest.approx([-5 / 6, 25 / 6], abs=1e-6)
    assert text.split("# ---- end of provenance\n")[1].replace(
        "singleton(" + repr(float(Space(load(out)).x0[0])) + ")", "singleton(0)").replace(
        "singleton(" + repr(float(Space(load(out)).x0[1])) + ")", "singleton(1)") == \
        rule.read_text()                    # nothing else of the file changed


def test_two_runs_are_byte_identical(files, tmp_path):
    rule, train, _ = files
    outs = [tmp_path / f"run{i}.fz" for i in range(3)]
    for out, seed in zip(outs, (5, 5, 6)):
        assert main(["tune", str(rule), "--data", str(train), "--folds", "3",
                     "--seed", str(seed), "-o", str(out)]) == 0
    assert outs[0].read_bytes() == outs[1].read_bytes()
    # another seed splits the folds otherwise: the file says so (its seed line at least)
    assert outs[0].read_bytes() != outs[2].read_bytes()
    assert "# 3-fold cross-validation RMSE " in outs[0].read_text()


def test_refusals(files, tmp_path, capsys):
    rule, train, check = files
    bad = tmp_path / "bad.csv"
    bad.write_text("x,z\n1,2\n")
    assert main(["tune", str(rule), "--data", str(bad), "-o", str(tmp_path / "o.fz")]) == 2
    assert "no column for y (the header has x, z)" in capsys.readouterr().err
    bad.write_text("x,y\n1,oops\n")
    assert main(["tune", str(rule), "--data", str(bad), "-o", str(tmp_path / "o.fz")]) == 2
    assert "bad.csv:2: a row of numbers is needed for x, y" in capsys.readouterr().err
    plain = tmp_path / "plain.fz"
    plain.write_text(rule.read_text().split("  tune {")[0] + "}\n")
    assert main(["tune", str(plain), "--data", str(train), "-o", str(tmp_path / "o.fz")]) == 2
    assert "has no `tune` section" in capsys.readouterr().err
    broken = tmp_path / "broken.fz"
    broken.write_text(rule.read_text().replace("y.a.value", "y.c.value"))
    assert main(["tune", str(broken), "--data", str(train), "-o", str(tmp_path / "o.fz")]) == 2
    assert "broken.fz:11:7: error: `y` has no term `c`" in capsys.readouterr().err
    # never over an input, and an existing file only with --force
    assert main(["tune", str(rule), "--data", str(train), "-o", str(rule), "--force"]) == 2
    assert f"{rule} is the input file {rule}" in capsys.readouterr().err
    assert main(["tune", str(rule), "--data", str(train), "-o", str(train), "--force"]) == 2
    assert f"{train} is the input file {train}" in capsys.readouterr().err
    out = tmp_path / "exists.fz"
    out.write_text("mine")
    assert main(["tune", str(rule), "--data", str(train), "-o", str(out)]) == 2
    assert "not overwriting" in capsys.readouterr().err and out.read_text() == "mine"
    assert main(["tune", str(rule), "--data", str(train), "-o", str(out), "--force"]) == 0
    assert out.read_text().startswith("# ---- fuzzyc tune: provenance")
    with pytest.raises(SystemExit):        # --validate and --folds exclude each other
        main(["tune", str(rule), "--data", str(train), "--validate", str(check),
              "--folds", "2", "-o", str(tmp_path / "o.fz")])


def test_the_api_gives_the_commands_text(files, tmp_path):
    import fuzzyc
    rule, train, check = files
    out = tmp_path / "tuned.fz"
    assert main(["tune", str(rule), "--data", str(train), "--validate", str(check),
                 "-o", str(out)]) == 0
    result = fuzzyc.tune(rule, train, validate=check)
    assert result.text == out.read_text()
    assert result.fit.values == pytest.approx([-5 / 6, 25 / 6], abs=1e-6)
    import fuzzyc.tune as package                 # the package is the same callable
    assert package(rule, train, validate=check).text == result.text
