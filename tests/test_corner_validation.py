"""`python -m fuzzyc.plants.corner_table --against FILE`: the corner model scored against
measured errors (Table 4 is held out of the project, so the files here are made up, each with
the answer it must give)."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.plants import corner_table, corner_validation as cv

HEADER = ", ".join(cv.COLUMNS)
ROWS = np.array([[50.0, 160.0], [21.0, 40.0]])


def write(tmp_path, *lines: str):
    path = tmp_path / "table4.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def row_text(h, f, normal, controlled) -> str:
    return ", ".join(f"{v:.6g}" for v in [h, f, *normal, *controlled])


def test_within_is_relative_to_the_measurement_and_includes_the_bound():
    # 125 / 100 - 1 = 0.25 (in), 126 / 100 - 1 = 0.26 (out), 75 / 100 - 1 = -0.25 (in)
    got = cv.within(np.array([125.0, 126.0, 75.0, 74.0]), np.array([100.0] * 4))
    assert got.tolist() == [True, False, True, False]


@pytest.fixture(scope="module")
def predicted():
    return corner_table.predict(ROWS)


def measured_file(tmp_path, predicted, scale: float):
    """Measured = the model's normal errors, and its controlled errors times `scale`."""
    lines = ["# made up: the model's own numbers, controlled ones scaled", HEADER]
    for (h, f), n, c in zip(ROWS, predicted["normal"], predicted["controlled"]):
        lines.append(row_text(h, f, n, c * scale))
    return write(tmp_path, *lines)


def test_target_met_when_every_controlled_cell_is_within_25_percent(tmp_path, predicted, capsys):
    # model / measured = 1 / 1.2 = 0.833: 16.7 % under, inside +-25 %; model time +7.0 / +0.6 %
    path = measured_file(tmp_path, predicted, 1.2)
    assert corner_table.main(["--against", str(path)]) == 0
    out = capsys.readouterr().out
    assert "controlled cells within +-25 %: 10 of 10 (target 8)" in out
    assert "normal machining cells within +-25 %: 10 of 10" in out
    assert "model machining time: at most +7.0%" in out and "\ntarget met\n" in out


def test_target_missed_and_cells_marked_when_the_model_is_off(tmp_path, predicted, capsys,
                                                            monkeypatch):
    # model / measured = 1 / 1.4 = 0.714: 28.6 % under, outside; every cell is marked.
    # The loop at the file's rows is the fixture's (the test above runs it through main)
    def same_rows(rows):
        assert rows.tolist() == ROWS.tolist()
        return predicted
    monkeypatch.setattr(corner_table, "predict", same_rows)
    path = measured_file(tmp_path, predicted, 1.4)
    assert corner_table.main(["--against", str(path)]) == 1
    out = capsys.readouterr().out
    assert "controlled cells within +-25 %: 0 of 10 (target 8)" in out
    assert out.count(" *") == 10 and "\ntarget NOT met\n" in out
    # the first row's 30 deg cell: measured 1.4 x 84.37 = 118.1 um, ratio 118.1 / 210.9 = 0.56
    assert "| 50 | 160 | 118.1 (0.56) / 84.4 (0.40) *" in out


def test_a_slow_model_misses_the_target_even_when_every_cell_agrees():
    measured = cv.Measured(ROWS, np.full((2, 5), 50.0), np.full((2, 5), 20.0))
    predicted = {"normal": np.full((2, 5), 50.0), "controlled": np.full((2, 5), 20.0),
                 "normal_time": np.array([100.0, 100.0]), "time": np.array([105.0, 111.0])}
    result = cv.score(measured, predicted, np.zeros((2, 5)))
    assert result.controlled_within.all() and not result.met     # +11 % > +10 %


def test_columns_in_any_order(tmp_path):
    names = list(reversed(cv.COLUMNS))
    values = {"thickness": 50, "feed": 160, **{f"normal_{a}": 100 + a for a in cv.ANGLES},
              **{f"controlled_{a}": 50 + a for a in cv.ANGLES}}
    path = write(tmp_path, ",".join(names), ",".join(str(values[n]) for n in names))
    got = cv.read_measured(path)
    assert got.conditions.tolist() == [[50, 160]]
    assert got.normal.tolist() == [[130, 160, 190, 220, 250]]
    assert got.controlled.tolist() == [[80, 110, 140, 170, 200]]


GOOD = row_text(50, 160, [200, 90, 70, 40, 20], [90, 40, 30, 20, 12])


@pytest.mark.parametrize("lines, where, words", [
    ([], "1:1", "no header line"),
    ([HEADER], "1:1", "no rows under the header"),
    (["thickness, feed, normal_30"], "1:1", "missing column(s) normal_60"),
    ([HEADER + ", time"], "1:", "unknown column 'time'"),
    (["thickness, thickness" + HEADER[9:]], "1:12", "column 'thickness' named twice"),
    ([HEADER, "50, 160, 1"], "2:1", "3 fields, the header names 12"),
    ([HEADER, GOOD.replace("200", "2OO")], "2:10", "normal_30: '2OO' is not a finite number"),
    ([HEADER, GOOD.replace("200", "inf")], "2:10", "normal_30: 'inf' is not a finite number"),
    ([HEADER, GOOD.replace("200", "-1")], "2:10", "a corner error in um, above 0"),
    ([HEADER, GOOD.replace("160", "400")], "2:5", "feed: 400 is outside (0, 250]"),
    ([HEADER, "# a comment", GOOD, GOOD], "4:1", "already on line 3"),
])
def test_bad_files_are_refused_with_their_place(tmp_path, capsys, lines, where, words):
    path = write(tmp_path, *lines)
    with pytest.raises(FuzzycError) as err:
        cv.read_measured(path)
    assert f"{path}:{where}" in str(err.value) and words in str(err.value)
    # the command line prints the same, no traceback, and exits with 2
    assert corner_table.main(["--against", str(path)]) == 2
    err_text = capsys.readouterr().err
    assert words in err_text and "Traceback" not in err_text


def test_a_file_that_is_not_utf8_or_missing_is_refused(tmp_path, capsys):
    path = tmp_path / "latin1.csv"
    path.write_bytes(HEADER.encode() + b"\n\xe9\n")
    assert corner_table.main(["--against", str(path)]) == 2
    assert f"{path}:2:1: error: byte 0xe9 is not UTF-8" in capsys.readouterr().err
    assert corner_table.main(["--against", str(tmp_path / "none.csv")]) == 2
    assert "cannot read" in capsys.readouterr().err


def test_commanded_reduction_at_50_mm_160_and_90_deg_by_hand():
    # feed 160 between B (145) and VB (180): B 20/35 = 0.571, VB 15/35 = 0.429; thickness 50 is
    # B; angle 90: M = (135 - 90)/52.5 = 0.857, B = (90 - 82.5)/52.5 = 0.143. Rules 20 (B B M ->
    # VB) 0.571, 21 (B B B -> M) 0.143, 26 (VB B M -> VB) 0.429, 27 (VB B B -> M) 0.143; max:
    # VB 0.571, M 0.143; centre of area (0.571 x 60 + 0.143 x 30)/0.714 = 54.0 %.
    # At 21 mm, 40 mm^2/min, 150 deg: feed VS, angle B, rule 3 -> VS = 5 %.
    got = cv.commanded_reduction(np.array([[50.0, 160.0], [21.0, 40.0]]))
    assert got[0, 2] == pytest.approx(54.0, abs=0.05)
    assert got[1, 4] == pytest.approx(5.0, abs=1e-9)
    # the user's like scales it: 2 x 5 = 10 %
    assert cv.commanded_reduction(np.array([[21.0, 40.0]]), like=2.0)[0, 4] == pytest.approx(10.0)


def test_force_linear_floor_by_hand():
    # Table 2's fit: H = 10.7071 mm, E0(90) = 11.2 um, s(90) = 0.034975; x = 160 (10.7071/2 +
    # 50/8) = 1856.6, s x = 64.93 um; keep 1 - 0.54 = 0.46: 0.46 x 64.93 / (11.2 + 64.93)
    # = 0.392. With no reduction the floor is the force part's share, 0.853.
    rows = np.array([[50.0, 160.0]])
    assert cv.force_linear_floor(rows, np.full((1, 5), 54.0))[0, 2] == pytest.approx(0.392,
                                                                                      abs=2e-3)
    assert cv.force_linear_floor(rows, np.zeros((1, 5)))[0, 2] == pytest.approx(0.853, abs=2e-3)


def test_report_marks_measured_ratios_under_the_force_linear_floor():
    # the floors of the 21 mm, 40 mm^2/min row at its commands (15, 9.3, 5, 5, 5 %):
    # 0.11 0.26 0.47 0.25 0.13; measured ratios 0.40 everywhere: the 90 deg cell is under its
    # floor (lag and vibration at keep 0.95 leave 0.47 of the normal error even without E0)
    rows = np.array([[21.0, 40.0]])
    reduction = cv.commanded_reduction(rows)
    measured = cv.Measured(rows, np.full((1, 5), 50.0), np.full((1, 5), 20.0))
    predicted = {"normal": np.full((1, 5), 50.0), "controlled": np.full((1, 5), 45.0),
                 "normal_time": np.array([100.0]), "time": np.array([101.0])}
    result = cv.score(measured, predicted, reduction)
    assert result.floor[0] == pytest.approx([0.11, 0.26, 0.47, 0.25, 0.13], abs=0.01)
    assert result.below_floor.tolist() == [[False, False, True, False, False]]
    out = cv.report(measured, predicted, result)
    assert "| 21 | 40 | 0.40 / 0.11 | 0.40 / 0.26 | 0.40 / 0.47 ! |" in out
    assert out.endswith("measured under the force-linear floor: 1 of 5 cells\n")


def test_the_floor_table_in_docs_is_the_one_computed():
    # docs/plants.md prints the floors of Table 4's rows at the shipped rules' commands
    from pathlib import Path
    from fuzzyc.plants.wedm_corner import TABLE4_CONDITIONS
    text = (Path(__file__).resolve().parents[1] / "docs" / "plants.md").read_text("utf-8")
    section = text.split("### The force-linear floor")[1].split("###")[0]
    rows = [line.split("|")[1:-1] for line in section.splitlines()
            if line.startswith("| ") and line[2].isdigit()]
    printed = np.array([[float(c) for c in row[2:]] for row in rows])
    assert [[float(row[0]), float(row[1])] for row in rows] == TABLE4_CONDITIONS.tolist()
    floor = cv.force_linear_floor(TABLE4_CONDITIONS, cv.commanded_reduction(TABLE4_CONDITIONS))
    assert printed == pytest.approx(np.round(floor, 2), abs=1e-9)
