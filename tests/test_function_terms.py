"""fuzzylite's Function terms (a formula parsed with lark, kept as a tuple tree) and
lock-previous (an output holding its last value where no rule fires), with hand-computed
answers; the tools themselves are compared in tests/test_conformance_tools.py."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fuzzyc.backends.c.header import check_supported
from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import READERS, WRITERS
from fuzzyc.formats.tool_semantics import Chain
from fuzzyc.engine.formula import Formula, FormulaError, parse_formula
from fuzzyc.language.parser import parse
from fuzzyc.verifier.reach.rulebase import unsupported

# fuzzylite 6's approximation example (takagi-sugeno/approximation.fll), cut to three terms:
# outputFx is a Sugeno output holding its value, trueFx = sin(inputX)/inputX (held too),
# diffFx = |outputFx - trueFx| reads the two outputs before it.
APPROXIMATION = """Engine: approximation
InputVariable: inputX
  range: 0.000 10.000
  term: NEAR_1 Triangle 0.000 1.000 2.000
  term: NEAR_2 Triangle 1.000 2.000 3.000
  term: NEAR_9 Triangle 8.000 9.000 10.000
OutputVariable: outputFx
  range: -1.000 1.000
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  lock-previous: true
  term: f1 Constant 0.840
  term: f2 Constant 0.450
  term: f9 Constant 0.040
OutputVariable: trueFx
  range: -1.000 1.000
  aggregation: none
  defuzzifier: WeightedAverage Automatic
  default: nan
  lock-previous: true
  term: fx Function sin(inputX)/inputX
OutputVariable: diffFx
  range: -1.000 1.000
  aggregation: none
  defuzzifier: WeightedAverage Automatic
  default: nan
  lock-previous: false
  term: diff Function fabs(outputFx-trueFx)
RuleBlock:
  conjunction: none
  disjunction: none
  implication: none
  activation: General
  rule: if inputX is NEAR_1 then outputFx is f1
  rule: if inputX is NEAR_2 then outputFx is f2
  rule: if inputX is NEAR_9 then outputFx is f9
  rule: if inputX is any  then trueFx is fx and diffFx is diff
"""

MAMDANI = """Engine: m
InputVariable: a
  range: 0 2
  term: half Function 1 - x / 2
OutputVariable: y
  range: 0 1
  aggregation: Maximum
  defuzzifier: Centroid
  term: up Function x
RuleBlock:
  conjunction: Minimum
  implication: Minimum
  rule: if a is half then y is up
"""


def test_formula_arithmetic_known_answers():
    f = parse_formula("sin(x)/x")
    assert f.evaluate({"x": math.pi / 2}) == pytest.approx(2 / math.pi)   # sin(pi/2) = 1
    assert parse_formula("2^3^2").evaluate({}) == 512.0      # right-associative: 2^9
    assert parse_formula("-2^2").evaluate({}) == -4.0        # -(2^2)
    assert parse_formula("7 % 3 + 10 / 4").evaluate({}) == 3.5   # 1 + 2.5
    assert parse_formula("fabs(a - b)").evaluate({"a": 0.04, "b": -0.05}) == pytest.approx(0.09)
    # the comparison functions are 0/1: lt(0.2, 0.333) = 1, gt(0.2, 0.333) = 0
    assert parse_formula("lt(x, 0.333) + 2 * gt(x, 0.333) + 4 * eq(x, 0.2)").evaluate(
        {"x": 0.2}) == 5.0
    assert parse_formula("pow(2, 10) - max(3, pi) + min(1, 2)").evaluate({}) == \
        pytest.approx(1024 - math.pi + 1)
    f = parse_formula("(a - (b - c)) / (d * -e)")
    assert parse_formula(f.infix()).tree == f.tree      # written back, read back the same


@pytest.mark.parametrize("text, words", [
    ("__import__('os').system('true')", "unexpected `'`"),
    ("(" * 100 + "1" + ")" * 100, "nested deeper than 64"),
    ("-" * 5000 + "1", "a formula of 5001 characters"),
    ("1" + "+1" * 200, "nests deeper than 64"),
    ("open(x)", "unknown function `open`"),
    ("sin(1, 2)", "`sin` takes 1 argument, got 2"),
    ("x +", "the formula ends too early"),
])
def test_hostile_formulas_are_refused(text, words):
    with pytest.raises(FormulaError) as err:
        parse_formula(text)
    assert words in str(err.value)


def test_huge_exponents_are_infinite_not_an_error():
    assert parse_formula("10^10^10").evaluate({}) == math.inf
    assert parse_formula("exp(1000) - exp(1000)").evaluate({}) != \
        parse_formula("exp(1000) - exp(1000)").evaluate({})    # inf - inf is NaN, no exception


def test_function_membership_known_answers():
    # a is half: 1 - a/2, at a = 1: 0.5; y's term `up` is mu(u) = u on [0, 1] clipped at 0.5:
    # centroid = (int_0^.5 u^2 du + int_.5^1 .5 u du) / (int_0^.5 u du + .5 * .5)
    #          = (1/24 + 3/16) / (1/8 + 1/4) = (11/48) / (3/8) = 11/18
    model = READERS[".fll"](MAMDANI, "m.fll")
    y = evaluate(model.rulebase, np.array([[1.0]]))
    assert y[0, 0] == pytest.approx(11 / 18, abs=1e-6)


def test_takagi_sugeno_function_reads_earlier_outputs_and_lock_previous_holds():
    model = READERS[".fll"](APPROXIMATION, "approximation.fll")
    x = np.array([[1.5], [10.0], [10.0]])
    y = Chain(model).evaluate(x)              # the rows are one controller's sequence
    # 1.5: NEAR_1 and NEAR_2 at 0.5 each: (0.84 + 0.45) / 2 = 0.645; sin(1.5)/1.5 = 0.664997
    assert y[0, 0] == pytest.approx(0.645)
    assert y[0, 1] == pytest.approx(math.sin(1.5) / 1.5)
    assert y[0, 2] == pytest.approx(abs(0.645 - math.sin(1.5) / 1.5))
    # 10: NEAR_9(10) = 0, nothing concludes outputFx: it holds 0.645; diffFx reads the held value
    assert y[1, 0] == y[2, 0] == pytest.approx(0.645)
    assert y[1, 2] == pytest.approx(abs(0.645 - math.sin(10) / 10))   # 0.6994021...


def test_nan_of_a_formula_per_semantics():
    """x = 0 after x = 1.5: sin(0)/0 is NaN.  Exact: the term has no value, its rule does not
    fire, trueFx holds 0.664997; fuzzylite 6 carries the NaN (a rule fired: nothing to hold);
    pyfuzzylite 8 replaces any NaN of a locked output by its previous value."""
    chain = Chain(READERS[".fll"](APPROXIMATION, "approximation.fll"))
    x = np.array([[1.5], [0.0]])
    held = math.sin(1.5) / 1.5
    assert chain.evaluate(x)[1, 1] == pytest.approx(held)
    assert math.isnan(chain.evaluate(x, "fuzzylite")[1, 1])
    assert chain.evaluate(x, "pyfuzzylite")[1, 1] == pytest.approx(held)
    # before anything was held: exact gives the default (0, for `default: nan`), the tools NaN
    assert chain.evaluate(np.array([[0.0]]))[0].tolist() == [0.0, 0.0, 0.0]
    assert np.isnan(chain.evaluate(np.array([[0.0]]), "fuzzylite")).all()


def test_controller_holds_per_loop():
    model = READERS[".fll"](APPROXIMATION, "approximation.fll")
    controller = Controller(model, batch=2)
    controller.step({"inputX": np.array([0.5, 1.5])})    # 0.84 (NEAR_1 alone), 0.645
    out = controller.step({"inputX": np.array([10.0, 10.0])})
    assert out["outputFx_out"] == pytest.approx([0.84, 0.645])
    controller.reset()
    out = controller.step({"inputX": np.array([10.0, 10.0])})
    assert out["outputFx_out"] == pytest.approx([0.0, 0.0])    # nothing held: the default


def test_stateless_readers_refuse_lock_previous_by_name():
    model = READERS[".fll"](APPROXIMATION, "approximation.fll")
    with pytest.raises(FuzzycError) as err:
        evaluate(model.rulebase, np.array([[1.0]]))
    assert "approximation.fll:7:17: error: `outputFx` has lock-previous" in str(err.value)
    with pytest.raises(FuzzycError) as err:
        check_supported(model.rulebase)
    assert "does not emit lock-previous (`outputFx`" in str(err.value)
    assert "lock-previous on `outputFx`" in unsupported(model.rulebase)
    mamdani = READERS[".fll"](MAMDANI, "m.fll").rulebase
    assert "Function (formula) terms of `a`" in unsupported(mamdani)
    with pytest.raises(FuzzycError) as err:
        check_supported(mamdani)
    assert "does not emit function terms (`half` of `a`)" in str(err.value)


@pytest.mark.parametrize("line, replacement, where, words", [
    ("  term: fx Function sin(inputX)/inputX",
     "  term: fx Function sin(inputX)/inputY", "22:33", "unknown name `inputY`"),
    ("  term: fx Function sin(inputX)/inputX",
     "  term: fx Function sin(inputX)/diffFx", "22:33", "`diffFx` is defuzzified after"),
    ("  term: fx Function sin(inputX)/inputX",
     "  term: fx Function sin(x)", "22:25", "x in a Takagi-Sugeno Function term"),
    ("  term: fx Function sin(inputX)/inputX",
     "  term: fx Function sin(inputX)/$inputX", "22:33", "unexpected `$`"),
    ("  term: fx Function sin(inputX)/inputX",
     "  term: fx Function exec(inputX)", "22:21", "unknown function `exec`"),
])
def test_bad_formulas_are_reported_at_their_place(line, replacement, where, words):
    with pytest.raises(FuzzycError) as err:
        READERS[".fll"](APPROXIMATION.replace(line, replacement), "a.fll")
    assert f"a.fll:{where}: error: " in str(err.value) and words in str(err.value), \
        str(err.value)


def test_an_input_term_reads_x_only():
    with pytest.raises(FuzzycError) as err:
        READERS[".fll"](MAMDANI.replace("1 - x / 2", "1 - a / 2"), "m.fll")
    assert "m.fll:4:27: error: `a`: an input's Function term reads x" in str(err.value)


def test_exports_write_formulas_where_the_format_can():
    model = READERS[".fll"](APPROXIMATION, "approximation.fll")
    x = np.array([[1.5], [10.0], [3.3]])
    expected = Chain(model).evaluate(x)
    for fmt in (".fll", ".fcl"):
        text = WRITERS[fmt](model, [])
        assert "Function fabs(outputFx - trueFx)" in text
        again = READERS[fmt](text, f"back{fmt}")
        np.testing.assert_allclose(Chain(again).evaluate(x), expected, rtol=1e-12)
    assert "DEFAULT := 0 | NC;" in WRITERS[".fcl"](model, [])
    with pytest.raises(FuzzycError) as err:
        WRITERS[".fis"](model, [])
    assert "FIS cannot say that `outputFx` holds its last value" in str(err.value)
    # .fz: test_fz_writes_formulas_and_hold_and_reads_them_back


def test_grouped_weighted_average_reads_the_function_value():
    """WeightedAverage grouped by Maximum (the center of area) over a Function term of an
    input: at a = 1.5, lo = 0.25 and hi = 0.75, twice = 2 * 1.5 = 3:
    (0.25 * 3 + 0.75 * 5) / (0.25 + 0.75) = 4.5 (pyfuzzylite 8 and the fuzzylite 6 CLI say so
    too, measured)."""
    text = MAMDANI.replace("  term: half Function 1 - x / 2",
                           "  term: lo Triangle 0 0 2\n  term: hi Triangle 0 2 2")
    text = text.replace("  defuzzifier: Centroid\n  term: up Function x",
                        "  defuzzifier: WeightedAverage\n  term: twice Function 2 * a\n"
                        "  term: five Constant 5")
    text = text.replace("if a is half then y is up",
                        "if a is lo then y is twice\n  rule: if a is hi then y is five")
    model = READERS[".fll"](text.replace("range: 0 1", "range: 0 10"), "g.fll")
    assert evaluate(model.rulebase, np.array([[1.5]]))[0, 0] == pytest.approx(4.5)


LEAVES = st.one_of(st.floats(0, 1e6, allow_nan=False).map(lambda v: ("num", v)),
                   st.sampled_from(["x", "a", "b"]).map(lambda n: ("name", n)))
TREES = st.recursive(LEAVES, lambda sub: st.one_of(
    st.tuples(st.sampled_from(["+", "-", "*", "/", "%", "^"]), sub, sub),
    st.tuples(st.just("neg"), sub),
    st.tuples(st.just("call"), st.sampled_from(["sin", "fabs", "sqrt"]), sub),
    st.tuples(st.just("call"), st.sampled_from(["min", "atan2", "lt"]), sub, sub)),
    max_leaves=12)


@settings(max_examples=200, deadline=None)
@given(TREES)
def test_a_formula_written_back_reads_back_the_same(tree):
    """infix() parenthesises by precedence and associativity: the text parses to the same tree
    and the same numbers (NaN where the formula is NaN)."""
    text = Formula("", tree).infix()
    again = parse_formula(text)
    assert again.tree == tree, text
    env = {"x": np.array([0.0, 0.5, -3.0]), "a": 2.0, "b": 1e-3}
    np.testing.assert_array_equal(again.evaluate(env), Formula("", tree).evaluate(env))


# ---- the same in .fz: `f = formula("...")` and `var y ... hold_last` (issue 28: .fz says what
# the model holds, so converted files keep them)

def test_fz_writes_formulas_and_hold_and_reads_them_back():
    model = READERS[".fll"](APPROXIMATION, "approximation.fll")
    text = WRITERS[".fz"](model, [])
    assert "  var outputFx in [-1, 1] default 0 hold_last\n" in text
    assert '  terms trueFx : fx = formula("sin(inputX) / inputX")\n' in text
    assert '  terms diffFx : diff = formula("fabs(outputFx - trueFx)")\n' in text
    back = parse(text, "approximation.fz")
    x = np.array([[1.5], [10.0], [10.0], [0.0]])
    for semantics in ("exact", "fuzzylite", "pyfuzzylite"):
        assert np.array_equal(Chain(back).evaluate(x, semantics),
                              Chain(model).evaluate(x, semantics), equal_nan=True)
    # by hand, as above: 0.645 at 1.5, held at 10 (NEAR_9 is 0 there)
    assert Chain(back).evaluate(x)[:3, 0] == pytest.approx([0.645] * 3)


def test_a_fz_formula_term_by_hand():
    # MAMDANI above, written in .fz: a = 1 -> half = 1 - 1/2 = 0.5; centroid 11/18
    text = """controller m {
      input a in [0, 2]
      terms a : half = formula("1 - x / 2")
      var y in [0, 1] default 0
      terms y : up = formula("x")
      inference and = min, or = max, implication = min, aggregation = max, defuzzify = centroid
      rule if a is half then y is up
      output y_out in [0, 1] = y
    }"""
    model = parse(text, "m.fz")
    assert evaluate(model.rulebase, np.array([[1.0]]))[0, 0] == pytest.approx(11 / 18, abs=1e-6)
    held = parse(text.replace("default 0\n", "default 0 hold_last\n"), "m.fz")
    # a = 2: half = 0, nothing fires: the held output keeps the 11/18 of a = 1
    controller = Controller(held, batch=1)
    controller.step({"a": np.array([1.0])})
    assert controller.step({"a": np.array([2.0])})["y_out"] == pytest.approx([11 / 18], abs=1e-6)


@pytest.mark.parametrize("formula, col, words", [
    ("1 - z / 2", 37, "`z`: an input's Function term reads x (the input's value) only"),
    ("open(x)", 33, "unknown function `open`"),
    ("__import__('os')", 44, "unexpected `'`"),
    ("1 \\\\ 2", 33, "a formula has no backslash"),
])
def test_fz_formula_errors_are_located(formula, col, words):
    text = f"""controller m {{
      input a in [0, 2]
      terms a : half = formula("{formula}")
      var y in [0, 1] default 0
      terms y : up = tri(0, 1, 1)
      rule if a is half then y is up
      output y_out in [0, 1] = y
    }}"""
    with pytest.raises(FuzzycError) as err:
        parse(text, "m.fz")
    assert f"m.fz:3:{col}: error: {words}" in str(err.value), str(err.value)
