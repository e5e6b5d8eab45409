"""User names never meet the names fuzzyc generates.

What fuzzyc names itself: the hidden steps of delta/prev/lowpass (`__delta1_ce`: the prefix
`__` is reserved in .fz), the term of a numeric conclusion (`_v1`, or `_v1_2` when the file
has a `_v1`), the signal-chain output of an imported rule-base output `y` (`y_out`, or `y_out2`,
... when the file has a `y_out`), and in C the prefixes v_, u_, reciprocal_, memory_, seen_,
out_, NAME_PARAM_, NAME_IN_, NAME_OUT_, NAME_TERMS_ before every user name (so C keywords are
names like any other).  The property tests draw names among these and C keywords, and check
that a model means the same as with neutral names a, b, ...: check, eval, the CSV header, an
export, and the C header compiled by gcc."""
from __future__ import annotations

import contextlib
import io
import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.load import CController
from fuzzyc.cli import main
from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fis, read_fll, write_fis, write_fll, write_fz
from fuzzyc.language.parser import parse

GRAMMAR = Path(__file__).resolve().parents[1] / "fuzzyc" / "language" / "grammar" / "fuzzyc.lark"
FZ_WORDS = set(re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)"', GRAMMAR.read_text()))
C_KEYWORDS = ["int", "return", "default", "float", "double", "static", "const", "struct",
              "void", "char", "while", "switch", "case", "unsigned", "inline", "goto", "sizeof",
              "typedef", "union", "volatile", "extern", "long", "signed", "enum", "break",
              "else", "register", "auto", "do", "for", "if"]
# what the code generates, or names of the generated C (locals, helpers, fields, macros)
GENERATED = ["_delta1_n3", "_delta2_n3", "_lowpass1_n2", "_prev1_x", "_v0", "_v1", "_v1_2",
             "x_out", "y_out", "y_out2", "y_out_out", "n4_out", "arg", "value", "x", "y", "s",
             "k", "b", "xg", "yw", "num", "out", "step", "init", "state", "clamp", "rulebase",
             "fired", "isfinite", "NAN", "INFINITY", "memory_x", "seen_x", "out_y", "v_x",
             "u_x", "reciprocal_x", "PARAM_x", "IN_X", "OUT_Y", "TERMS_X", "fz_step", "m_step"]
FZ_POOL = [n for n in C_KEYWORDS + GENERATED if n not in FZ_WORDS]
NEUTRAL = ["a", "b", "c", "d", "e", "f", "g"]


def names(pool: list[str], n: int):
    """n distinct names, distinct also as the C #defines see them (upper case: `e1` and `E1`
    are one C name, refused by design)."""
    return st.lists(st.sampled_from(pool), min_size=n, max_size=n, unique_by=str.upper)


def run_cli(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(list(args))
    return code, out.getvalue()


def csv_columns(text: str) -> tuple[list[str], np.ndarray]:
    lines = text.strip().splitlines()
    return lines[0].split(","), np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])


# ---- .fz: hidden steps, numeric-conclusion terms ----------------------------------------------

def fz_text(n: list[str]) -> str:
    """Two inputs, a lowpass and a delta (hidden steps), a rule base with a numeric conclusion
    beside a declared `_v1`, a plain and an integrating output; n: the 7 names."""
    i0, i1, lp, dl, y, u, w = n
    return f"""controller m {{
  input {i0} in [0, 10]
  input {i1} in [0, 10]
  let {lp} in [0, 10] = lowpass({i1}, 0.5, 0.5)
  let {dl} in [-10, 10] = clamp(delta({i0}) + {i0}, -10, 10)
  terms {lp}, {dl} : lo = lshoulder(0, 10), hi = rshoulder(0, 10)
  var {y} in [0, 10] default 0
  terms {y} : _v1 = singleton(2), big = singleton(9)
  inference defuzzify = weighted_average
  rule if {dl} is hi and {lp} is hi then {y} is big
  rule if {dl} is lo then {y} is 7
  rule if {lp} is lo then {y} is _v1
  output {u} in [-20, 30] = {y} + {dl}
  output {w} in [0, 100] = integrate({y}) from 0
}}
"""


SERIES = np.array([[2.0, 8.0], [5.0, 1.0], [9.0, 4.0], [0.0, 10.0]])


def series(controller, names_in: list[str]) -> np.ndarray:
    controller.reset(1)
    rows = []
    for row in SERIES:
        out = controller.step({k: np.array([v]) for k, v in zip(names_in, row)})
        rows.append([float(out[name][0]) for name in controller.output_names])
    return np.array(rows)


@pytest.fixture(scope="module")
def neutral_fz():
    model = parse(fz_text(NEUTRAL), "neutral.fz")
    return model, series(Controller(model), NEUTRAL[:2])


def fz_names():
    """Seven names, often one spelled as a hidden step of fz_text was once named (the lowpass
    is the first stateful call, the delta the second: `_lowpass1_LP`, `_delta2_DL`)."""
    def twist(n):
        i0, i1, lp, dl, y, u, w = n
        return st.sampled_from([n, [f"_delta2_{dl}", i1, lp, dl, y, u, w],
                                [i0, f"_lowpass1_{lp}", lp, dl, y, u, w],
                                [i0, i1, lp, dl, y, f"_delta2_{dl}", w],
                                [i0, i1, lp, dl, f"_lowpass1_{lp}", u, w]])
    return names(FZ_POOL, 7).flatmap(twist).filter(lambda n: len({x.upper() for x in n}) == 7)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=fz_names())
def test_fz_names_mean_what_neutral_names_mean(n, neutral_fz):
    neutral, expected = neutral_fz
    text = fz_text(n)
    model = parse(text, "drawn.fz")
    assert not [s.name for s in model.steps if s.name in n and s.hidden]
    np.testing.assert_array_equal(series(Controller(model), n[:2]), expected)
    with tempfile.TemporaryDirectory() as work:
        rule_file, rows = Path(work, "m.fz"), Path(work, "in.csv")
        rule_file.write_text(text)
        assert run_cli("check", str(rule_file))[0] == 0
        rows.write_text(f"{n[0]},{n[1]}\n" + "".join(f"{a},{b}\n" for a, b in SERIES.tolist()))
        code, out = run_cli("eval", str(rule_file), "--csv", str(rows), "--series")
        assert code == 0
        header, values = csv_columns(out)
        # inputs, the rule-base output, the chain's outputs: each user name once, its value
        assert header == [n[0], n[1], n[4], n[5], n[6]]
        np.testing.assert_array_equal(values[:, 3:], expected)
    # the exported rule base (FLL) evaluates as the neutral one
    rb = read_fll(write_fll(model, []), "x.fll").rulebase
    x = np.array([[a, b] for a in np.linspace(-10, 10, 9) for b in np.linspace(0, 10, 7)])
    np.testing.assert_allclose(evaluate(rb, x), evaluate(neutral.rulebase, x), rtol=0,
                               atol=1e-12)
    # the C header: compiled with -Wshadow -Werror, the same numbers as the engine
    got = series(CController(model), n[:2])
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-4)


def test_let_named_like_delta_memory_keeps_its_value():
    """The review's case: `let _delta1_ce` was overwritten by delta(ce)'s hidden step."""
    text = """controller d {
  input x in [0, 2]
  let _delta1_ce in [0, 2] = x
  let ce in [-2, 2] = delta(x)
  terms _delta1_ce : P = rshoulder(0, 2)
  var y in [0, 1] default 0
  terms y : singletons zero=0 one=1
  inference defuzzify = weighted_average
  rule if _delta1_ce is P then y is one
  rule if _delta1_ce is not P then y is zero
  output u in [-2, 3] = y + ce
}
"""
    model = parse(text, "d.fz")
    # x = 2 on the first sample: _delta1_ce = 2, P = 2/2 = 1, not P = 0,
    # y = (1*1 + 0*0) / (1 + 0) = 1; ce = delta(x) = 0 on the first sample; u = 1 + 0 = 1
    # (the hidden step overwrote _delta1_ce with 0: P = 0, y = 0, u = 0)
    out = Controller(model).step({"x": np.array([2.0])})
    assert float(out["u"][0]) == 1.0
    # second sample x = 1: _delta1_ce = 1, P = 0.5, not P = 0.5, y = 0.5 / 1 = 0.5;
    # ce = 1 - 2 = -1; u = 0.5 - 1 = -0.5
    c = CController(model)
    assert float(c.step({"x": np.array([2.0])})["u"][0]) == 1.0
    assert float(c.step({"x": np.array([1.0])})["u"][0]) == pytest.approx(-0.5, abs=1e-6)
    assert "__delta1_ce" in generate_header(model)
    # the same read by the output alone: u = _delta1_ce + ce = 2 + 0 = 2 on the first sample
    # (the hidden step's 0 gave u = 0)
    model = parse(text.replace("= y + ce", "= _delta1_ce + ce"), "d.fz")
    assert float(Controller(model).step({"x": np.array([2.0])})["u"][0]) == 2.0


@pytest.mark.parametrize("statement", ["input __x in [0, 1]", "param __k = 2",
                                       "let __delta1_x = 1", "var __y in [0, 1] default 0",
                                       "output __u in [0, 1] = 1"])
def test_reserved_prefix_is_refused_with_its_place(statement):
    text = f"controller r {{\n  {statement}\n}}\n"
    with pytest.raises(FuzzycError) as err:
        parse(text, "r.fz")
    column = statement.index("__") + 3          # 1-based, after the two leading spaces
    message = str(err.value)
    assert f"r.fz:2:{column}:" in message and "reserved" in message


def test_numeric_conclusion_beside_a_term_named_v1():
    model = parse("""controller t {
  input x in [0, 1]
  terms x : lo = lshoulder(0, 1), hi = rshoulder(0, 1)
  var y in [0, 10] default 0
  terms y : _v1 = singleton(2)
  inference defuzzify = weighted_average
  rule if x is lo then y is _v1
  rule if x is hi then y is 8
  output u in [0, 10] = y
}
""", "t.fz")
    assert model.rulebase.outputs[0].names == ["_v1", "_v1_2"]
    # x = 0.25: lo = 0.75 (-> 2), hi = 0.25 (-> 8): y = (0.75*2 + 0.25*8) / 1 = 3.5
    assert evaluate(model.rulebase, [[0.25]])[0, 0] == pytest.approx(3.5, abs=1e-12)


# ---- imported formats: the chain outputs -----------------------------------------------------

FLL_WORDS = {"if", "then", "is", "and", "or", "with", "not", "any", "very", "somewhat",
             "extremely", "seldom"}
FLL_POOL = [n for n in C_KEYWORDS + GENERATED + ["y_OUT", "x_out2"] if n not in FLL_WORDS]


def fll_text(i0: str, i1: str, o0: str, o1: str) -> str:
    var = "  range: 0 10\n  term: lo Triangle -10 0 10\n  term: hi Triangle 0 10 20\n"
    out = "  range: 0 10\n  default: 0\n  aggregation: Maximum\n  defuzzifier: WeightedAverage\n"
    return (f"Engine: m\nInputVariable: {i0}\n{var}InputVariable: {i1}\n{var}"
            f"OutputVariable: {o0}\n{out}  term: small Constant 2\n  term: big Constant 8\n"
            f"OutputVariable: {o1}\n{out}  term: small Constant 1\n  term: big Constant 9\n"
            "  term: mid Constant 5\n"
            "RuleBlock:\n  conjunction: Minimum\n  disjunction: Maximum\n"
            "  activation: General\n"
            f"  rule: if {i0} is lo and {i1} is hi then {o0} is small and {o1} is big\n"
            f"  rule: if {i0} is hi then {o0} is big and {o1} is small\n"
            f"  rule: if {i1} is lo then {o1} is mid\n")


POINTS = np.array([[2.0, 8.0], [5.0, 1.0], [9.0, 4.0], [0.0, 10.0], [7.5, 7.5]])


def imported_names():
    """Four names, with an output or an input often named after another output's `_out`."""
    def twist(n):
        i0, i1, o0, o1 = n
        return st.sampled_from([n, [i0, i1, o0, o0 + "_out"], [i0, o0 + "_out", o0, o1],
                                [o1 + "_out", i1, o0, o1], [i0, i1, o0, o0.upper() + "_OUT"]])
    return names(FLL_POOL, 4).flatmap(twist).filter(
        lambda n: len({x.upper() for x in n}) == 4)


@pytest.fixture(scope="module")
def neutral_fll():
    model = read_fll(fll_text("a", "b", "c", "d"), "neutral.fll")
    return evaluate(model.rulebase, POINTS)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=imported_names(), fmt=st.sampled_from(["fll", "fis"]))
def test_imported_names_mean_what_neutral_names_mean(n, fmt, neutral_fll):
    expected = neutral_fll
    text = fll_text(*n)
    if fmt == "fis":
        text = write_fis(read_fll(text, "m.fll"), [])
    model = (read_fll if fmt == "fll" else read_fis)(text, f"m.{fmt}")
    chain = [o.name for o in model.outputs]
    assert not set(chain) & set(n) and len({c.upper() for c in chain + n}) == 6
    assert [str(o.expr) for o in model.outputs] == n[2:]      # each passes its own output
    with tempfile.TemporaryDirectory() as work:
        rule_file, rows = Path(work, f"m.{fmt}"), Path(work, "in.csv")
        rule_file.write_text(text)
        assert run_cli("check", str(rule_file))[0] == 0
        rows.write_text(f"{n[0]},{n[1]}\n" + "".join(f"{a},{b}\n" for a, b in POINTS.tolist()))
        code, out = run_cli("eval", str(rule_file), "--csv", str(rows))
        assert code == 0
        header, values = csv_columns(out)
        assert header == [*n, *chain]          # every name once
        np.testing.assert_allclose(values[:, 2:4], expected, rtol=0, atol=1e-12)
        np.testing.assert_allclose(values[:, 4:6], expected, rtol=0, atol=1e-12)
        # explained at the inputs' own values (not an output's of the same name)
        code, out = run_cli("eval", str(rule_file), f"{n[0]}=2", f"{n[1]}=8")
        assert f"rule-base inputs {n[0]} = 2, {n[1]} = 8" in out
    if not FZ_WORDS & set(n):     # (.fz keywords as names: tests/test_names_keywords.py)
        # to .fz and back: the same chain names, the same numbers
        again = parse(write_fz(model, []), "m.fz")
        assert [o.name for o in again.outputs] == chain
        np.testing.assert_allclose(evaluate(again.rulebase, POINTS), expected, rtol=0,
                                   atol=1e-12)
    c = CController(model, batch=len(POINTS))
    got = c.step({n[0]: POINTS[:, 0], n[1]: POINTS[:, 1]})
    np.testing.assert_allclose(np.column_stack([got[k] for k in chain]), expected, rtol=0,
                               atol=1e-5)


def test_fll_outputs_y_and_y_out_keep_their_values():
    """The review's case: outputs `y` and `y_out`; y's chain output was named `y_out` too."""
    model = read_fll(fll_text("x", "z", "y", "y_out"), "two.fll")
    assert [o.name for o in model.outputs] == ["y_out2", "y_out_out"]
    with tempfile.TemporaryDirectory() as work:
        path = Path(work, "two.fll")
        path.write_text(fll_text("x", "z", "y", "y_out"))
        code, out = run_cli("eval", str(path), "x=0", "z=10")
    # x = 0: lo = 1, hi = 0; z = 10: lo = 0, hi = 1.  Rule 1 fires min(1, 1) = 1: y small (2),
    # y_out big (9); rules 2 and 3 fire 0.  Weighted average: y = 2, y_out = 9.
    assert out.splitlines()[-1] == "outputs: y = 2, y_out = 9, y_out2 = 2, y_out_out = 9"
    c = CController(model)
    got = c.step({"x": np.array([0.0]), "z": np.array([10.0])})
    assert (float(got["y_out2"][0]), float(got["y_out_out"][0])) == pytest.approx((2, 9))


FIS_INPUT_Y_OUT = """[System]
Name='f'
Type='sugeno'
NumInputs=2
NumOutputs=1
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='prod'
AggMethod='sum'
DefuzzMethod='wtaver'

[Input1]
Name='x'
Range=[0 10]
NumMFs=1
MF1='A':'trimf',[-10 0 10]

[Input2]
Name='y_out'
Range=[0 10]
NumMFs=1
MF1='B':'trimf',[0 10 20]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='lo':'constant',[1]
MF2='hi':'constant',[9]

[Rules]
1 0, 1 (1) : 1
0 1, 2 (1) : 1
"""


def test_fis_input_named_y_out_is_explained_with_its_own_value(tmp_path):
    """The review's case: the chain output of `y` was named `y_out`, over the input."""
    path = tmp_path / "f.fis"
    path.write_text(FIS_INPUT_Y_OUT)
    code, out = run_cli("eval", str(path), "x=2", "y_out=6")
    assert code == 0
    # x = 2: A = (10 - 2) / 10 = 0.8 -> lo (1); y_out = 6: B = 6 / 10 = 0.6 -> hi (9)
    # y = (0.8*1 + 0.6*9) / (0.8 + 0.6) = 6.2 / 1.4 = 4.428571...
    lines = out.splitlines()
    assert lines[0] == "f: rule-base inputs x = 2, y_out = 6"
    assert lines[-1] == "outputs: y = 4.42857, y_out2 = 4.42857"


def test_controller_named_like_the_headers_locals_is_refused():
    model = parse(fz_text(NEUTRAL).replace("controller m", "controller v"), "v.fz")
    with pytest.raises(FuzzycError, match="rename the controller"):
        generate_header(model)


def test_controller_named_fz_runs_through_the_batch_shim():
    model = parse(fz_text(NEUTRAL).replace("controller m", "controller fz"), "fz.fz")
    np.testing.assert_allclose(series(CController(model), NEUTRAL[:2]),
                               series(Controller(model), NEUTRAL[:2]), rtol=0, atol=1e-4)
