"""`fuzzyc eval` and `fuzzyc plot` on the shipped WEDM rule base (values as in
test_rulebases_by_hand: e1 = 1, e2 = .75, ce2 = 0 gives du1 = du2 = .75)."""
import json
from pathlib import Path

import pytest

from fuzzyc.cli import main

WEDM = str(Path(__file__).resolve().parents[1] / "rulebases" / "wedm_three_region.fz")


def test_eval_json_lists_outputs_and_fired_rules(capsys):
    assert main(["eval", WEDM, "spark_freq=26", "abnormal_ratio=0.325", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["outputs"]["du1"] == pytest.approx(0.75)
    assert result["outputs"]["feed"] == pytest.approx(0.300135)
    assert sorted(f["activation"] for f in result["fired"]) == pytest.approx([0.5, 0.5])
    assert {f["text"] for f in result["fired"]} == {
        "if e1 is P and e2 is PB and ce2 is ZO then du1 is PB, du2 is PB",
        "if e1 is P and e2 is PS and ce2 is ZO then du1 is PS, du2 is PS"}


def test_eval_core_table(capsys):
    assert main(["eval", WEDM, "e1=1", "e2=1", "ce2=1", "--core"]) == 0
    out = capsys.readouterr().out
    assert "if e1 is P and e2 is PB and ce2 is PB then du1 is PB, du2 is PB" in out
    assert "du1 = 1, du2 = 1" in out


def test_eval_csv_batch(tmp_path, capsys):
    data = tmp_path / "in.csv"
    data.write_text("e1,e2,ce2\n1,1,1\n1,0.75,0\n0.5,0.75,0.75\n")
    assert main(["eval", WEDM, "--csv", str(data), "--core"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0] == "e1,e2,ce2,du1,du2"
    rows = [[float(v) for v in line.split(",")] for line in lines[1:]]
    assert [r[3:] for r in rows] == [pytest.approx(v) for v in ([1, 1], [0.75, 0.75], [0.75, 0.5])]


@pytest.mark.parametrize("args,words", [
    (["spark_freq=26"], "missing input: abnormal_ratio"),
    (["spark_freq=26", "abnormal_ratio=x"], "`x` is not a number"),
    (["spark=26", "abnormal_ratio=0.3"], "`spark` is not an input"),
])
def test_eval_bad_arguments_exit_2(args, words, capsys):
    assert main(["eval", WEDM, *args]) == 2
    assert words in capsys.readouterr().err


def test_eval_bad_csv_cell_names_line_and_column(tmp_path, capsys):
    data = tmp_path / "in.csv"
    data.write_text("spark_freq,abnormal_ratio\n26,0.3\n27,oops\n")
    assert main(["eval", WEDM, "--csv", str(data)]) == 2
    assert f"{data}:3:2: `oops` is not a number" in capsys.readouterr().err


def test_eval_warns_out_of_range_without_clamping(capsys):
    assert main(["eval", WEDM, "spark_freq=250", "abnormal_ratio=0.3", "--json"]) == 0
    assert "outside its range [0, 200] (not clamped)" in capsys.readouterr().err


def test_plot_writes_pngs(tmp_path, capsys):
    assert main(["plot", WEDM, "-o", str(tmp_path), "--inputs", "e2,ce2", "--at", "e1=0"]) == 0
    names = {p.name for p in tmp_path.glob("*.png")}
    assert {"wedm_three_region_e1_terms.png", "wedm_three_region_du1_surface.png",
            "wedm_three_region_du2_surface.png"} <= names
    assert all((tmp_path / n).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for n in names)
