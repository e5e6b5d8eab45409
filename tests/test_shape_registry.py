"""The registry of term shapes (fuzzyc.semantics.shapes) walked record by record: one record
per TermKind, the grammar's words are its words, each enclosure holds the engine's values over
boxes (and is attained where the record says it is exact), derivatives agree with finite
differences, the C float header and the q15/q31 headers agree with the engine where a record
says they emit the shape and refuse it by name where it says they do not; and the regression
of issue 27: a gaussian product over a box around its top was bounded by its end values."""
from __future__ import annotations

import math
import re
from importlib import resources

import numpy as np
import pytest

from fuzzyc.api import parse
from fuzzyc.backends.c.load import CController
from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c_fixed.header import ERROR_BOUND, FORMATS
from fuzzyc.engine.inference import evaluate
from fuzzyc.engine.membership import memberships
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import READERS
from fuzzyc.semantics.model import TermKind, Variable
from fuzzyc.semantics.shapes import SHAPES, WORDS, c_kinds
from fuzzyc.verifier.reach import rulebase as set_rulebase

from test_c_fixed import fixed_point_runner

ENCLOSED = [k for k, s in SHAPES.items() if s.enclosure is not None]
DERIVED = [k for k, s in SHAPES.items() if s.derivative is not None]


def random_params(kind: TermKind, rng: np.random.Generator, n: int) -> np.ndarray:
    """n valid parameter rows of a row shape (widths and slopes kept away from 0)."""
    u = rng.uniform(-8.0, 8.0, (n, 4))
    width = rng.uniform(0.5, 3.0, (n, 4))
    sign = rng.choice([-1.0, 1.0], (n, 4))
    if kind in (TermKind.TRAPEZOID, TermKind.PISHAPE):
        p = np.sort(u, axis=1)
        if kind == TermKind.PISHAPE:      # S and Z overlapping (b > c) half of the time
            p[::2] = np.column_stack([u[::2, 0], u[::2, 0] + width[::2, 0],
                                      u[::2, 0] + 0.5 * width[::2, 0],
                                      u[::2, 0] + 2.0 * width[::2, 0]])
        p[:, 3] = np.maximum(p[:, 3], p[:, 0] + 0.5)
        if kind == TermKind.TRAPEZOID:
            p[0, :2], p[1, 2:] = -np.inf, np.inf     # a left and a right shoulder
            p[2] = (p[2, 0], p[2, 0], p[2, 3], p[2, 3])   # vertical edges
        return p
    columns = {
        TermKind.GAUSSIAN: (u[:, 0], width[:, 0], 0 * u[:, 0], 0 * u[:, 0]),
        TermKind.BELL: (u[:, 0], width[:, 0], 4.0 * width[:, 1] / 3.0, 0 * u[:, 0]),
        TermKind.SIGMOID: (u[:, 0], sign[:, 0] * width[:, 1], 0 * u[:, 0], 0 * u[:, 0]),
        TermKind.SINGLETON: (np.round(u[:, 0], 1), 0 * u[:, 0], 0 * u[:, 0], 0 * u[:, 0]),
        TermKind.SPIKE: (u[:, 0], 2.0 * width[:, 0], 0 * u[:, 0], 0 * u[:, 0]),
        TermKind.COSINE: (u[:, 0], 2.0 * width[:, 0], 0 * u[:, 0], 0 * u[:, 0]),
        TermKind.GAUSSIAN_PRODUCT: (u[:, 0], width[:, 0], u[:, 1], width[:, 1]),
        TermKind.SIGMOID_DIFFERENCE: (u[:, 0], sign[:, 0] * width[:, 0],
                                      sign[:, 1] * width[:, 1], u[:, 1]),
        TermKind.SIGMOID_PRODUCT: (u[:, 0], sign[:, 0] * width[:, 0],
                                   sign[:, 1] * width[:, 1], u[:, 1]),
        TermKind.LINEAR: tuple(u.T),
    }
    if kind in columns:
        return np.column_stack(columns[kind])
    start = u[:, 0]             # two numbers that must differ (and, some, be ordered)
    end = start + sign[:, 0] * width[:, 0]
    if kind in (TermKind.SSHAPE, TermKind.ZSHAPE):
        end = start + width[:, 0]
    return np.column_stack([start, end, 0 * start, 0 * start])


def random_variable(kind: TermKind, rng: np.random.Generator, n: int = 12) -> Variable:
    if kind == TermKind.DISCRETE:
        points = {}
        for t in range(n):
            k = int(rng.integers(2, 7))
            xs = np.sort(rng.choice(np.arange(-80, 81) / 10.0, k, replace=False))
            points[t] = np.column_stack([xs, rng.uniform(0.0, 1.0, k)])
        params = np.zeros((n, 4))
    else:
        points, params = None, random_params(kind, rng, n)
    return Variable(name="x", lo=-10.0, hi=10.0, names=[f"t{t}" for t in range(n)],
                    kinds=np.full(n, int(kind)), params=params, points=points)


def random_boxes(var: Variable, rng: np.random.Generator, n: int = 60):
    """Boxes anywhere, thin and wide, some of them a point and some ending at a parameter."""
    lo = rng.uniform(-10.0, 10.0, n)
    width = np.exp(rng.uniform(np.log(0.01), np.log(12.0), n))
    width[:5] = 0.0
    finite = np.asarray(var.params, dtype=float)
    finite = finite[np.isfinite(finite)]
    lo[5:10] = rng.choice(finite, 5)
    return lo, lo + width


def critical_points(var: Variable) -> np.ndarray:
    """(T, K) the record's turning and jump points of each term (NaN: none)."""
    record = SHAPES[TermKind(int(var.kinds[0]))]
    if record.per_term:
        xs = [var.points[t][:, 0] for t in range(var.n_terms)]
        out = np.full((var.n_terms, max(map(len, xs))), np.nan)
        for t, x in enumerate(xs):
            out[t, :len(x)] = x
        return out
    if record.critical is None:
        return np.zeros((var.n_terms, 0))
    return np.asarray(record.critical(np.asarray(var.params, dtype=float)), dtype=float)


def sampled(var: Variable, lo: np.ndarray, hi: np.ndarray, rng, count: int = 2001):
    """The engine's memberships (N, S, T) at dense and random points of each box (ends in)."""
    grid = np.concatenate([np.linspace(0.0, 1.0, count), rng.uniform(0.0, 1.0, 200)])
    x = lo[:, None] + (hi - lo)[:, None] * grid[None, :]
    return memberships(var, x.ravel()).reshape(len(lo), len(grid), var.n_terms)


def test_every_term_kind_has_one_record():
    assert set(SHAPES) == set(TermKind)
    assert all(SHAPES[k].kind == k for k in SHAPES)


def test_the_grammars_shape_words_are_the_registrys():
    grammar = resources.files("fuzzyc").joinpath("language/grammar/fuzzyc.lark").read_text()
    body = re.search(r"^SHAPE(?:\.\d+)?:(.*?)/\\b/", grammar, re.S | re.M).group(1)
    assert set(re.findall(r'"([a-z_]+)"', body)) == set(WORDS)
    assert len(WORDS) == 22                 # tri trap lshoulder rshoulder + one per other kind


def test_a_bad_shape_names_every_registry_word():
    with pytest.raises(FuzzycError) as err:
        parse("controller t {\n  input x in [0, 1]\n  terms x : a = 3\n}")
    listed = re.search(r"a term shape \(([^)]*)\)", str(err.value)).group(1).split(", ")
    assert sorted(listed) == sorted(WORDS)


def test_records_say_what_they_do_not_support():
    for kind, record in SHAPES.items():
        if record.c_float is None:
            assert "no C emission" in record.notes, kind
        if record.derivative is None:
            assert "derivative" in record.notes, kind
    assert SHAPES[TermKind.FUNCTION].enclosure is None
    assert SHAPES[TermKind.FUNCTION].words == ()


@pytest.mark.parametrize("kind", ENCLOSED, ids=lambda k: k.name.lower())
def test_enclosure_holds_the_engines_values(kind):
    """Through the verifier's membership_bounds, as the closed-loop proofs use it: every
    dense engine sample of each box lies in its enclosure."""
    rng = np.random.default_rng(27 + int(kind))
    var = random_variable(kind, rng)
    lo, hi = random_boxes(var, rng)
    low, high = set_rulebase.membership_bounds(var, lo, hi)
    mu = sampled(var, lo, hi, rng)
    assert np.all(low[:, None, :] <= mu), kind
    assert np.all(mu <= high[:, None, :]), kind


@pytest.mark.parametrize("kind", [k for k in ENCLOSED if SHAPES[k].exact],
                         ids=lambda k: k.name.lower())
def test_exact_enclosures_are_reached(kind):
    """Where the record says exact, both ends are values the engine takes in the box (at the
    dense samples, the ends, or the record's critical points inside)."""
    rng = np.random.default_rng(100 + int(kind))
    var = random_variable(kind, rng)
    lo, hi = random_boxes(var, rng)
    low, high = set_rulebase.membership_bounds(var, lo, hi)
    mu = sampled(var, lo, hi, rng)
    points = critical_points(var)                                          # (T, K)
    at = np.array([memberships(var, np.nan_to_num(points[t]))[:, t]
                   for t in range(var.n_terms)]).reshape(points.shape)
    inside = (lo[:, None, None] <= points) & (points <= hi[:, None, None])  # (N, T, K)
    reached_high = np.maximum(mu.max(axis=1), np.where(inside, at, -np.inf).max(axis=2,
                                                                                initial=-np.inf))
    reached_low = np.minimum(mu.min(axis=1), np.where(inside, at, np.inf).min(axis=2,
                                                                             initial=np.inf))
    np.testing.assert_allclose(high, reached_high, rtol=0, atol=1e-12)
    np.testing.assert_allclose(low, reached_low, rtol=0, atol=1e-12)


def test_gaussian_product_over_its_top_reaches_one():
    """Issue 27: gaussian_product(4, 1, 6, 1) over x in [3, 7].  On [4, 6] both factors are 1
    (x >= mean_a and x <= mean_b), so the largest membership is 1; the least is at the ends:
    x = 3: exp(-(3 - 4)^2 / 2) * 1 = exp(-1/2) = 0.60653, x = 7: 1 * exp(-(7 - 6)^2 / 2), the
    same.  The old bound was [0.60653, 0.60653]."""
    model = parse("controller t {\n  input x in [0, 10]\n"
                  "  terms x : a = gaussian_product(4, 1, 6, 1)\n"
                  "  terms y in [0, 1] : lo = singleton(0), hi = singleton(1)\n"
                  "  rule if x is a then y is hi\n}")
    rb = model.rulebase
    low, high = set_rulebase.membership_bounds(rb.inputs[0], np.array([3.0]), np.array([7.0]))
    assert high[0, 0] == 1.0
    assert low[0, 0] == pytest.approx(math.exp(-0.5), rel=1e-15)
    # the rule base's own set-valued evaluation holds the engine's output at x = 5
    y_lo, y_hi = set_rulebase.evaluate(rb, np.array([[3.0]]), np.array([[7.0]]))
    y = evaluate(rb, np.array([[5.0]]))
    assert y_lo[0, 0] <= y[0, 0] <= y_hi[0, 0]


def test_a_shape_without_enclosure_is_refused_by_name():
    fll = ("Engine: f\nInputVariable: a\n  enabled: true\n  range: 0 2\n"
           "  term: half Function 1 - x / 2\nOutputVariable: y\n  enabled: true\n"
           "  range: 0 1\n  aggregation: Maximum\n  defuzzifier: WeightedAverage\n"
           "  default: 0\n  term: one Constant 1\nRuleBlock: r\n  enabled: true\n"
           "  conjunction: Minimum\n  implication: Minimum\n  rule: if a is half then y is one\n")
    rb = READERS[".fll"](fll, "f.fll").rulebase
    assert "Function (formula) terms of `a`" in set_rulebase.unsupported(rb)


@pytest.mark.parametrize("kind", DERIVED, ids=lambda k: k.name.lower())
def test_derivatives_match_central_differences(kind):
    """d mu / d p against (mu(p + h) - mu(p - h)) / 2h at random points; entries at a kink
    (the one-sided differences disagree) are skipped, and most entries must be checked."""
    rng = np.random.default_rng(300 + int(kind))
    record = SHAPES[kind]
    p = random_params(kind, rng, 200)
    p = p[np.all(np.isfinite(p), axis=1)]
    x = rng.uniform(-10.0, 10.0, len(p))
    analytic = record.derivative(x, p)                      # (T, 4)
    h = 1e-6
    checked, total = 0, 0
    for j in range(4):
        step = np.zeros_like(p)
        step[:, j] = h
        with np.errstate(all="ignore"):
            up, mid, down = (record.membership(x, q) for q in (p + step, p, p - step))
        forward, backward = (up - mid) / h, (mid - down) / h
        central = (up - down) / (2 * h)
        smooth = np.abs(forward - backward) <= 1e-4 * (1 + np.abs(central))
        total += len(p)
        checked += int(smooth.sum())
        np.testing.assert_allclose(analytic[smooth, j], central[smooth], rtol=1e-4, atol=1e-5,
                                   err_msg=f"{kind.name} parameter {j}")
    assert checked >= 0.8 * total


# -- C back ends ---------------------------------------------------------------------------

C_CASES = {   # a .fz word and its numbers per record with a C emission
    TermKind.TRAPEZOID: [("tri", (-2, 1.5, 4)), ("trap", (-6, -1, 2, 7)),
                         ("lshoulder", (-3, 1)), ("rshoulder", (0.5, 6))],
    TermKind.GAUSSIAN: [("gauss", (1.25, 2.5))],
    TermKind.BELL: [("bell", (-1, 3, 2.5))],
    TermKind.SIGMOID: [("sigmoid", (2, -1.5))],
    TermKind.SINGLETON: [("singleton", (0.5,))],
}
OTHER_CASES = {TermKind.SSHAPE: "sshape(-1, 3)", TermKind.ZSHAPE: "zshape(-1, 3)",
               TermKind.PISHAPE: "pishape(-4, -1, 1, 5)", TermKind.SPIKE: "spike(0, 4)",
               TermKind.COSINE: "cosine(0, 6)", TermKind.CONCAVE: "concave(-2, 3)",
               TermKind.SIGMOID_DIFFERENCE: "sigmoid_difference(-2, 2, 2, 3)",
               TermKind.SIGMOID_PRODUCT: "sigmoid_product(-2, 2, 2, 3)",
               TermKind.GAUSSIAN_PRODUCT: "gaussian_product(-1, 1, 2, 1)",
               TermKind.BINARY: "binary(1, 5)", TermKind.SEMI_ELLIPSE: "semi_ellipse(-3, 4)",
               TermKind.ARC: "arc(-3, 4)", TermKind.DISCRETE: "discrete(-2, 0, 0, 1, 3, 0.5)"}


def one_term_model(shape_text: str):
    """mu(x) of one term as the rule base's output: one rule, weighted sum, y = mu * 1."""
    return parse("controller shape_check {\n  input x in [-10, 10]\n"
                 f"  terms x : a = {shape_text}\n"
                 "  terms y in [0, 1] : one = singleton(1)\n"
                 "  inference defuzzify = weighted_sum\n"
                 "  rule if x is a then y is one\n}")


def test_the_c_cases_cover_every_record():
    assert set(C_CASES) == set(c_kinds())
    assert set(OTHER_CASES) | set(C_CASES) | {TermKind.LINEAR, TermKind.FUNCTION} == \
        set(TermKind)


@pytest.mark.parametrize("numeric", ["float", "double"])
@pytest.mark.parametrize("kind", sorted(C_CASES), ids=lambda k: k.name.lower())
def test_c_header_membership_matches_the_engine(kind, numeric):
    rng = np.random.default_rng(int(kind))
    tolerance = 1e-5 if numeric == "float" else 1e-12
    for word, numbers in C_CASES[kind]:
        model = one_term_model(f"{word}({', '.join(f'{v:g}' for v in numbers)})")
        x = np.concatenate([rng.uniform(-12.0, 12.0, 3000), numbers,
                            [np.nan, np.inf, -np.inf]])[:, None]
        c = CController(model, numeric=numeric).evaluate(x)
        engine = evaluate(model.rulebase, x)
        np.testing.assert_allclose(c, engine, rtol=0, atol=tolerance, err_msg=word)
        assert np.all(engine[:, 0] <= 1.0) and np.any(engine[:, 0] > 0.5), word


@pytest.mark.parametrize("kind", sorted(OTHER_CASES), ids=lambda k: k.name.lower())
def test_the_c_header_refuses_a_shape_without_emission_by_name(kind):
    model = one_term_model(OTHER_CASES[kind])
    with pytest.raises(FuzzycError, match=f"does not emit {SHAPES[kind].name} terms"):
        generate_header(model, "float")


def test_the_c_header_refuses_linear_terms_by_name():
    model = parse("controller lin {\n  input x in [-10, 10]\n  terms x : a = tri(-5, 0, 5)\n"
                  "  terms y in [-20, 20] : l = linear(1, 2)\n"
                  "  inference defuzzify = weighted_average\n"
                  "  rule if x is a then y is l\n}")
    with pytest.raises(FuzzycError, match="does not emit linear terms"):
        generate_header(model, "float")


@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_fixed_point_partitions_of_trapezoids_follow_the_engine(numeric):
    """The only record the q15/q31 inputs take (c_fixed_input): random trapezoid partitions
    (at most two terms positive anywhere), center of area over singletons, within the
    header's stated bound."""
    assert [k for k, s in SHAPES.items() if s.c_fixed_input] == [TermKind.TRAPEZOID]
    rng = np.random.default_rng(15)
    _, full, _ = FORMATS[numeric]
    for _ in range(3):
        k = np.sort(rng.choice(np.arange(-95, 96) / 10.0, 6, replace=False))
        model = parse(
            "controller fixed_shapes {\n  input x in [-10, 10]\n"
            f"  terms x : A = lshoulder({k[0]:g}, {k[1]:g}), "
            f"B = trap({k[0]:g}, {k[1]:g}, {k[2]:g}, {k[3]:g}), "
            f"C = trap({k[2]:g}, {k[3]:g}, {k[4]:g}, {k[5]:g}), D = rshoulder({k[4]:g}, {k[5]:g})\n"
            "  terms y in [0, 3] : s0 = singleton(0), s1 = singleton(1), s2 = singleton(2), "
            "s3 = singleton(3)\n  inference defuzzify = center_of_area\n"
            "  rule if x is A then y is s0\n  rule if x is B then y is s1\n"
            "  rule if x is C then y is s2\n  rule if x is D then y is s3\n}")
        xq = np.arange(0, full + 1, max(1, full // 20000), dtype=np.int64)[:, None]
        yq = fixed_point_runner(model, numeric)(xq)
        engine = evaluate(model.rulebase, -10.0 + xq / full * 20.0)
        error = np.abs(yq / full * 3.0 - engine) / 3.0
        assert error.max() <= ERROR_BOUND[numeric]


def test_fixed_point_refuses_other_input_shapes_by_name():
    model = one_term_model("gauss(0, 2)")
    with pytest.raises(FuzzycError, match="`x` has gaussian terms"):
        fixed_point_runner(model, "q15")
