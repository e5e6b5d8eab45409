"""The Mackey-Glass benchmark with a small budget (the full run is
`python -m fuzzyc.tune.mackey_glass`): the series against its closed form where the delay
reads 0, the first step that reads it (Jang's generator's x_{k-169}), the data set's shape,
the 104-parameter file, and a short fit's error."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.language.parser import load
from fuzzyc.tune import mackey_glass as mg
from fuzzyc.tune.space import Space

# NDEI train, check after 20 epochs of Jang's rule (printed by this code; 0.0084 and 0.0079
# in the command's table)
NDEI_20 = (0.008418903896065595, 0.007870793671838986)


def test_series_before_the_delay_acts():
    # for t < 17 the delayed x is 0 (x = 0 before t = 0): dx/dt = -0.1 x, x = 1.2 exp(-0.1 t);
    # fourth-order Runge-Kutta multiplies by 1 - z + z^2/2 - z^3/6 + z^4/24 (z = 0.01) a step
    x = mg.series(20.0)
    z = 0.01
    step = 1 - z + z ** 2 / 2 - z ** 3 / 6 + z ** 4 / 24
    assert x[0] == 1.2 and x[1] == pytest.approx(1.2 * step, rel=1e-15)
    assert x[100] == pytest.approx(1.2 * np.exp(-1.0), rel=1e-9)      # t = 10
    assert x[170] == pytest.approx(1.2 * step ** 170, rel=1e-12)      # t = 17
    # the step from t = 17 (k = 170) reads the ring's oldest value, x_1 = x(0.1) (Jang's
    # mackeyglass.c: x(0) never enters the ring), held over the four stages
    def f(v, past):
        return 0.2 * past / (1 + past ** 10) - 0.1 * v
    h, v, past = 0.1, x[170], x[1]
    k1 = f(v, past)
    k2 = f(v + h / 2 * k1, past)
    k3 = f(v + h / 2 * k2, past)
    k4 = f(v + h * k3, past)
    assert x[171] == pytest.approx(v + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), rel=1e-15)
    assert x[171] > 1.2 * step ** 171
    # --delay-steps 170 reads x_0 = 1.2 there instead: another trajectory from t = 17.1 on
    assert mg.series(20.0, back=170)[171] != x[171]


def test_dataset_and_rule_file():
    X, y = mg.dataset()
    assert X.shape == (1000, 4) and y.shape == (1000,)
    x = mg.samples()
    assert len(x) == 1201                       # t = 0..1200, as mgdata.dat
    assert x[0] == 1.2 and abs(x[118] - mg.series()[1180]) <= 5e-7   # six decimals
    assert all(float(f"{v:.6f}") == v for v in x)
    # row 0 is t = 118: x(100), x(106), x(112), x(118) -> x(124)
    assert X[0].tolist() == [x[100], x[106], x[112], x[118]] and y[0] == x[124]
    assert np.array_equal(X[6:, 3], y[:-6])     # x(t) six rows on is the target x(t + 6)
    model = load(mg.rule_file())
    space = Space(model)
    assert space.size == 104                  # 4 x 2 x 3 premise + 16 x 5 consequent
    assert len(model.rulebase.antecedents) == 16


def test_a_short_fit():
    fit, ndei_train, ndei_check, _ = mg.run(passes=1, max_nfev=3, method="least_squares")
    # one pass: the consequents by least squares on the written bells, 3 premise steps
    assert 0.005 < ndei_train < 0.02 and 0.005 < ndei_check < 0.02
    assert fit.rmse_after < fit.rmse_before
    text = mg.table(fit, ndei_train, ndei_check, 1.0, mg.row_name("least_squares", 1, 3))
    assert "| fuzzyc tune (1 pass, max_nfev 3) |" in text
    assert "| Jang 1993, ANFIS (500 epochs) | - | 0.007 | 104 | - |" in text
    assert f"| {ndei_train:.4f} | {ndei_check:.4f} | 104 |" in text


def test_twenty_epochs_of_jangs_rule():
    # the numbers this code printed (python -m fuzzyc.tune.mackey_glass --epochs 20); as in
    # Jang's paper and MATLAB's demo, the checking error is below the training error
    fit, ndei_train, ndei_check, _ = mg.run(passes=20, max_nfev=None)
    assert ndei_train == pytest.approx(NDEI_20[0], rel=1e-6)
    assert ndei_check == pytest.approx(NDEI_20[1], rel=1e-6)
    assert ndei_check < ndei_train
    assert fit.method.startswith("ANFIS (Jang 1993: 20 epochs")
    assert "| fuzzyc tune, method anfis (20 epochs) |" in mg.table(
        fit, ndei_train, ndei_check, 1.0, mg.row_name("anfis", 20, None))
