"""Every kind of figure fuzzyc draws meets docs/plots.md's standard (issue 30), read from the
matplotlib Figure objects, not from screenshots:

- every axis that shows tick labels has a label, its own or its grid column's / row's;
- every label names its unit in brackets: `name [unit]`, `[-]` for dimensionless;
- a legend on a data panel with more than one kind of line (the rule viewer's titles name
  each term and value instead, as MATLAB's does);
- the data drawn lie within the axis limits (nothing cut off, no axis running past the data);
- a 3D surface has a colour bar labelled with the output.
"""
from __future__ import annotations

import re

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection

import fuzzyc
from fuzzyc.runtime.plots import draw_runs
from fuzzyc.runtime.trace import Trace

UNIT = re.compile(r"\S.*\[[^\[\]]+\]$")        # `name [unit]`


def shows_ticks(axis) -> bool:
    return axis.get_visible() and any(t.get_text() for t in axis.get_ticklabels())


def neighbours(ax: Axes, which: str) -> list[Axes]:
    """The axes of the same grid column (x) or row (y) as ax, ax included."""
    spec = ax.get_subplotspec()
    if spec is None:
        return [ax]
    span = (lambda s: s.colspan) if which == "x" else (lambda s: s.rowspan)
    return [other for other in ax.figure.axes if other.get_subplotspec() is not None
            and span(other.get_subplotspec()) == span(spec)]


def label_problems(fig) -> list[str]:
    fig.canvas.draw()         # tick labels exist once drawn
    problems = []
    for ax in fig.axes:
        axes = {"x": ax.xaxis, "y": ax.yaxis}
        if getattr(ax, "zaxis", None) is not None:
            axes["z"] = ax.zaxis
        for which, axis in axes.items():
            if not shows_ticks(axis):
                continue
            own = axis.get_label().get_text()
            labels = [own] if own or which == "z" else [
                other.xaxis.get_label().get_text() if which == "x"
                else other.yaxis.get_label().get_text() for other in neighbours(ax, which)]
            labels = [text for text in labels if text]
            if not labels:
                problems.append(f"{ax.get_title() or ax}: no {which} label")
            problems += [f"`{text}` names no unit" for text in labels if not UNIT.match(text)]
    return problems


def limit_problems(ax: Axes) -> list[str]:
    """Lines and stems drawn in data coordinates that leave the axis limits."""
    (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
    slack_x, slack_y = 1e-9 * max(1.0, x1 - x0), 1e-9 * max(1.0, y1 - y0)
    points = [np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
              for line in ax.lines if line.get_transform() == ax.transData]
    points += [np.concatenate(c.get_segments()) for c in ax.collections
               if isinstance(c, LineCollection) and c.get_segments()]
    problems = []
    for xy in points:
        xy = xy[np.isfinite(xy).all(axis=1)]
        if len(xy) and (xy[:, 0].min() < x0 - slack_x or xy[:, 0].max() > x1 + slack_x
                        or xy[:, 1].min() < y0 - slack_y or xy[:, 1].max() > y1 + slack_y):
            problems.append(f"{ax.get_ylabel()}: data outside the limits")
    return problems


def legend_problems(ax: Axes) -> list[str]:
    kinds = len(ax.lines) + sum(isinstance(c, LineCollection) for c in ax.collections)
    if kinds > 1 and ax.get_legend() is None:
        return [f"{ax.get_ylabel() or ax.get_xlabel()}: {kinds} lines and no legend"]
    return []


def check_figure(fig, legends: bool = True) -> None:
    problems = label_problems(fig)
    for ax in fig.axes:
        if getattr(ax, "zaxis", None) is not None or not ax.get_subplotspec():
            continue                       # 3D axes and colour bars: labels only
        problems += limit_problems(ax)
        if legends:
            problems += legend_problems(ax)
    assert problems == []


def check_surface(fig) -> None:
    check_figure(fig)
    surface, bar = fig.axes                # the 3D axes and its colour bar
    assert bar.get_ylabel() == surface.get_zlabel()
    width, height = fig.get_size_inches()
    assert width >= 7 and height >= 5      # matplotlib's 6.4 x 4.8 crammed the 3D labels
    for axis, (lo, hi) in ((surface.xaxis, surface.get_xlim()),
                           (surface.yaxis, surface.get_ylim())):
        ticks = [t for t in axis.get_majorticklocs() if min(lo, hi) <= t <= max(lo, hi)]
        assert 2 <= len(ticks) <= 6, ticks  # a physical input's 4-digit ticks ran together


MODELS = ["wedm_three_region.fz", "wedm_corner.fz", "milling_neurofuzzy.fz", "edm_sink_gap.fz",
          "fopdt_pi.fz", "cartpole.fz", "pendulum.fz"]


@pytest.mark.parametrize("name", MODELS)
def test_model_figures(name):
    model = fuzzyc.load(fuzzyc.example(name))
    figures = fuzzyc.plot(model)
    assert figures
    for key, fig in figures.items():
        (check_surface if "_surface" in key else check_figure)(fig)
    # the rule viewer in the middle of every rule-base input
    point = {v.name: 0.5 * (v.lo + v.hi) for v in model.rulebase.inputs}
    check_figure(fuzzyc.plot(model, point=point)[f"{model.name}_rules"], legends=False)


def test_scaled_inputs_are_not_in_the_signals_unit():
    """e1 = clamp((Yr1 - spark_freq) * GE1, -1, 1) with GE1 in kHz^-1: e1 is dimensionless, not
    kHz (the rule viewer said `e1 [kHz]` on [-1, 1]); milling's e and cf (gains declared
    without a unit: unknown) were `[N]`."""
    wedm = fuzzyc.load(fuzzyc.example("wedm_three_region.fz"))
    assert [v.unit for v in wedm.rulebase.inputs] == [None, None, None]
    milling = fuzzyc.plot(fuzzyc.example("milling_neurofuzzy.fz"))
    axes = milling["milling_neurofuzzy_e_terms"].axes[0]
    assert axes.get_xlabel() == "e [-]"


def test_a_gain_with_a_unit_makes_the_scaled_error_dimensionless():
    text = """controller u {
      param Yr1 = 30 kHz
      param GE1 = 0.25 kHz^-1
      input f : kHz in [0, 200]
      let e1 UNIT in [-1, 1] = clamp((Yr1 - f) * GE1, -1, 1)
      terms e1 : uniform N Z P over [-1, 1]
      var du in [-1, 1]
      terms du : singletons N=-1 Z=0 P=1
      rule if e1 is N then du is N
      output y in [0, 1] = du
    }"""
    model = fuzzyc.parse(text.replace("UNIT", ""))
    assert model.rulebase.inputs[0].unit is None         # kHz * 1/kHz: dimensionless, [-]
    with pytest.raises(fuzzyc.FuzzycError, match="declared in kHz but its expression is in "
                                                 "dimensionless"):
        fuzzyc.parse(text.replace("UNIT", ": kHz"))


SCENARIOS = [("fopdt_step", {}), ("wedm_rough", {"duration": 4}),
             ("milling_step", {"duration": 5}), ("edm_sink", {"duration": 1})]


@pytest.mark.parametrize("scenario, settings", SCENARIOS)
def test_simulation_traces(scenario, settings):
    sim = fuzzyc.simulate(scenario, settings=settings, batch=2)
    base = fuzzyc.simulate(scenario, settings=settings, batch=2, baseline=True)
    fig = fuzzyc.plot(sim, compare=base)["trace"]
    check_figure(fig)
    top = fig.axes[0]
    # the rule base's run on top of the baseline's, which is lighter
    fuzzy = [line for line in top.lines if line.get_color() == "C0"]
    baseline = [line for line in top.lines if line.get_color() == "C1"]
    assert min(line.get_zorder() for line in fuzzy) > max(line.get_zorder() for line in baseline)
    assert all(line.get_alpha() < 1 for line in baseline)
    assert (max(line.get_linewidth() for line in baseline)
            < min(line.get_linewidth() for line in fuzzy))        # and thinner
    # drawn in zorder: every fuzzy line after (above) every baseline line
    order = sorted(top.get_children(), key=lambda artist: artist.get_zorder())
    assert max(map(order.index, baseline)) < min(map(order.index, fuzzy))
    assert fig.axes[-1].get_xlim() == (sim.trace.time[0], sim.trace.time[-1])


def test_corner_path_time_axis_ends_with_the_path():
    """The corner scenario runs 12,600 s (the slowest row of Table 4) while its default row's
    path is done at 3,078 s: the axis ends there, with the path, not 9,500 s of flat lines."""
    sim = fuzzyc.simulate("corner_path")
    fig = fuzzyc.plot(sim)["trace"]
    check_figure(fig)
    done = sim.trace["done"][:, 0] > 0
    end = float(sim.trace.time[np.argmax(done)])
    assert sim.trace.time[-1] == pytest.approx(12600)
    assert fig.axes[-1].get_xlim() == pytest.approx((sim.trace.time[0], end))
    assert 3000 < end < 3200
    assert max(max(line.get_xdata()) for ax in fig.axes for line in ax.lines) <= end


def test_trace_time_axis_ends_where_the_plant_is_done():
    """A plant that reports `done` (the corner path) at sample 3 of 6: the axis and the lines
    end there (time 0.3 s), not at the scenario's duration."""
    t = np.arange(1, 7) * 0.1
    done = np.array([0, 0, 1, 1, 1, 1.0])[:, None]
    trace = Trace(t, {"y": np.arange(6.0)[:, None], "done": done}, 0.1)
    fig = draw_runs({"fuzzy": trace}, ["y"], units={"y": "mm"})
    ax = fig.axes[0]
    assert ax.get_xlim() == pytest.approx((0.1, 0.3))
    assert ax.lines[0].get_xdata() == pytest.approx([0.1, 0.2, 0.3])
    check_figure(fig)


def test_counterexample_plots():
    """fopdt_pi on its step (y: 0 -> 1): `always y < 0.9` breaks when y nears 1 and
    `always abs(y - r) < 0.5` at the step (r = 1, y = 0)."""
    model = fuzzyc.load(fuzzyc.example("fopdt_pi.fz"))
    text = model.source_text.replace("settles y to r within 0.05 by 25 s",
                                     "always y < 0.9\n      always abs(y - r) < 0.5")
    report = fuzzyc.verify(fuzzyc.parse(text, name="fopdt_bad.fz"), only="fopdt_step",
                           max_examples=5)
    figures = fuzzyc.plot(report)
    assert len(figures) == 2
    for fig in figures.values():
        check_figure(fig)
    limit, band = figures.values()
    y = next(ax for ax in limit.axes if ax.get_ylabel() == "y [-]")
    legend = [t.get_text() for t in y.get_legend().get_texts()]
    assert legend[:2] == ["y", "limit: y < 0.9"] and legend[2].startswith("first violated")
    y = next(ax for ax in band.axes if ax.get_ylabel() == "y [-]")
    legend = [t.get_text() for t in y.get_legend().get_texts()]
    assert legend[:3] == ["y", "set point r", "limit: Abs(r - y) < 0.5"]


def test_learning_plot():
    learned = fuzzyc.learn(fuzzyc.example("milling_neurofuzzy.fz"), "milling_step", cycles=2,
                           settings={"duration": 5})
    check_figure(fuzzyc.plot(learned)["pi"])


@pytest.mark.parametrize("name, labels", [
    ("pendulum", ["cos_th [-]", "theta_dot [rad/s]", "torque [N*m]", "return [-]"]),
    ("cartpole", ["theta [rad]", "x [m]", "force [-]", "return [-]"])])
def test_gymnasium_traces(name, labels):
    # the units come from the scenario's plant `units:` (an environment declares none) and
    # the rule file; the episode's return is a score, dimensionless
    pytest.importorskip("gymnasium")
    sim = fuzzyc.simulate(fuzzyc.example(f"{name}.yaml"), fuzzyc.example(f"{name}.fz"),
                          settings={"duration": 6})
    fig = fuzzyc.plot(sim)["trace"]
    check_figure(fig)
    assert [ax.get_ylabel() for ax in fig.axes] == labels
    # CartPole's push jumps by about half its range every step (its lines fill a band): its
    # panel, and only its, adds the running mean
    means = [ax.get_ylabel() for ax in fig.axes
             if any(line.get_label().startswith("running mean") for line in ax.lines)]
    assert means == (["force [-]"] if name == "cartpole" else [])
