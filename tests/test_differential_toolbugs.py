"""The tool bugs the differential fuzzer recognises (tests/differential/toolbugs.py): each
claimed only with its evidence, each reproduced on a hand-written file against the live tool
(skipped where the tool is not installed), and a disagreement without the evidence left one."""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from tests.differential import toolbugs, tools
from tests.differential.compare import disagreeing_rows, ours

FILES = Path(__file__).resolve().parent / "differential" / "toolbug_files"
SEMI = FILES / "pyfuzzylite_semiellipse_end.fll"
EMPTY = FILES / "octave_empty_sugeno.fis"
OCTAVE_ERROR = "next_agg_output(1,_): out of bound 0 (dimensions are 0x0)"


def _semi_case():
    # x at the semi-ellipse's start, inside, at its end (10.99: r^2 - (x - c)^2 < 0 there)
    x = np.array([[7.651], [9.0], [10.99]])
    got = ours(SEMI, x, "pyfuzzylite")
    assert got.status == "imported", got.message
    return x, got.y


def test_semi_ellipse_end_by_hand():
    x, y = _semi_case()
    # the semi-ellipse is 0 at its ends: `not half` fires 1 alone, y = 2 (the Constant low)
    assert y[2, 0] == pytest.approx(2.0)
    tool = y.copy()
    tool[2, 0] = np.nan                     # what pyfuzzylite 8.0.6 gives there (live below)
    tolerance = np.array([1e-6 * 10])
    rows = disagreeing_rows(y, tool, tolerance)
    assert rows.tolist() == [2]
    why = toolbugs.explain_disagreement("pyfuzzylite-fll", toolbugs.fll_input_terms(
        SEMI.read_text()), x, y, tool, tolerance, rows)
    assert why.startswith("pyfuzzylite 8 bug: SemiEllipse membership NaN at its end")
    assert "x = 10.99" in why


def test_semi_ellipse_bug_not_claimed_without_its_evidence():
    x, y = _semi_case()
    tolerance = np.array([1e-5])
    inside = y.copy()
    inside[1, 0] = np.nan                   # NaN at 9.0, inside the term: no evidence
    assert toolbugs.explain_disagreement("pyfuzzylite-fll", toolbugs.fll_input_terms(
        SEMI.read_text()), x, y, inside, tolerance, disagreeing_rows(y, inside, tolerance)) \
        is None
    number = y.copy()
    number[2, 0] = 5.0                      # a number, not NaN, at the end: a disagreement
    assert toolbugs.explain_disagreement("pyfuzzylite-fll", toolbugs.fll_input_terms(
        SEMI.read_text()), x, y, number, tolerance, disagreeing_rows(y, number, tolerance)) \
        is None


def test_semi_ellipse_end_live():
    why = tools.available("pyfuzzylite")
    if why:
        pytest.skip(why)
    x, y = _semi_case()
    (tool,) = tools.run("pyfuzzylite", [(SEMI, x, ["x"], ["y"])])
    assert not isinstance(tool, Exception), tool
    assert np.isnan(tool[2, 0]) and np.allclose(tool[:2], y[:2])


def test_octave_empty_sugeno_by_hand():
    # x = 5 lies in no term: no rule fires; x = 1 and 8 fire one rule each
    x = np.array([[1.0], [5.0], [8.0]])
    got = ours(EMPTY, x, "octave")
    assert got.status == "imported" and got.y[:, 0].tolist() == pytest.approx([0.2, 0.5, 0.9])
    why = toolbugs.explain_error("octave-fis", OCTAVE_ERROR, EMPTY, x)
    assert why.startswith("Octave toolkit bug: evalfis fails where no rule fires")
    assert "1 of 3 rows fire nothing, e.g. row 1" in why
    # the same error where every row fires something is not this bug
    assert toolbugs.explain_error("octave-fis", OCTAVE_ERROR, EMPTY, x[[0, 2]]) is None
    assert toolbugs.explain_error("octave-fis", "some other error", EMPTY, x) is None


def test_octave_empty_sugeno_live():
    why = tools.available("octave")
    if why:
        pytest.skip(why)
    fails, works, none = tools.run("octave", [
        (EMPTY, np.array([[1.0], [5.0], [8.0]]), ["x"], ["y"]),
        (EMPTY, np.array([[1.0], [3.0], [8.0]]), ["x"], ["y"]),
        (EMPTY, np.array([[5.0], [4.5]]), ["x"], ["y"])])
    # evalfis fails the matrix; row by row it gives rows 0 and 2 and fails row 1 (x = 5)
    assert isinstance(fails, tools.RowsFailed) and OCTAVE_ERROR in str(fails)
    assert fails.rows.tolist() == [1] and fails.y[[0, 2], 0].tolist() == pytest.approx([0.2, 0.9])
    assert np.allclose(works[:, 0], [0.2, 0.2, 0.9])
    # no row evaluates: a plain tool error
    assert isinstance(none, Exception) and not isinstance(none, tools.RowsFailed)


def test_a_file_is_judged_on_the_rows_the_tool_evaluates(tmp_path):
    from tests.differential.judge import _verdict
    x = np.array([[1.0], [5.0], [8.0]])
    mine = ours(EMPTY, x, "octave")
    # the parts of a differential.spec System a verdict reads (the file is EMPTY)
    output = SimpleNamespace(name="y", lo=0.0, hi=1.0, default=np.nan)
    system = SimpleNamespace(inputs=[], outputs=[output], sugeno=True)
    tool = tools.RowsFailed(OCTAVE_ERROR, np.array([[0.2], [np.nan], [0.9]]), np.array([1]))
    verdict = _verdict(system, EMPTY, x, mine, tool, "octave-fis")
    # rows 0 and 2 agree (0.2, 0.9 by hand above); row 1 fires nothing: the bug's evidence
    assert verdict.status == "tool-bug" and verdict.x.tolist() == [[1.0], [8.0]]
    assert verdict.message.startswith("Octave toolkit bug: evalfis fails where no rule fires")
    assert verdict.message.endswith("1 of 3 rows fire nothing, e.g. row 1; the rows it "
                                    "evaluates agree")
    # the failed rows must be exactly the silent ones: row 0 claimed failed is not the bug
    wrong = tools.RowsFailed(OCTAVE_ERROR, np.array([[np.nan], [np.nan], [0.9]]),
                             np.array([0, 1]))
    assert _verdict(system, EMPTY, x, mine, wrong, "octave-fis").status == "tool-error"
    far = tools.RowsFailed(OCTAVE_ERROR, np.array([[0.5], [np.nan], [0.9]]), np.array([1]))
    assert _verdict(system, EMPTY, x, mine, far, "octave-fis").status == "disagree"


SEMI_DEFAULT = FILES / "pyfuzzylite_semiellipse_end_default.fll"


def test_semi_ellipse_end_with_a_numeric_default():
    # pyfuzzylite replaces the NaN by the output's default (3.3): the same bug, its evidence
    x = np.array([[7.651], [9.0], [10.99]])
    got = ours(SEMI_DEFAULT, x, "pyfuzzylite")
    tool = got.y.copy()
    tool[2, 0] = 3.3
    tolerance = np.array([1e-5])
    rows = disagreeing_rows(got.y, tool, tolerance)
    text = SEMI_DEFAULT.read_text()
    assert toolbugs.fll_output_defaults(text) == [3.3]
    why = toolbugs.explain_disagreement("pyfuzzylite-fll", toolbugs.fll_input_terms(text), x,
                                        got.y, tool, tolerance, rows,
                                        toolbugs.fll_output_defaults(text))
    assert why and "x = 10.99" in why
    # without the default the same number is a disagreement
    assert toolbugs.explain_disagreement("pyfuzzylite-fll", toolbugs.fll_input_terms(text), x,
                                         got.y, tool, tolerance, rows) is None
    if tools.available("pyfuzzylite") is None:        # the live tool says so too
        (live,) = tools.run("pyfuzzylite", [(SEMI_DEFAULT, x, ["x"], ["y"])])
        assert live[2, 0] == 3.3 and np.allclose(live[:2], got.y[:2])


HAMACHER = FILES / "octave_hamacher_sum_noise.fis"


def test_octave_hamacher_noise_by_hand(tmp_path):
    # x = 5: rules 1 and 3 fire 1 (t1, a trapezoid 1 on [3, 6]), rule 2 fires b = exp(-25/8),
    # 0.044, on t2.  On the plateau the fold is 0 -> 1 -> hamacher(1, 0.044 g) -> then 1 again:
    # the value is 1 throughout, computed (1 - v) / (1 - v) with v an ulp from 1 (the toolkit
    # gives 2 there, live below); fuzzyc's fold meets that step, the evidence.
    x = np.array([[3.0], [5.0], [7.0]])
    got = ours(HAMACHER, x, "octave")
    tool = got.y.copy()
    tool[1, 0] = 4.0                        # a som elsewhere on the plateau
    tolerance = np.array([1e-3 * 10])
    rows = disagreeing_rows(got.y, tool, tolerance)
    assert rows.tolist() == [1]
    why = toolbugs.explain_octave_disagreement(HAMACHER, x, got.y, tool, tolerance, rows)
    assert why.startswith("Octave toolkit bug: hamacher_sum.m's")
    assert "1 row(s), e.g. y: rule" in why
    # the same disagreement on a file aggregating with max is no such bug
    other = tmp_path / "hamacher_max.fis"
    other.write_text(HAMACHER.read_text().replace("'hamacher_sum'", "'max'"))
    assert toolbugs.explain_octave_disagreement(other, x, got.y, tool, tolerance, rows) is None


def test_octave_hamacher_noise_live():
    """The toolkit's aggregated set (evalfis's fourth output) holds 2 on the plateau, where
    the s-norm is 1."""
    why = tools.available("octave")
    if why:
        pytest.skip(why)
    import subprocess
    script = ("pkg load fuzzy-logic-toolkit; warning('off', 'all');"
              f" f = readfis('{HAMACHER}'); [o, ri, ro, fo] = evalfis(5, f);"
              " printf('%.17g\\n', max(fo));")
    done = subprocess.run(["octave", "--no-gui", "--quiet", "--no-window-system", "--eval",
                           script], capture_output=True, text=True, timeout=120)
    assert float(done.stdout.split()[0]) == 2.0


EMPTY_DSIGMF = FILES / "octave_empty_sugeno_dsigmf.fis"


def test_octave_empty_sugeno_dsigmf():
    # d = dsigmf [2 3 0.5 7]: at x = 0 1 / (1 + e^6) - 1 / (1 + e^3.5) = 0.00247 - 0.0293 < 0,
    # which the toolkit clips to 0 (dsigmf.m: no rule fires, evalfis fails, live below) and
    # fuzzyc's own reading takes as |difference| = 0.027: the evidence reads the toolkit's.
    # At x = 5: 0.982 - 0.269 = 0.713, the rule fires: 0.8.
    x = np.array([[0.0], [5.0]])
    why = toolbugs.explain_error("octave-fis", OCTAVE_ERROR, EMPTY_DSIGMF, x)
    assert why and "1 of 2 rows fire nothing, e.g. row 0" in why
    assert toolbugs.explain_error("octave-fis", OCTAVE_ERROR, EMPTY_DSIGMF, x[1:]) is None
    if tools.available("octave") is None:
        fails, works = tools.run("octave", [(EMPTY_DSIGMF, x, ["x"], ["y"]),
                                            (EMPTY_DSIGMF, x[1:], ["x"], ["y"])])
        assert isinstance(fails, Exception) and OCTAVE_ERROR in str(fails)
        assert works[0, 0] == pytest.approx(0.8)


SEMI_NUMBER = FILES / "pyfuzzylite_semiellipse_end_number.fll"


def _semi_number_case(x):
    tri = SimpleNamespace(shape="Triangle", params=[9.0, 11.0, 13.0])
    half = SimpleNamespace(shape="SemiEllipse", params=[7.651, 10.99])
    system = SimpleNamespace(
        inputs=[SimpleNamespace(name="x", terms=[half, tri])], sugeno=False,
        outputs=[SimpleNamespace(name="y", lo=0.0, hi=10.0, default=np.nan)])
    mine = ours(SEMI_NUMBER, x, "pyfuzzylite")
    return system, mine


def test_semi_ellipse_end_that_drops_a_rule_live():
    # x = 10.99, the semi-ellipse's end: half = 0, `not half` = 1 keeps big (6, 8, 10) whole
    # (area 2, centroid 8); high = (10.99 - 9) / 2 = 0.995 clips small (0, 2, 4): area
    # (4 + 0.02) / 2 * 0.995 = 1.99995, centroid 2; y = (16 + 3.9999) / 3.99995 = 5.0000375.
    # pyfuzzylite's half is NaN there, its rule dropped: 2 (live); one ulp inside, 5.0000375.
    from tests.differential.judge import _semi_ellipse_numbers, _verdict
    why = tools.available("pyfuzzylite")
    if why:
        pytest.skip(why)
    x = np.array([[9.0], [10.99]])
    system, mine = _semi_number_case(x)
    assert mine.y[:, 0] == pytest.approx([8.0, 5.0000375], abs=1e-6)
    (tool,) = tools.run("pyfuzzylite", [(SEMI_NUMBER, x, ["x"], ["y"])])
    assert tool[:, 0] == pytest.approx([8.0, 2.0], abs=1e-6)
    verdict = _verdict(system, SEMI_NUMBER, x, mine, tool, "pyfuzzylite-fll")
    assert verdict.status == "disagree"
    _semi_ellipse_numbers("pyfuzzylite", [system], [SEMI_NUMBER], [mine], [verdict])
    assert verdict.status == "tool-bug"
    assert "x = 10.99 -> 10.989999999999998" in verdict.message


def test_a_number_apart_inside_a_semi_ellipse_is_no_tool_bug():
    from tests.differential.judge import _semi_ellipse_numbers, _verdict
    x = np.array([[9.0], [10.5]])            # 10.5: inside the term, the formula a number
    system, mine = _semi_number_case(x)
    tool = mine.y.copy()
    tool[1, 0] = 2.0
    verdict = _verdict(system, SEMI_NUMBER, x, mine, tool, "pyfuzzylite-fll")
    _semi_ellipse_numbers("pyfuzzylite", [system], [SEMI_NUMBER], [mine], [verdict])
    assert verdict.status == "disagree"
