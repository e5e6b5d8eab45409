"""fit_data against answers computed by hand, the Takagi-Sugeno form against the engine, and
the tuned text: only the tuned numbers change, and it reads back as the tuned values."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.engine.inference import evaluate
from fuzzyc.language.parser import parse
from fuzzyc.tune import fit_data
from fuzzyc.tune.rewrite import rewrite
from fuzzyc.tune.space import Space
from fuzzyc.tune.sugeno import SugenoForm, sugeno_problem

# mu_lo(x) = 1 - x, mu_hi(x) = x on [0, 1]: they sum to 1, so y(x) = a (1 - x) + b x
TWO_SINGLETONS = """controller hand {
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  var y in [-10, 10] default 0
  terms y : a = singleton(0), b = singleton(1)    # the consequents the data moves
  inference and = product, defuzzify = %s
  rule if x is lo then y is a
  rule if x is hi then y is b
  output u in [-10, 10] = y
  tune {
    y.a.value in [-10, 0.4]
    y.b.value in [0.6, %s]
  }
}
"""
# the data (0, -1), (0.5, 2), (1, 4): the least-squares line y = a + (b - a) x has
# slope sum((x - 0.5)(y - 5/3)) / sum((x - 0.5)^2) = (0.5 * 8/3 + 0.5 * 7/3) / 0.5 = 5 and
# intercept 5/3 - 5 * 0.5 = -5/6, so a = -5/6 and b = -5/6 + 5 = 25/6; the residuals are
# 1/6, -1/3, 1/6: RMSE sqrt((1/36 + 4/36 + 1/36) / 3) = sqrt(1/18)
X = np.array([[0.0], [0.5], [1.0]])
Y = np.array([-1.0, 2.0, 4.0])


@pytest.mark.parametrize("defuzzify", ["weighted_average", "centroid"])
def test_two_singletons_least_squares_by_hand(defuzzify):
    model = parse(TWO_SINGLETONS % (defuzzify, 10))
    fit = fit_data(model, X, Y)
    # weighted average: the Takagi-Sugeno form (exact linear least squares); centroid over
    # singletons is the same function, found by the generic path (finite differences)
    assert ("ANFIS" in fit.method) == (defuzzify == "weighted_average")
    assert fit.values == pytest.approx([-5 / 6, 25 / 6], abs=1e-6)
    assert fit.rmse_after == pytest.approx(np.sqrt(1 / 18), abs=1e-6)
    # before: a = 0, b = 1, y = x: errors 1, 1.5, 3, RMSE sqrt((1 + 2.25 + 9) / 3)
    assert fit.rmse_before == pytest.approx(np.sqrt(12.25 / 3))
    # the result model is the engine's: it predicts the fitted line
    assert evaluate(fit.model.rulebase, X)[:, 0] == pytest.approx([-5 / 6, 5 / 3, 25 / 6],
                                                                   abs=1e-6)


def test_an_active_bound_by_hand():
    # b held at its bound 3: minimise (a + 1)^2 + (0.5 a - 0.5)^2 + 1, so
    # (a + 1) + 0.5 (0.5 a - 0.5) = 0 and a = -0.6
    fit = fit_data(parse(TWO_SINGLETONS % ("weighted_average", 3)), X, Y)
    assert fit.values == pytest.approx([-0.6, 3.0], abs=1e-9)


def test_validation_and_folds():
    model = parse(TWO_SINGLETONS % ("weighted_average", 10))
    fit = fit_data(model, X, Y, validate=(np.array([[0.25]]), np.array([0.0])))
    # at 0.25 the line is -5/6 + 5 * 0.25 = 5/12; before it was 0.25
    assert fit.validation == pytest.approx(5 / 12, abs=1e-6)
    assert fit.validation_before == pytest.approx(0.25)
    xs = np.linspace(0, 1, 12)[:, None]
    exact = fit_data(model, xs, -1 + 3 * xs[:, 0], folds=3)
    assert exact.validation == pytest.approx(0.0, abs=1e-6)     # a line is fitted exactly
    assert fit_data(model, X, Y, seed=4, folds=3).validation == \
        fit_data(model, X, Y, seed=4, folds=3).validation


def test_params_and_bad_data_are_refused():
    model = parse(TWO_SINGLETONS % ("weighted_average", 10))
    with pytest.raises(ValueError, match="NaN"):
        fit_data(model, X, np.array([1.0, np.nan, 2.0]))
    with pytest.raises(ValueError, match="3 input rows but 2 output rows"):
        fit_data(model, X, Y[:2])
    text = (TWO_SINGLETONS % ("weighted_average", 10)).replace(
        "  input x", "  param G = 1\n  input x").replace("  tune {", "  tune {\n    G in [0, 2]")
    with pytest.raises(ValueError, match=r"params \(G\) move the signal chain"):
        fit_data(parse(text), X, Y)


MG_LIKE = """controller tsk {
  input p in [0, 2]
  input q in [0, 2]
  terms p : S = bell(0.5, 0.6, 2), M = tri(0.4, 1, 1.6), L = gauss(1.5, 0.5)
  terms q : S = bell(0.4, 0.7, 1.5), L = bell(1.6, 0.6, 2.5)
  var y in [-5, 5] default 0.25
  terms y : r1 = linear(0.1, 1, -1), r2 = linear(0, 2, 0.5), r3 = singleton(1),
            r4 = linear(-1, 0.5, 1)
  inference and = product, defuzzify = %s
  rule if p is S and q is S then y is r1
  rule if p is S and q is L then y is r2 with 0.7
  rule r3: if p is L and q is S then y is r3
  rule if p is L and q is L then y is r4
  rule if p is M then y is r2 with 0.5
  output u in [-5, 5] = y
  tune {
    p.S, p.M, p.L, q.* in +/- 0.1
    y in +/- 3
    r3.weight in [0.2, 1]
  }
}
"""


@pytest.mark.parametrize("defuzzify", ["weighted_average", "weighted_sum"])
def test_sugeno_form_is_the_engine_and_its_jacobian_the_derivative(defuzzify):
    model = parse(MG_LIKE % defuzzify)
    assert sugeno_problem(model) == ""
    rng = np.random.default_rng(3)
    x = rng.uniform(-0.2, 2.2, size=(200, 2))       # some outside the ranges: clamped inputs
    space = Space(model)
    form = SugenoForm(space, x)
    assert form.analytic
    theta = space.lo + (space.hi - space.lo) * rng.uniform(size=space.size)
    assert form.predict(theta) == pytest.approx(evaluate(space.apply(theta).rulebase, x),
                                                abs=1e-12)
    J = form.jacobian(theta)
    for k in range(space.size):
        h = 1e-6
        up, down = theta.copy(), theta.copy()
        up[k] += h
        down[k] -= h
        numeric = (form.predict(up) - form.predict(down)).ravel() / (2 * h)
        assert J[:, k] == pytest.approx(numeric, abs=1e-6), space.numbers[k].target
    A, b = form.design(theta)
    assert A @ theta[form.linear_part] + b == pytest.approx(form.predict(theta).ravel())


def test_tuned_text_changes_only_the_tuned_numbers():
    source = TWO_SINGLETONS % ("weighted_average", 10)
    model = parse(source)
    fit = fit_data(model, X, Y)
    text = rewrite(source, fit.numbers, fit.values, ["a line", "another"])
    lines = text.split("\n")
    assert lines[:4] == ["# ---- fuzzyc tune: provenance", "# a line", "# another",
                         "# ---- end of provenance"]
    body, old = lines[4:], source.split("\n")
    changed = [i for i, (new, was) in enumerate(zip(body, old)) if new != was]
    assert len(body) == len(old) and changed == [4]          # the `terms y` line only
    a, b = (repr(float(v)) for v in fit.values)
    assert body[4] == f"  terms y : a = singleton({a}), b = singleton({b})    # the " \
                      "consequents the data moves"
    again = parse(text)
    assert Space(again).x0.tolist() == fit.values.tolist()   # read back bit for bit
    # a second tune replaces the provenance block instead of stacking another
    assert rewrite(text, again.tunables, fit.values, ["new"]).split("\n")[:3] == [
        "# ---- fuzzyc tune: provenance", "# new", "# ---- end of provenance"]


def test_a_rule_weight_not_written_is_added():
    source = MG_LIKE % "weighted_average"
    model = parse(source)
    weight = next(n for n in model.tunables if n.kind == "weight")
    text = rewrite(source, [weight], [0.5], [])
    assert "  rule r3: if p is L and q is S then y is r3 with 0.5\n" in text
    assert parse(text).rulebase.weights[2] == 0.5


def test_relative_bounds_are_written_absolute():
    # `+/- 3` around the written values: around the tuned ones it would be another box, and
    # a value tuned to its bound would put the next tune's box outside the rules of the file
    source = MG_LIKE % "weighted_average"
    model = parse(source)
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 2, size=(40, 2))
    fit = fit_data(model, x, np.sin(x[:, 0]) + x[:, 1] ** 2, max_nfev=5, passes=2)
    text = rewrite(source, fit.numbers, fit.values, [])
    assert "  tune {  # the bounds as tuned, absolute\n    p.S.center in [0.4, 0.6]\n" in text
    again = parse(text)
    assert [(n.target, n.lo, n.hi) for n in again.tunables] == \
        [(n.target, n.lo, n.hi) for n in fit.numbers]
    assert Space(again).x0.tolist() == fit.values.tolist()
