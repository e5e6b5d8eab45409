"""`fuzzyc eval --csv`: rows as independent points (default) or as a time series (--series, as
examples/c reads them), and NAME=VALUE holding an input the CSV lacks.

WEDM three-region at spark_freq = 26 or 20 kHz, abnormal_ratio = 0.325 (test_cli_eval_plot):
e1 = clamp((30 - 26) * 0.25) = 1 (and clamp(2.5) = 1 at 20 kHz), e2 = (0.40 - 0.325) * 10 =
0.75, ce2 = delta(e2) = 0 for a constant input, so du1 = 0.75 every sample and
feed = feed(k-1) + 1.8e-4 * 0.75 = previous + 0.000135 from the initial 0.3 mm/min.
"""
import shutil
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.language.parser import load

WEDM = str(Path(__file__).resolve().parents[1] / "rulebases" / "wedm_three_region.fz")


def csv_rows(capsys) -> tuple[list[str], np.ndarray]:
    lines = capsys.readouterr().out.strip().splitlines()
    return lines[0].split(","), np.array([[float(v) for v in line.split(",")]
                                          for line in lines[1:]])


@pytest.fixture
def steady(tmp_path) -> Path:
    data = tmp_path / "in.csv"
    data.write_text("spark_freq,abnormal_ratio\n26,0.325\n26,0.325\n26,0.325\n")
    return data


def test_rows_are_independent_points_by_default(steady, capsys):
    assert main(["eval", WEDM, "--csv", str(steady)]) == 0
    header, rows = csv_rows(capsys)
    feed = rows[:, header.index("feed")]
    assert feed == pytest.approx([0.300135] * 3)       # each row: 0.3 + 0.000135


def test_series_carries_the_integrators_from_row_to_row(steady, capsys):
    assert main(["eval", WEDM, "--csv", str(steady), "--series"]) == 0
    header, rows = csv_rows(capsys)
    assert rows[:, header.index("du1")] == pytest.approx([0.75] * 3)
    assert rows[:, header.index("feed")] == pytest.approx([0.300135, 0.30027, 0.300405])


def test_name_value_holds_an_input_the_csv_lacks(tmp_path, capsys):
    data = tmp_path / "in.csv"
    data.write_text("spark_freq\n26\n20\n")
    assert main(["eval", WEDM, "--csv", str(data), "abnormal_ratio=0.325"]) == 0
    header, rows = csv_rows(capsys)
    assert header == ["spark_freq", "abnormal_ratio", "du1", "du2", "feed", "t_off"]
    assert rows[:, 1] == pytest.approx([0.325, 0.325])
    assert rows[:, header.index("du1")] == pytest.approx([0.75, 0.75])
    assert rows[:, header.index("feed")] == pytest.approx([0.300135, 0.300135])


@pytest.mark.parametrize("args,words", [
    (["abnormal_ratio=0.3"], "given both as NAME=VALUE and as a column"),
    (["--series", "--core"], "the rule base alone (--core) has no state"),
    (["spark=1"], "`spark` is not an input"),
])
def test_refused_with_a_reason(steady, capsys, args, words):
    assert main(["eval", WEDM, "--csv", str(steady), *args]) == 2
    assert words in capsys.readouterr().err


def test_series_without_csv_refused(capsys):
    assert main(["eval", WEDM, "spark_freq=26", "abnormal_ratio=0.3", "--series"]) == 2
    assert "--series reads the rows of --csv" in capsys.readouterr().err


def test_series_is_what_the_c_example_computes(tmp_path, capsys):
    """examples/c/main.c steps one controller through its input lines: the same numbers as
    `eval --csv --series` (float C against the double engine: 5e-5 of the output range)."""
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    from test_c_chain import build_example, run_csv
    model = load(WEDM)
    assert main(["compile", WEDM, "-o", str(tmp_path)]) == 0
    program = build_example(tmp_path, model.name, tmp_path / "controller")
    seq = np.random.default_rng(1).uniform([0, 0], [60, 1], (200, 2))
    data = tmp_path / "series.csv"
    rows_text = "".join(f"{a:.17g},{b:.17g}\n" for a, b in seq)
    data.write_text("spark_freq,abnormal_ratio\n" + rows_text)
    capsys.readouterr()
    assert main(["eval", WEDM, "--csv", str(data), "--series"]) == 0
    header, rows = csv_rows(capsys)
    names = [o.name for o in model.outputs]
    expected = rows[:, [header.index(n) for n in names]]
    assert np.ptp(expected[:, 0]) > 0.01                  # the feed really moves
    span = np.array([o.hi - o.lo for o in model.outputs])
    got = run_csv(program, seq)
    assert np.all(np.abs(got - expected) <= 5e-5 * span)
    # and the rows taken one by one are not a series: the independent mode differs
    assert main(["eval", WEDM, "--csv", str(data)]) == 0
    _, independent = csv_rows(capsys)
    assert np.abs(independent[:, header.index("feed")] - expected[:, 0]).max() > 0.01
