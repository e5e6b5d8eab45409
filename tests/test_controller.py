"""The signal chain: steps, rule base, outputs, with hand-computed traces."""
import math

import numpy as np
import pytest
import sympy

from fuzzyc.engine.chain import Controller
from fuzzyc.engine.expressions import evaluate_expr
from fuzzyc.semantics.model import (Defuzzifier, Model, Op, Output, OutputKind, Param, Signal, Step)
from test_engine_core import rulebase, var

x, e, du, G = sympy.symbols("x e du G")


def model(direct=False):
    """e = 2x; du = COA of singletons N=-1, Z=0, P=1 with e in N/Z/P (so du = e on [-1, 1]);
    u = integrate(G du) in [0, 1] from 0.5; t = 1/integrate(0.01 du) in [2, 10] from 4."""
    ein = var("e", {"N": ("tri", -2, -1, 0), "Z": ("tri", -1, 0, 1), "P": ("tri", 0, 1, 2)})
    dout = var("du", {"N": ("single", -1.0), "Z": ("single", 0.0), "P": ("single", 1.0)})
    rb = rulebase([ein], [dout], [(["N"], ["N"]), (["Z"], ["Z"]), (["P"], ["P"])],
                  defuzzifier=Defuzzifier.CENTER_OF_AREA)
    steps = [Step("e", Op.ASSIGN, 2 * x), Step("d", Op.DELTA, x), Step("p", Op.PREV, x),
             Step("l", Op.LOWPASS, x, coeffs=(0.75, 0.25))]
    outputs = [Output("u", OutputKind.INCREMENT, G * du, 0.0, 1.0, init=0.5),
               Output("t", OutputKind.RECIPROCAL_INCREMENT, 0.01 * du, 2.0, 10.0, init=4.0)]
    if direct:
        outputs.append(Output("v", OutputKind.DIRECT, 3 * du, -2.0, 2.0, init=0.0))
    return Model("m", [rb], params={"G": Param("G", 0.5)}, signals=[Signal("x", -1, 1)],
                 steps=steps, outputs=outputs)


def run(c, xs):
    return [(c.step({"x": np.array([v])}), dict(c.signals)) for v in xs]


def test_three_step_trace():
    c = Controller(model())
    assert c.input_names == ["x"] and c.output_names == ["u", "t"]
    trace = run(c, [0.2, 0.6, -0.4])
    sig = lambda k, name: trace[k][1][name][0]          # noqa: E731
    # e = 2x = 0.4, 1.2, -0.8; du = 0.4, 1 (only P: 0.8), (-0.8 + 0) / (0.8 + 0.2) = -0.8
    np.testing.assert_allclose([sig(k, "du") for k in range(3)], [0.4, 1.0, -0.8])
    np.testing.assert_allclose([sig(k, "d") for k in range(3)], [0.0, 0.4, -1.0])
    np.testing.assert_allclose([sig(k, "p") for k in range(3)], [0.2, 0.2, 0.6])
    # lowpass: 0.2; 0.75*0.2 + 0.25*0.6 = 0.3; 0.75*0.3 - 0.25*0.4 = 0.125
    np.testing.assert_allclose([sig(k, "l") for k in range(3)], [0.2, 0.3, 0.125])
    # u: 0.5 + 0.2 = 0.7; 0.7 + 0.5 = 1.2 -> saturates at 1; 1 - 0.4 = 0.6
    np.testing.assert_allclose([sig(k, "u") for k in range(3)], [0.7, 1.0, 0.6])
    # v = 1/t: 0.25 + 0.004, + 0.01, - 0.008
    np.testing.assert_allclose([sig(k, "t") for k in range(3)], [1 / 0.254, 1 / 0.264, 1 / 0.256])


def test_reciprocal_saturates_the_state_so_the_output_stays_in_range():
    c = Controller(model(), batch=2)
    for _ in range(200):   # du = +1 / -1: v moves by 0.01 per step from 0.25
        out = c.step({"x": np.array([0.5, -0.5])})
    # v saturates to [1/10, 1/2]: t = 2 (v = 0.5) and t = 10 (v = 0.1)
    np.testing.assert_allclose(out["t"], [2.0, 10.0])
    np.testing.assert_allclose(out["u"], [1.0, 0.0])


def test_nan_input_holds_memories_and_outputs():
    c = Controller(model(direct=True))
    run(c, [0.2])
    out, sig = run(c, [np.nan])[0]
    assert math.isnan(sig["d"][0]) and sig["du"][0] == 0.0       # rule-base default
    # u holds (increment G * 0); v = 3 * du follows the rule base's default 0
    assert out["u"][0] == pytest.approx(0.7) and out["v"][0] == 0.0
    out, sig = run(c, [0.6])[0]
    assert sig["d"][0] == pytest.approx(0.4)      # 0.6 - 0.2: the NaN did not enter the memory
    assert sig["p"][0] == pytest.approx(0.2)
    assert sig["l"][0] == pytest.approx(0.3)
    assert all(np.isfinite(v).all() for v in out.values())


def test_direct_output_saturates_and_holds_on_nan():
    m = model(direct=True)
    m.outputs[-1].expr = 3 / (x - 0.5)     # x = 0.5 divides by zero: the output holds
    c = Controller(m)
    assert c.step({"x": np.array([0.0])})["v"][0] == -2.0      # 3 / -0.5 = -6 -> -2
    assert c.step({"x": np.array([0.5])})["v"][0] == -2.0
    assert c.step({"x": np.array([1.5])})["v"][0] == 2.0       # 3 / 1 = 3 -> 2


def test_batch_equals_one_by_one_and_reset():
    xs = np.random.default_rng(0).uniform(-1, 1, (5, 4))
    c = Controller(model(), batch=4)
    batched = [c.step({"x": row})["u"] for row in xs]
    for k in range(4):
        one = Controller(model())
        np.testing.assert_allclose([one.step({"x": row[k:k + 1]})["u"][0] for row in xs],
                                   [b[k] for b in batched])
    c.reset(batch=2)
    assert c.step({"x": np.array([0.2, 0.2])})["u"] == pytest.approx([0.7, 0.7])


def test_set_consequent_values_doubles_the_output():
    c = Controller(model())
    c.set_consequent_values("du", np.array([-2.0, 0.0, 2.0]))
    c.step({"x": np.array([0.1])})
    assert c.signals["du"][0] == pytest.approx(0.4)     # e = 0.2: (0.8*0 + 0.2*2) / 1
    with pytest.raises(ValueError):
        c.set_consequent_values("du", np.array([1.0, 2.0]))


def test_expressions_walk_the_tree():
    a, b = sympy.symbols("a b")
    env = {"a": np.array([1.0, 4.0]), "b": 2.0}
    expr = sympy.Min(1, sympy.Max(-1, (a - b) * 0.25)) + sympy.sqrt(a) + sympy.Abs(-b) / a
    # a=1: max(-1, -0.25) + 1 + 2 = 2.75; a=4: min(1, 0.5) + 2 + 0.5 = 3
    np.testing.assert_allclose(evaluate_expr(expr, env), [2.75, 3.0])
    np.testing.assert_allclose(evaluate_expr(sympy.exp(sympy.log(a)) + a ** 2, env), [2, 20])
    with pytest.raises(ValueError):
        evaluate_expr(sympy.sin(a), env)
