"""The Mackey-Glass benchmark with a small budget (the full run is
`python -m fuzzyc.tune.mackey_glass`): the series against its closed form where the delay
reads 0, the data set's shape, the 104-parameter file, and a short fit's error."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.language.parser import load
from fuzzyc.tune import mackey_glass as mg
from fuzzyc.tune.space import Space


def test_series_before_the_delay_acts():
    # for t < 17 the delayed x is 0 (x = 0 before t = 0): dx/dt = -0.1 x, x = 1.2 exp(-0.1 t);
    # fourth-order Runge-Kutta multiplies by 1 - z + z^2/2 - z^3/6 + z^4/24 (z = 0.01) a step
    x = mg.series(20.0)
    z = 0.01
    step = 1 - z + z ** 2 / 2 - z ** 3 / 6 + z ** 4 / 24
    assert x[0] == 1.2 and x[1] == pytest.approx(1.2 * step, rel=1e-15)
    assert x[100] == pytest.approx(1.2 * np.exp(-1.0), rel=1e-9)      # t = 10
    assert x[170] == pytest.approx(1.2 * step ** 170, rel=1e-12)      # t = 17
    # the step from t = 17 reads x(t - 17) = x(0) = 1.2 (held over the step)
    assert x[171] > 1.2 * step ** 171


def test_dataset_and_rule_file():
    X, y = mg.dataset()
    assert X.shape == (1000, 4) and y.shape == (1000,)
    x = mg.series()
    # row 0 is t = 118: x(100), x(106), x(112), x(118) -> x(124)
    assert X[0].tolist() == [x[1000], x[1060], x[1120], x[1180]] and y[0] == x[1240]
    assert np.array_equal(X[6:, 3], y[:-6])     # x(t) six rows on is the target x(t + 6)
    model = load(mg.rule_file())
    space = Space(model)
    assert space.size == 104                  # 4 x 2 x 3 premise + 16 x 5 consequent
    assert len(model.rulebase.antecedents) == 16


def test_a_short_fit():
    fit, ndei_train, ndei_check, _ = mg.run(passes=1, max_nfev=3)
    # one pass: the consequents by least squares on the written bells, 3 premise steps
    assert 0.005 < ndei_train < 0.02 and 0.005 < ndei_check < 0.02
    assert fit.rmse_after < fit.rmse_before
    text = mg.table(fit, ndei_train, ndei_check, 1.0, 1, 3)
    assert "| Jang 1993, ANFIS (500 epochs) | - | 0.007 | 104 | - |" in text
    assert f"| {ndei_train:.4f} | {ndei_check:.4f} | 104 |" in text
