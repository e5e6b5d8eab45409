"""The tool bugs the differential fuzzer recognises (tests/differential/toolbugs.py): each
claimed only with its evidence, each reproduced on a hand-written file against the live tool
(skipped where the tool is not installed), and a disagreement without the evidence left one."""
from __future__ import annotations

from pathlib import Path

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
    fails, works = tools.run("octave", [(EMPTY, np.array([[1.0], [5.0], [8.0]]), ["x"], ["y"]),
                                        (EMPTY, np.array([[1.0], [3.0], [8.0]]), ["x"], ["y"])])
    assert isinstance(fails, Exception) and OCTAVE_ERROR in str(fails)
    assert np.allclose(works[:, 0], [0.2, 0.2, 0.9])


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
