"""Vanishing activations: one floor (`fuzzyc.semantics.model.ACTIVATION_FLOOR`, 1e-12) that the engine and
the C headers follow, for every defuzzifier the C back end emits.

Two rule bases force a rule to fire at 1e-300 ... 1e-6, just below (0.99e-12) and just above
(1.01e-12) the floor:
- TAIL: the level is a gaussian term gauss(0, 0.1) far in its tail (the dense path), g chosen
  so that exp(-(g / 0.1)^2 / 2) is the level; a second input z fires another rule fully
  (z = 1) or not at all (z = 0);
- WEIGHTED: input x is a uniform partition T0..T8 (peaks 0..8), rule k concludes with weight
  LEVELS[k], so at x = k exactly one rule fires, at exactly that level (the sparse path, the
  engine's grid of term strengths and its closed-form centroid).
Each is evaluated by the engine and by the double and float headers built with gcc
(`cload.CController`, strict flags).  Stated tolerances, as a fraction of the output's range:
double 1e-10 (test_c_area's), float 1e-5 (the float header's).  The hand-computed values are
held against the engine to 1e-12 (the arithmetic in `single_rule`).
"""
from __future__ import annotations

import re

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.load import CController
from fuzzyc.engine.inference import activations, evaluate
from fuzzyc.semantics.model import ACTIVATION_FLOOR, set_entries
from fuzzyc.language.parser import parse

LEVELS = [1e-300, 1e-100, 1e-30, 1e-18, 1e-15, 0.99e-12, 1.01e-12, 1e-9, 1e-6]
TOLERANCE = {"double": 1e-10, "float": 1e-5}
SPAN = 10.0                      # both outputs on [0, 10]
DEFAULTS = (5.0, 1.0)            # y's and v's declared defaults

# y: A = tri(1, 2, 3) (fired fully by the second rule of TAIL), B = tri(5, 7, 9) (the tiny rule);
# v: P = tri(1, 2, 3), R = trap(6, 6, 6, 9): 1 at 6 (a vertical edge), falling to 0 at 9.
OUTPUTS = """
  var y in [0, 10] default 5
  terms y : A = tri(1, 2, 3), B = tri(5, 7, 9)
  var v in [0, 10] default 1
  terms v : P = tri(1, 2, 3), R = trap(6, 6, 6, 9)
  inference implication = IMP, aggregation = AGG, defuzzify = METHOD
"""
ENDS = """
  output uy in [0, 10] = y
  output uv in [0, 10] = v
}
"""
TAIL = """controller tail {
  input g in [0, 10]
  input z in [0, 1]
  terms g : T = gauss(0, 0.1)
  terms z : OFF = lshoulder(0, 1), ON = rshoulder(0, 1)
""" + OUTPUTS + """
  rule if g is T then y is B, v is R
  rule if z is ON then y is A, v is P
""" + ENDS
N = len(LEVELS)
WEIGHTED = f"""controller weighted {{
  input x in [0, {N - 1}]
  terms x : uniform {" ".join(f"T{k}" for k in range(N))}
""" + OUTPUTS + "".join(f"  rule if x is T{k} then y is B, v is R\n" for k in range(N)) + ENDS

AREA = ["centroid", "bisector", "mean_of_maximum"]
PEAK = ["center_of_area", "weighted_average", "weighted_sum"]
NORMS = [("min", "max"), ("product", "max"), ("product", "sum"), ("min", "sum")]
CASES = [(m, imp, agg) for m in AREA for imp, agg in NORMS] + \
    [(m, "min", agg) for m in PEAK for agg in ("max", "sum")]


def text_of(source: str, method: str, imp: str, agg: str) -> str:
    return source.replace("METHOD", method).replace("IMP", imp).replace("AGG", agg)


def tail_model(method, imp, agg):
    return parse(text_of(TAIL, method, imp, agg), "tail.fz")


def weighted_model(method, imp, agg):
    model = parse(text_of(WEIGHTED, method, imp, agg), "weighted.fz")
    set_entries(model.rulebase, "weights", np.s_[:], np.array(LEVELS))
    return model


def tail_inputs() -> np.ndarray:
    """Rows (g, z): g where gauss(0, 0.1) is each level, with z = 0 (the tiny rule alone) and
    then z = 1 (A fired fully beside it)."""
    g = 0.1 * np.sqrt(2.0 * np.log(1.0 / np.array(LEVELS)))    # exp(-(g/0.1)^2/2) = level
    return np.concatenate([np.stack([g, np.zeros_like(g)], axis=1),
                           np.stack([g, np.ones_like(g)], axis=1)])


def weighted_inputs() -> np.ndarray:
    return np.arange(len(LEVELS), dtype=float)[:, None]          # x = k fires rule k alone


def single_rule(method: str, imp: str, h: float) -> tuple[float, float]:
    """(y, v) by hand where one rule concludes y is B, v is R at level h and nothing else fires.

    Below the floor nothing fires: the defaults (5, 1).  Above it:
    y, B = tri(5, 7, 9) clipped (min) or scaled (product) at h is symmetric about 7, so its
      centroid, bisector and mean of maximum are 7; its peak is 7 (center of area, weighted
      average); the weighted sum is h * 7.
    v, R = 1 at 6 falling to 0 at 9 (R(u) = (9 - u) / 3):
      min: M = h on [6, 9 - 3h] (R >= h there), then (9 - u) / 3 down to 0 at 9:
        area = h (3 - 3h) + 3h * h / 2 = 3h - 1.5h^2;
        moment = h (3 - 3h) (6 + 9 - 3h) / 2 + 1.5h^2 (9 - 2h)   (the ramp's centroid 9 - 2h);
        centroid = moment / area -> 7.5 as h -> 0;
        bisector: half the area, 1.5h - 0.75h^2, is reached on the flat part at
          6 + (1.5h - 0.75h^2) / h = 7.5 - 0.75h;
        mean of maximum: the plateau [6, 9 - 3h], its middle 7.5 - 1.5h;
      product: M = h R, the triangle (6, 0), (6, h), (9, 0):
        centroid (6 + 6 + 9) / 3 = 7;
        bisector: the area right of u is h (9 - u)^2 / 6, half of 1.5h at 9 - sqrt(4.5) = 6.8787;
        mean of maximum: the one maximal point 6;
      center of area, weighted average: R's peak (b + c) / 2 = 6; weighted sum h * 6.
    """
    if h < ACTIVATION_FLOOR:
        return DEFAULTS
    if method == "weighted_sum":
        return 7.0 * h, 6.0 * h
    if method in ("center_of_area", "weighted_average"):
        return 7.0, 6.0
    if imp == "product":
        return 7.0, {"centroid": 7.0, "bisector": 9.0 - np.sqrt(4.5),
                     "mean_of_maximum": 6.0}[method]
    area = 3 * h - 1.5 * h * h
    moment = h * (3 - 3 * h) * (15 - 3 * h) / 2 + 1.5 * h * h * (9 - 2 * h)
    return 7.0, {"centroid": moment / area, "bisector": 7.5 - 0.75 * h,
                 "mean_of_maximum": 7.5 - 1.5 * h}[method]


def beside_a_full_rule(method: str, imp: str, agg: str, h: float) -> float | None:
    """y by hand where A = tri(1, 2, 3) fires at 1 and B at h (supports apart), or None.

    Below the floor only A fires: every defuzzifier gives A's 2 (its centroid, bisector, mean
    of maximum and peak; the weighted sum 1 * 2).  Above it, min-max centroid: A's area 1 at
    2, B clipped at h a trapezoid of bases 4 and 4 - 4h, area 4h - 2h^2, at 7:
    (2 + 7 (4h - 2h^2)) / (1 + 4h - 2h^2), 2 + 2.0e-11 at 1.01e-12, 2.00002 at 1e-6; the mean of
    maximum is A's peak 2 for h < 1."""
    if h < ACTIVATION_FLOOR:
        return 2.0
    if method == "centroid" and (imp, agg) == ("min", "max"):
        b = 4 * h - 2 * h * h
        return (2 + 7 * b) / (1 + b)
    if method == "mean_of_maximum" and h < 1.0:
        return 2.0
    return None


@pytest.fixture(scope="module", params=CASES, ids=["-".join(c) for c in CASES])
def case(request):
    return request.param


@pytest.mark.parametrize("numeric", ["double", "float"])
@pytest.mark.parametrize("build, inputs", [(tail_model, tail_inputs),
                                           (weighted_model, weighted_inputs)],
                         ids=["tail", "weighted"])
def test_engine_and_c_agree(case, numeric, build, inputs):
    model = build(*case)
    x = inputs()
    expected = evaluate(model.rulebase, x)
    got = CController(model, numeric=numeric).evaluate(x)
    error = np.abs(got - expected) / SPAN
    assert error.max() <= TOLERANCE[numeric], np.column_stack([x, expected, got])


@pytest.mark.parametrize("build, inputs", [(tail_model, tail_inputs),
                                           (weighted_model, weighted_inputs)],
                         ids=["tail", "weighted"])
def test_hand_computed_on_each_side_of_the_floor(case, build, inputs):
    method, imp, agg = case
    model = build(method, imp, agg)
    y = evaluate(model.rulebase, inputs())
    for k, h in enumerate(LEVELS):
        assert y[k] == pytest.approx(single_rule(method, imp, h), rel=1e-12, abs=1e-12), (k, h)


def test_the_tail_levels_are_the_intended_ones():
    # the gaussian tail gives each level to ~1e-13 (so 0.99e-12 and 1.01e-12 stay on their side
    # of the floor), and the floor drops exactly those below 1e-12
    rb = tail_model("centroid", "min", "max").rulebase
    x = tail_inputs()[:len(LEVELS)]
    with np.errstate(under="ignore"):
        raw = np.exp(-0.5 * (x[:, 0] / 0.1) ** 2)
    assert raw == pytest.approx(LEVELS, rel=1e-12)
    fired = activations(rb, x)[:, 0]
    assert fired[:6].tolist() == [0.0] * 6                    # 1e-300 ... 0.99e-12
    assert fired[6:] == pytest.approx(LEVELS[6:], rel=1e-12)  # 1.01e-12 ... 1


def test_hand_computed_beside_a_full_rule(case):
    method, imp, agg = case
    rb = tail_model(method, imp, agg).rulebase
    y = evaluate(rb, tail_inputs()[len(LEVELS):])[:, 0]
    for k, h in enumerate(LEVELS):
        want = beside_a_full_rule(method, imp, agg, h)
        if want is not None:
            assert y[k] == pytest.approx(want, rel=0, abs=1e-13), (k, h)


def test_floor_is_written_from_the_constant():
    # the helper of backends/c/real_helpers.c reads the macro the header defines from it
    header = generate_header(tail_model("centroid", "min", "max"), "double")
    floor = re.search(r"#define (\w+)_ACTIVATION_FLOOR (\S+)\n", header)
    assert floor is not None and floor.group(2) == repr(ACTIVATION_FLOOR)
    assert f"a < {floor.group(1)}_ACTIVATION_FLOOR ? 0 : a" in header


def test_lookup_table_follows_the_floor():
    # the table samples the engine: its nodes x = 0..8 are the WEIGHTED rule base's single
    # rules, so it reads back the hand values (the defaults below the floor, (7, 7.5 - ...)
    # above, min-max centroid)
    from fuzzyc.backends.lut import LookupTable
    rb = weighted_model("centroid", "min", "max").rulebase
    got = LookupTable(rb, resolution=N).evaluate(weighted_inputs())
    hand = [single_rule("centroid", "min", h) for h in LEVELS]
    assert got == pytest.approx(np.array(hand), rel=1e-12, abs=1e-12)
