"""Properties kept: for each kind (bounded, monotone, covers) the unconstrained optimum of the
data violates it, and the tuned result keeps it, as the verifier decides; the verifier's
counterexamples join the penalty sets."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.language.parser import parse
from fuzzyc.tune import fit_data
from fuzzyc.tune.consequent_bounds import corner_bounds
from fuzzyc.tune.constraints import SEGMENT_PARTS, Penalties, check
from fuzzyc.tune.space import Space
from fuzzyc.tune.sugeno import SugenoForm
from fuzzyc.verifier.runner import Options, check_property
from fuzzyc.verifier.result import Result, Status

from test_tune_fit import TWO_SINGLETONS, X, Y

KEPT = (Status.PROVED, Status.HELD)


def verdict(model, kind: str) -> Status:
    prop = next(p for p in model.properties if p.kind == kind)
    return Result(prop, prop.text, check_property(model, prop, Options(max_examples=50))).status


def with_verify(text: str, props: str) -> str:
    return text.replace("  tune {", f"  verify {{\n    {props}\n  }}\n  tune {{")


def test_bounded_is_kept():
    # unconstrained, b = 25/6 (test_tune_fit): y(1) = 25/6 leaves [-1, 3]
    model = parse(with_verify(TWO_SINGLETONS % ("weighted_average", 10), "bounded y in [-1, 3]"))
    assert verdict(model, "bounded") in KEPT            # y = x as written
    free = fit_data(model, X, Y, keep_properties=False)
    assert free.values[1] == pytest.approx(25 / 6) and verdict(free.model, "bounded") == \
        Status.VIOLATED
    kept = fit_data(model, X, Y)
    assert verdict(kept.model, "bounded") in KEPT
    assert kept.values[1] <= 3.0 and kept.values[1] == pytest.approx(3.0, abs=1e-3)
    # with b = 3 the best a is -0.6 (test_tune_fit's active bound)
    assert kept.values[0] == pytest.approx(-0.6, abs=1e-2)
    assert [(c.text, c.before, c.after) for c in kept.properties] == [
        ("bounded y in [-1, 3]", "proved", "proved")]
    assert kept.rmse_after > free.rmse_after              # what keeping it costs


MONOTONE = """controller mono {
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  var y in [-5, 5] default 0
  terms y : r1 = linear(0, 1), r2 = linear(0, 1)
  inference and = product, defuzzify = weighted_average
  rule if x is lo then y is r1
  rule if x is hi then y is r2
  output u in [-5, 5] = y
  verify {
    monotone y increasing in x
  }
  tune {
    y in +/- 4
  }
}
"""


def test_monotone_is_kept():
    # y = (1 - x)(c0 + c1 x) + x (d0 + d1 x) is any quadratic; the data rises then falls, so
    # the best quadratic falls at the end
    model = parse(MONOTONE)
    xs = np.linspace(0, 1, 9)
    ys = np.sin(np.pi * xs * 0.8)               # up to x = 0.625, then down
    assert verdict(model, "monotone") in KEPT   # y = x as written
    free = fit_data(model, xs[:, None], ys, keep_properties=False)
    assert verdict(free.model, "monotone") == Status.VIOLATED
    kept = fit_data(model, xs[:, None], ys)
    assert verdict(kept.model, "monotone") in KEPT
    grid = np.linspace(0, 1, 401)[:, None]
    assert np.all(np.diff(evaluate(kept.model.rulebase, grid)[:, 0]) >= -1e-9)
    assert kept.rmse_before > kept.rmse_after > free.rmse_after
    # the first candidate loses it, its counterexample joins the penalty, the next keeps it
    assert "counterexample points added" in kept.rejected[0]


COVERS = """controller cover {
  input x in [0, 1]
  terms x : lo = gauss(0, 0.5), hi = gauss(1, 0.5)
  var y in [0, 1] default 0
  terms y : a = singleton(0), b = singleton(1)
  inference and = product, defuzzify = weighted_average
  rule if x is lo then y is a
  rule if x is hi then y is b
  output u in [0, 1] = y
  verify {
    covers x at least 0.5
  }
  tune {
    x.lo.sigma, x.hi.sigma in [0.05, 1]
  }
}
"""


def test_covers_is_kept():
    # a step at 0.5 wants steep Gaussians; the strongest rule at x = 0.5 fires
    # exp(-0.25 / (2 sigma^2)), at least 0.5 while sigma >= sqrt(0.125 / ln 2) = 0.4247
    model = parse(COVERS)
    xs = np.linspace(0, 1, 21)
    ys = (xs > 0.5).astype(float)
    assert verdict(model, "covers") in KEPT     # sigma 0.5: exp(-0.5) = 0.61 at x = 0.5
    free = fit_data(model, xs[:, None], ys, keep_properties=False)
    assert verdict(free.model, "covers") == Status.VIOLATED
    kept = fit_data(model, xs[:, None], ys)
    assert verdict(kept.model, "covers") in KEPT
    # with sigmas s1, s2 the two cross at x = s1 / (s1 + s2), where both fire
    # exp(-1 / (2 (s1 + s2)^2)): at least 0.5 while s1 + s2 >= 1 / sqrt(2 ln 2) = 0.8493
    total = kept.values.sum()
    assert 1 / np.sqrt(2 * np.log(2)) - 1e-9 <= total < 0.86     # kept, and only just
    assert free.values.sum() < 0.8                                # the free fit went past it
    assert kept.rmse_after > free.rmse_after
    assert [(c.before, c.after) for c in kept.properties] == [("proved", "proved")]


LINE = """controller line {
  input x in [0, 1]
  terms x : all = trap(-1, 0, 1, 2)
  var y in [-5, 5] default 0
  terms y : l = linear(0, 1)
  inference and = product, defuzzify = weighted_average
  rule if x is all then y is l
  output u in [-5, 5] = y
  verify {
    bounded y in [0, 1.5]
  }
  tune {
    y in +/- 5
  }
}
"""


def test_bounded_linear_consequent_is_kept():
    # one rule firing 1 on [0, 1]: y = c0 + c1 x. The data y = 2 x at x = 0, 1/4, ..., 1 is
    # fitted exactly by c0 = 0, c1 = 2, and y(1) = 2 leaves [0, 1.5]. Kept, the line's top
    # end is at the bound: c1 = 1.5 - c0 and the error a (1 - x) - x / 2 is least at
    # a = (1/2) sum x (1 - x) / sum (1 - x)^2 = (1/2) 0.625 / 1.875 = 1/6: c0 = 1/6, c1 = 4/3
    model = parse(LINE)
    xs = np.linspace(0, 1, 5)
    assert verdict(model, "bounded") in KEPT            # y = x as written
    free = fit_data(model, xs[:, None], 2 * xs, keep_properties=False)
    assert free.values == pytest.approx([0, 2], abs=1e-9)
    assert verdict(free.model, "bounded") == Status.VIOLATED
    kept = fit_data(model, xs[:, None], 2 * xs)
    # the consequent's values at the box's corners x = 0, 1 (c0, c0 + c1) within [0, 1.5]:
    # linear constraints on the least squares, met by construction, no candidate rejected
    assert kept.values == pytest.approx([1 / 6, 4 / 3], abs=1e-6)
    assert "kept by construction" in kept.method and kept.rejected == []
    assert verdict(kept.model, "bounded") in KEPT
    dense = evaluate(kept.model.rulebase, np.linspace(0, 1, 10001)[:, None])[:, 0]
    assert dense.min() >= 0 and dense.max() <= 1.5
    assert [(c.before, c.after) for c in kept.properties] == [("proved", "proved")]


def test_counterexample_joins_the_penalty():
    # the free fit's y = 2 x breaks `bounded y in [0, 1.5]` at x = 1 (the verifier's grid
    # says so); the penalty set grows by that point and its neighbours half a penalty-grid
    # step away (x = 1 - 1 / 798: the grid has 400 points; x = 1 + 1 / 798 is clipped to 1)
    model = parse(LINE)
    xs = np.linspace(0, 1, 5)
    free = fit_data(model, xs[:, None], 2 * xs, keep_properties=False).model
    prop = free.properties[0]
    found, why, evidence = check(free, prop, 0)
    assert found == Status.VIOLATED and evidence.point == {"x": 1.0}
    penalties = Penalties(free, [prop])
    assert penalties.size(prop) == 400
    assert penalties.add(free, prop, evidence) == 2
    assert penalties.size(prop) == 402
    added = penalties.items[0].points[-2:, 0]
    assert added == pytest.approx([1 - 0.5 / 399, 1.0])
    # y = 2 at x = 1: 0.5 over the bound, less the margin (1e-4 of the range 1.5)
    assert penalties.residuals(free)[-1] == pytest.approx(0.5 + 1.5e-4)


def test_monotone_counterexample_is_a_segment():
    # a monotone counterexample (x, x') becomes SEGMENT_PARTS pairs along the segment
    model = parse(MONOTONE)
    xs = np.linspace(0, 1, 9)
    free = fit_data(model, xs[:, None], np.sin(np.pi * xs * 0.8), keep_properties=False).model
    prop = free.properties[0]
    found, _, evidence = check(free, prop, 0)
    assert found == Status.VIOLATED and evidence.to_point is not None
    penalties = Penalties(free, [prop])
    before = penalties.size(prop)
    assert penalties.add(free, prop, evidence) == 2 * SEGMENT_PARTS
    assert penalties.size(prop) == before + 2 * SEGMENT_PARTS
    a, b = evidence.point["x"], evidence.to_point["x"]
    pairs = penalties.items[0].pairs
    assert pairs[0][0][0] == pytest.approx(a) and pairs[-1][1][0] == pytest.approx(b)
    assert penalties.residuals(free).min() < 0      # the segment's slope goes the wrong way


def test_corner_constraints_of_a_linear_consequent():
    # y = c0 + c1 x on [0, 1] is within [0, 1.5] iff its corner values c0 (x = 0) and c0 + c1
    # (x = 1) are: rows [1, 0] and [1, 1] on (c0, c1)
    model = parse(LINE)
    space = Space(model)
    form = SugenoForm(space, np.zeros((1, 1)))
    corner = corner_bounds(space, form, model.properties)
    assert corner.corners == 2 and corner.C.tolist() == [[1, 0], [1, 1]]
    assert corner.lo.tolist() == [0, 0] and corner.hi.tolist() == [1.5, 1.5]
    assert corner.holds(np.array([0.0, 1.0])) and not corner.holds(np.array([0.0, 2.0]))


def test_linear_consequents_bounded_by_their_corners():
    # the verifier's proof: y = x as written is a convex combination of one consequent whose
    # values at the corners x = 0, 1 are 0 and 1, within [0, 1.5]: proved, not searched
    model = parse(LINE)
    prop = model.properties[0]
    evidence = check_property(model, prop, Options(max_examples=50))
    assert [(e.method, e.status) for e in evidence] == [("proof", Status.PROVED)]
    assert "2 corners: y in [0, 1]" in evidence[0].detail
    # y = 2 x reaches 2 at x = 1: no proof, the search finds it
    steep = parse(LINE.replace("linear(0, 1)", "linear(0, 2)"))
    assert verdict(steep, "bounded") == Status.VIOLATED


def test_bounded_by_counterexample_rounds_under_weighted_sum():
    # weighted_sum is no convex combination: no corner constraints, the penalty keeps it. The
    # first candidate ends just over 1.5 at x = 1; that point joins the penalty, the heavier
    # round keeps it (the verifier's search: held), near the same optimum c0 = 1/6, c1 = 4/3
    model = parse(LINE.replace("weighted_average", "weighted_sum"))
    xs = np.linspace(0, 1, 5)
    kept = fit_data(model, xs[:, None], 2 * xs)
    assert "kept by construction" not in kept.method
    assert len(kept.rejected) == 1 and "counterexample points added" in kept.rejected[0]
    assert kept.values == pytest.approx([1 / 6, 4 / 3], abs=1e-3)
    assert [(c.before, c.after) for c in kept.properties] == [("held", "held")]
    dense = evaluate(kept.model.rulebase, np.linspace(0, 1, 10001)[:, None])[:, 0]
    assert dense.min() >= 0 and dense.max() <= 1.5
