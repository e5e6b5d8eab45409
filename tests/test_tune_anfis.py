"""Jang's hybrid rule (fuzzyc.tune.anfis): the step-size heuristic on hand-made error
sequences, the premise gradient against finite differences of the training error, the
least-squares solver against numpy's, and the fit_data dispatch."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.language.parser import load
from fuzzyc.tune import anfis
from fuzzyc.tune import mackey_glass as mg
from fuzzyc.tune.space import Space
from fuzzyc.tune.sugeno import SugenoForm


def _rule(errors):
    rule = anfis.StepRule()
    for i in range(1, len(errors) + 1):
        rule.update(list(errors[:i]))
    return rule


def test_step_grows_after_four_reductions_in_a_row():
    # 5 > 4 > 3 > 2 > 1: four reductions at the fifth epoch (index 4): k = 0.01 * 1.1
    # the sixth (0.5) is a fifth reduction but only one epoch after the change: no second one
    rule = _rule([5, 4, 3, 2, 1, 0.5])
    assert rule.changes == [(4, pytest.approx(0.011))]
    # four more reductions (index 8, four after the change): 0.011 * 1.1 = 0.0121
    rule = _rule([5, 4, 3, 2, 1, 0.9, 0.8, 0.7, 0.6])
    assert rule.changes == [(4, pytest.approx(0.011)), (8, pytest.approx(0.0121))]


def test_step_shrinks_after_two_increase_reduction_pairs():
    # 1, 2, 1, 2, 1: up, down, up, down by index 4: k = 0.01 * 0.9
    assert _rule([1, 2, 1, 2, 1]).changes == [(4, pytest.approx(0.009))]
    # one pair only (1, 2, 1) after three reductions: neither rule
    assert _rule([4, 3, 2, 3, 2]).changes == []
    # growth at 4 (5 > 4 > 3 > 2 > 1), then 2, 1, 2, 1: up-down twice by index 8:
    # 0.01 * 1.1 * 0.9 = 0.0099
    rule = _rule([5, 4, 3, 2, 1, 2, 1, 2, 1])
    assert rule.changes == [(4, pytest.approx(0.011)), (8, pytest.approx(0.0099))]
    assert rule.k == pytest.approx(0.0099)


def test_lstsq_matches_numpy():
    rng = np.random.default_rng(3)
    A = rng.random((60, 7))
    A[:, 2] *= 1e-3                                 # a badly scaled column
    b = rng.random(60)
    expected = np.linalg.lstsq(A, b, rcond=None)[0]
    assert np.allclose(anfis.lstsq(A, b), expected, rtol=1e-9, atol=1e-12)
    A[:, 4] = 0.0
    assert anfis.lstsq(A, b) is None                # rank deficient: the caller falls back


def _form():
    X, y = mg.dataset()
    space = Space(load(mg.rule_file()))
    form = SugenoForm(space, X[:500])
    theta = anfis.consequents(form, space.x0, y[:500], space.lo, space.hi)
    return form, theta, y[:500]


def test_premise_gradient_against_finite_differences():
    # E = sum of squared errors with the consequents held; central differences, h = 1e-6
    form, theta, target = _form()
    g, sse = anfis.gradient(form, theta, target)
    premises = np.flatnonzero(~form.linear_part)
    assert len(premises) == 24 and len(g) == 24

    def error(t):
        r = form.predict(t).ravel() - target
        return float(r @ r)
    assert sse == pytest.approx(error(theta), rel=1e-12)
    for k, p in enumerate(premises):
        up, down = theta.copy(), theta.copy()
        up[p] += 1e-6
        down[p] -= 1e-6
        numeric = (error(up) - error(down)) / 2e-6
        assert g[k] == pytest.approx(numeric, rel=1e-4, abs=1e-9)


def test_consequents_are_the_least_squares_solution():
    # with the premises fixed the output is linear in the 80 consequents: the solve's error
    # is the least-squares minimum, so no consequent move lowers it
    form, theta, target = _form()
    A, b = form.design(theta)
    r = A @ theta[form.linear_part] + b - target
    assert np.abs(A.T @ r).max() < 1e-9 * np.abs(A).max() * np.abs(target).max() * len(target)


def test_epochs_are_reproducible_and_lower_the_error():
    form, theta, target = _form()
    space = form.space
    one = anfis.train(form, space.x0, target, space.lo, space.hi, epochs=6)
    two = anfis.train(form, space.x0, target, space.lo, space.hi, epochs=6)
    assert np.array_equal(one.theta, two.theta) and one.errors == two.errors
    # each epoch's gradient step lowers the training error here (k = 0.01 is short)
    assert all(b < a for a, b in zip(one.errors, one.errors[1:]))
    assert one.best_epoch == 5 and one.steps == [(4, pytest.approx(0.011))]


def test_fuzzyc_tune_method_anfis(tmp_path, capsys):
    from fuzzyc.cli.main import main
    rule, train, check = mg.export(tmp_path / "mg")
    out = tmp_path / "tuned.fz"
    assert main(["tune", str(rule), "--data", str(train), "--validate", str(check),
                 "--method", "anfis", "--passes", "3", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "104 numbers tuned by ANFIS (Jang 1993: 3 epochs" in printed
    assert "method: ANFIS (Jang 1993: 3 epochs" in out.read_text()
    # the data tuner's methods and the closed loop's do not mix
    with pytest.raises(ValueError, match="method powell goes with --scenario"):
        from fuzzyc.tune import tune
        tune(rule, train, method="powell")
