"""No verdict stronger than its evidence (`fuzzyc verify`, monotone properties).

- A monotone rule table is not a proof that the defuzzified output is monotone: PROVED only
  when the proof engine decided it, otherwise HELD on the grid and search cases.
- A table that goes against the direction is a warning about the table; VIOLATED needs two
  evaluated points where the output moves the wrong way, and the report shows them.
"""
from pathlib import Path

import numpy as np

from fuzzyc.engine import inference as engine
from fuzzyc.cli import main
from fuzzyc.language.parser import parse
from fuzzyc.verifier import Options, Status, verify_model

ROOT = Path(__file__).resolve().parents[1]
FOPDT = (ROOT / "rulebases" / "fopdt_pi.fz").read_text()

# A tipper whose OR rule concludes `generous` wherever the food is delicious: the cells
# (poor, delicious) and (good, delicious) each hold two conclusions (cheap + generous, average +
# generous), so the table reads generous -> average one service term up. The output does not
# fall: with singletons 5 / 15 / 25, d = delicious(food), for service s in [0, 5] the weights
# are 1 - s/5, s/5, d and tip = (5 + 2 s + 25 d) / (1 + d), rising in s; on [5, 10] the weight
# moves from average (15) to generous (25), which also only raises it.
TIPPER = """\
controller tipper_or "A tipper whose OR rule puts two conclusions in a cell" {
  input service in [0, 10]
  input food in [0, 10]
  terms service : uniform poor good excellent
  terms food : uniform rancid delicious
  var tip in [0, 30] default 15
  terms tip : singletons cheap=5 average=15 generous=25

  inference and = min, or = max, aggregation = max, defuzzify = center_of_area

  rule if service is poor then tip is cheap
  rule if service is good then tip is average
  rule if service is excellent or food is delicious then tip is generous

  verify {
    monotone tip increasing in service
  }
}
"""
# ... and one where rancid food also makes the tip cheap: where rancid(food) holds `cheap` at a
# constant weight while `average` grows, a tip above 15 (much generous) is pulled down.
TIPPER_BAD = TIPPER.replace("if service is poor then", "if service is poor or food is rancid then")


def _verify(text, name):
    model = parse(text, name)
    return model, verify_model(model, Options(max_examples=100, seed=0))


def test_a_monotone_table_is_not_a_proof():
    # fopdt_pi.fz: a monotone diagonal table, max-min-style center of area: no proof method
    model, results = _verify(FOPDT, "fopdt_pi.fz")
    mono = [r for r in results if r.prop.kind == "monotone"]
    assert len(mono) == 2
    for r in mono:
        by = {e.method: e for e in r.evidence}
        assert by["table"].status == Status.UNDECIDED       # a remark, never PROVED
        assert "rule table is monotone" in by["table"].detail
        assert by["proof"].status == Status.UNDECIDED
        assert r.status == Status.HELD
        # 141 x 141 grid points (budget 20,000 over two inputs) and 100 examples
        assert r.summary() == "held: grid 19881 points, search 100 examples"


def test_the_same_table_is_proved_when_the_proof_engine_decides():
    # and = product, aggregation = sum over a uniform partition: multilinear per cell
    text = FOPDT.replace("aggregation = max", "aggregation = sum")
    _, results = _verify(text, "fopdt_sum.fz")
    for r in (r for r in results if r.prop.kind == "monotone"):
        assert r.status == Status.PROVED and r.summary() == "proved (proof)"
        assert [e.method for e in r.evidence if e.status == Status.PROVED] == ["proof"]


def test_or_rule_cells_are_a_table_warning_not_a_violation(tmp_path, capsys):
    model, (r,) = _verify(TIPPER, "tipper_or.fz")
    table = r.evidence[0]
    assert table.method == "table" and table.status == Status.WARNING
    # the two cells, each named with the rules that conclude there (lines 11 + 13, 12 + 13)
    assert table.cells == [
        "tip is generous in (service is poor and food is delicious) [rule at line 11; rule at "
        "line 13] but average at a higher service in (service is good and food is delicious) "
        "[rule at line 12; rule at line 13]"]
    assert r.status == Status.HELD and not r.is_failure
    assert r.summary() == "held: grid 19881 points, search 100 examples; table warning"
    # a dense line check agrees: 2,001 points along service at 11 food values, no decrease
    s = np.linspace(0, 10, 2001)
    for food in np.linspace(0, 10, 11):
        tip = engine.evaluate(model.rulebase, np.column_stack([s, np.full_like(s, food)]))[:, 0]
        assert np.diff(tip).min() > -1e-9
    # the command: exit 0, the warning and its cells in the report
    path = tmp_path / "tipper_or.fz"
    path.write_text(TIPPER)
    assert main(["verify", str(path)]) == 0
    out = capsys.readouterr().out
    assert "HELD     tipper_or.fz::monotone tip increasing in service  [held: grid 19881 " \
           "points, search 100 examples; table warning" in out
    assert "table: warning - 1 pair(s) of cells go against `increasing`" in out
    assert "cell: tip is generous in (service is poor and food is delicious)" in out


def test_a_real_decrease_is_violated_with_two_points_that_reevaluate(tmp_path, capsys):
    model, (r,) = _verify(TIPPER_BAD, "tipper_bad.fz")
    assert r.status == Status.VIOLATED and r.is_failure
    bad = r.violation
    assert bad.method == "grid" and bad.point and bad.to_point
    a = np.array([[bad.point["service"], bad.point["food"]]])
    b = np.array([[bad.to_point["service"], bad.to_point["food"]]])
    assert b[0, 0] > a[0, 0] and b[0, 1] == a[0, 1]     # more service, same food
    ya, yb = (engine.evaluate(model.rulebase, x)[0, 0] for x in (a, b))
    assert yb < ya - 1e-9                                 # the tip falls: a real counterexample
    assert f"{ya:.6g}" in bad.detail and f"{yb:.6g}" in bad.detail
    path = tmp_path / "tipper_bad.fz"
    path.write_text(TIPPER_BAD)
    assert main(["verify", str(path)]) == 1
    out = capsys.readouterr().out
    assert "VIOLATED tipper_bad.fz::monotone tip increasing in service  [violated (grid)" in out
    assert f"at service={a[0, 0]:.6g}, food={a[0, 1]:.6g}" in out
    assert f"then service={b[0, 0]:.6g}, food={b[0, 1]:.6g}" in out


def test_the_table_warning_does_not_hide_a_cell_from_a_recorded_finding():
    # a finding note explains a violation only if it names every warned table place
    bad = TIPPER_BAD.replace("verify {", 'note "finding: monotone tip increasing in service '
                             '-- [rule at line 11; rule at line 13]"\n  verify {')
    _, (r,) = _verify(bad, "tipper_bad.fz")
    # the note names the places of the first cell pair only, not [rule at line 11; rule at
    # line 12] of the second: still a failure
    assert r.status == Status.VIOLATED and r.finding is None and r.is_failure
