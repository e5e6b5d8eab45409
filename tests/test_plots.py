"""The pictures' content: units on every axis, one colour per term, the rule viewer's rules,
stems and defuzzified value (hand-computed below), surfaces over the raw inputs, fuzzy and
baseline on one figure, titles that carry --set."""
from pathlib import Path

import numpy as np
import pytest
from matplotlib.collections import LineCollection

from fuzzyc.cli import main
from fuzzyc.language.parser import load
from fuzzyc.plotting import draw_signal_surface, draw_variable, raw_surface
from fuzzyc.ruleview import DEFUZZIFIED_COLOUR, draw_rule_view
from fuzzyc.runtime.plots import draw_runs
from fuzzyc.runtime.trace import Trace

RULEBASES = Path(__file__).resolve().parents[1] / "rulebases"
WEDM = load(RULEBASES / "wedm_three_region.fz")
CORNER = load(RULEBASES / "wedm_corner.fz")


def stems(ax) -> list[tuple[float, float, tuple]]:
    """(x, height, colour) of every vertical segment drawn with vlines."""
    out = []
    for c in ax.collections:
        if isinstance(c, LineCollection):
            for seg, colour in zip(c.get_segments(), np.broadcast_to(
                    c.get_colors(), (len(c.get_segments()), 4))):
                out.append((float(seg[0, 0]), float(seg[1, 1] - seg[0, 1]), tuple(colour)))
    return sorted(out)


def flat(drawn) -> list[float]:
    """x1, height1, x2, height2, ... of `stems`."""
    return [v for x, height, _ in drawn for v in (x, height)]


def vertical_lines(ax, colour=None) -> list[float]:
    """x of the axvline lines (two points at the same x spanning the axes), of one colour."""
    from matplotlib.colors import to_rgba
    return [float(line.get_xdata()[0]) for line in ax.lines
            if len(line.get_xdata()) == 2 and line.get_xdata()[0] == line.get_xdata()[1]
            and (colour is None or to_rgba(line.get_color()) == to_rgba(colour))]


def test_singleton_terms_have_distinct_colours_and_the_axes_units():
    y = CORNER.rulebase.outputs[0]          # singletons VS=5 S=15 M=30 B=45 VB=60
    ax = draw_variable(y).axes[0]
    drawn = stems(ax)
    assert [x for x, _, _ in drawn] == [5, 15, 30, 45, 60]
    assert len({colour for _, _, colour in drawn}) == 5
    assert ax.get_xlabel() == "y [-]" and ax.get_ylabel() == "membership [-]"
    thickness = draw_variable(CORNER.rulebase.inputs[1]).axes[0]
    assert thickness.get_xlabel() == "thickness [mm]"
    assert len(thickness.lines) == 2            # S and B, two curves


def test_rule_viewer_wedm_two_rules():
    """e1 = 1, e2 = 0.75, ce2 = 0: e2 is PB and PS at 0.5 each, ce2 ZO at 1, so rules 3
    (-> du1 PB) and 8 (-> du1 PS) fire at 0.5; center of area over the term peaks:
    du1 = (0.5 * 1 + 0.5 * 0.5) / (0.5 + 0.5) = 0.75."""
    fig = draw_rule_view(WEDM, {"e1": 1.0, "e2": 0.75, "ce2": 0.0})
    axes = np.array(fig.axes).reshape(3, 5)       # 2 rules + the aggregate row, 3 in + 2 out
    assert "2 rules fired" in fig._suptitle.get_text()
    du1 = axes[2, 3]
    assert vertical_lines(du1, DEFUZZIFIED_COLOUR) == pytest.approx([0.75])
    assert flat(stems(du1)) == pytest.approx([0.5, 0.5, 1.0, 0.5])
    # e1 = (Yr1 - spark_freq) * GE1 with GE1 in kHz^-1: dimensionless, not kHz (issue 30)
    assert [ax.get_xlabel() for ax in axes[2]] == ["e1 [-]", "e2 [-]", "ce2 [-]", "du1 [-]",
                                                  "du2 [-]"]
    # each rule row: the input marked on every clause, the consequent cut at 0.5
    assert all(vertical_lines(axes[0, i]) == pytest.approx([x]) for i, x in enumerate([1, .75, 0]))
    assert axes[0, 3].get_title() == "#3: du1 is PB (0.5)"


def test_rule_viewer_corner_eight_rules_center_of_area():
    """feedrate 120 (uniform VS..VB over [40, 180], peaks 35 apart: M = 25/35 = 5/7,
    B = 10/35 = 2/7), thickness 40 (S = 10/30 = 1/3, B = 2/3), angle 60 (S = 22.5/52.5 = 3/7,
    M = 30/52.5 = 4/7): 2 x 2 x 2 = 8 rules fire. Term strengths (max of min): S 1/3 (rule
    11), M 4/7 (rule 14), B 3/7 (rule 13), VB 2/7 (rules 16, 19, 20); y = (15/3 + 30*4/7 +
    45*3/7 + 60*2/7) / (1/3 + 9/7) = (410/7) / (34/21) = 1230/34 = 36.18 %."""
    fig = draw_rule_view(CORNER, {"feedrate": 120.0, "thickness": 40.0, "angle": 60.0})
    axes = np.array(fig.axes).reshape(9, 4)
    y = axes[8, 3]
    assert vertical_lines(y, DEFUZZIFIED_COLOUR) == pytest.approx([1230 / 34])
    assert flat(stems(y)) == pytest.approx([15, 1 / 3, 30, 4 / 7, 45, 3 / 7, 60, 2 / 7])
    assert [ax.get_xlabel() for ax in axes[8]] == [
        "feedrate [mm^2/min]", "thickness [mm]", "angle [deg]", "y [-]"]
    assert axes[0, 3].get_title() == "#14: y is M (0.571)"     # the strongest first


def test_rule_viewer_keeps_the_strongest_rules_and_says_so():
    fig = draw_rule_view(CORNER, {"feedrate": 120.0, "thickness": 40.0, "angle": 60.0},
                         max_rules=3)
    assert len(fig.axes) == 4 * 4
    assert "8 rules fired; the 3 strongest drawn" in fig._suptitle.get_text()


def test_surface_over_the_raw_inputs():
    """spark_freq 25 kHz, abnormal_ratio 0.375 (the 9-point grid hits both): e1 = clamp(5 *
    0.25) = 1 (P), e2 = 0.025 * 10 = 0.25 (ZO 0.5, PS 0.5), ce2 = 0 on the first step: the
    P-table cells (ZO, ZO) -> ZO and (PS, ZO) -> PS, du1 = (0.5 * 0 + 0.5 * 0.5) / 1 = 0.25."""
    fig = draw_signal_surface(WEDM, "du1", ("spark_freq", "abnormal_ratio"), {}, n=9)
    ax = fig.axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()) == (
        "spark_freq [kHz]", "abnormal_ratio [-]", "du1 [-]")
    X, Y, z = raw_surface(WEDM, "du1", ("spark_freq", "abnormal_ratio"), {}, n=9)
    assert (X[3, 1], Y[3, 1]) == (25, 0.375)
    assert z[3, 1] == pytest.approx(0.25)
    # 0 kHz, ratio 0: e1 = clamp(7.5) = 1 (P), e2 = clamp(4) = 1 (PB only), ce2 = 0 (ZO):
    # the cell (PB, ZO) -> PB, du1 = its peak, 1
    assert z[0, 0] == pytest.approx(1.0)


def test_plot_command_writes_the_raw_surfaces(tmp_path, capsys):
    assert main(["plot", str(RULEBASES / "wedm_three_region.fz"), "-o", str(tmp_path),
                 "--at", "spark_freq=25"]) == 0
    names = {p.name for p in tmp_path.iterdir()}
    assert {"wedm_three_region_du1_surface_raw.png",
            "wedm_three_region_du2_surface_raw.png"} <= names
    assert all(n.endswith(".png") for n in names)           # nothing else (no temporaries)


def test_plot_draws_a_variable_without_terms(tmp_path, capsys):
    # found by `make fuzz`: a FIS output with NumMFs=0 made the legend call raise
    fis = tmp_path / "t.fis"
    fis.write_text("[System]\nName='t'\nType='mamdani'\nNumInputs=1\nNumOutputs=1\n"
                   "NumRules=0\nAndMethod='min'\nOrMethod='max'\nImpMethod='min'\n"
                   "AggMethod='max'\nDefuzzMethod='centroid'\n\n[Input1]\nName='a'\n"
                   "Range=[0 10]\nNumMFs=1\nMF1='lo':'trimf',[0 0 10]\n\n[Output1]\n"
                   "Name='y'\nRange=[0 30]\nNumMFs=0\n\n[Rules]\n")
    assert main(["plot", str(fis), "-o", str(tmp_path / "out")]) == 0
    assert "t_y_terms.png" in {p.name for p in (tmp_path / "out").iterdir()}


def test_eval_plot_writes_the_rule_viewer(tmp_path, capsys):
    out = tmp_path / "view.png"
    assert main(["eval", str(RULEBASES / "wedm_three_region.fz"), "spark_freq=26",
                 "abnormal_ratio=0.325", "--plot", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["view.png"]
    assert main(["eval", str(RULEBASES / "wedm_three_region.fz"), "--csv", str(out),
                 "--plot", str(out)]) == 2
    assert "--plot draws one evaluation" in capsys.readouterr().err


def test_runs_on_one_figure_with_units():
    t = np.arange(5) * 0.1
    fuzzy = Trace(t, {"feed": np.ones((5, 3)), "spark_freq": np.zeros((5, 3))}, 0.1)
    baseline = Trace(t, {"feed": np.full((5, 3), 2.0), "spark_freq": np.zeros((5, 3))}, 0.1)
    fig = draw_runs({"fuzzy": fuzzy, "baseline": baseline}, ["feed", "spark_freq"],
                    {"feed": 1.5}, "a title", {"feed": "mm/min", "spark_freq": "kHz"})
    top, bottom = fig.axes
    assert len(top.lines) == 3 + 3 + 1              # 3 loops of each run, the set point
    assert [line.get_color() for line in top.lines] == ["C0"] * 3 + ["C1"] * 3 + ["k"]
    assert top.lines[-1].get_ydata()[0] == 1.5
    assert [t.get_text() for t in top.get_legend().get_texts()] == ["fuzzy", "baseline",
                                                                     "set point 1.5"]
    assert top.get_ylabel() == "feed [mm/min]" and bottom.get_ylabel() == "spark_freq [kHz]"
    assert bottom.get_xlabel() == "time [s]" and top.get_title() == "a title"


def test_every_panel_of_every_shipped_scenario_has_a_unit():
    from fuzzyc.plants.scenario import available, load as load_scenario
    from fuzzyc.runtime.simulate import signal_units
    for name in available():
        scenario = load_scenario(name)
        units = signal_units(scenario)
        assert [p for p in scenario.plots if not units.get(p)] == [], name


def test_title_follows_set(tmp_path, capsys):
    from fuzzyc.plants.scenario import load as load_scenario
    scenario = load_scenario("wedm_finish", {"plant.on_time": "0.6", "duration": "0.4"})
    assert scenario.title.endswith("[--set plant.on_time=0.6, duration=0.4]")
    assert main(["simulate", "--scenario", "wedm_finish", "--set", "duration=0.4",
                 "--compare", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "summary.txt").read_text()
    assert text.count("[--set duration=0.4]") == 2 and "controller: baseline" in text
    import json
    result = json.loads((tmp_path / "summary.json").read_text())
    assert set(result["baseline_metrics"]) == set(result["metrics"])


CENTROID = """controller area {
  input a in [0, 1]
  terms a : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var m in [0, 1]
  terms m : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  inference implication = min, aggregation = max, defuzzify = centroid
  rule if a is L then m is L
  rule if a is H then m is H
  output u in [0, 1] = m
}
"""


def test_rule_viewer_area_aggregate(tmp_path):
    """a = 0.3: L fires 0.7, H 0.3; M(u) = max(min(.7, 1 - u), min(.3, u)) is .7 up to .3,
    1 - u to .7, then .3. Area .21 + .2 + .09 = .5; moment .0315 + (.130667 - .036) + .0765 =
    .202667; centroid .405333."""
    source = tmp_path / "area.fz"
    source.write_text(CENTROID)
    fig = draw_rule_view(load(source), {"a": 0.3})
    axes = np.array(fig.axes).reshape(3, 2)
    aggregate = axes[2, 1]
    assert vertical_lines(aggregate, DEFUZZIFIED_COLOUR) == pytest.approx([0.405333], abs=1e-6)
    curve = next(line for line in aggregate.lines if len(line.get_xdata()) > 2)
    u, m = curve.get_xdata(), curve.get_ydata()
    assert m == pytest.approx(np.maximum(np.minimum(0.7, 1 - u), np.minimum(0.3, u)))
    assert axes[0, 1].get_title() == "#1: m is L (0.7)"
