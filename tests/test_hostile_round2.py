"""Hostile input, round 2: each case used to end in exit 70 with a traceback (or read a number
C reads differently). Now each is exit 2 with a clear, located message, and no traceback;
numbers from user text have one syntax (fuzzyc.language.numbers), the one the C example's strtod reads;
the Python API takes real numbers only."""

import math
import shutil
import subprocess
import time

import numpy as np
import pytest

import fuzzyc
from conftest import ROOT
from fuzzyc.cli import main
from fuzzyc.cli.simulate import parse_sets
from fuzzyc.errors import FuzzycError
from fuzzyc.language.limits import MAX_BATCH, MAX_HEDGES, MAX_NESTING
from fuzzyc.language.numbers import parse_number

CORPUS = ROOT / "tests" / "format_corpus"
FLL = (CORPUS / "tipper.fll").read_text()
FCL = (CORPUS / "tipper.fcl").read_text()
FLL_RULE = "if service is poor or food is rancid then tip is cheap"   # line 38 of tipper.fll
FCL_RULE = "IF service IS poor OR food IS rancid THEN tip IS cheap;"  # line 42 of tipper.fcl


def run(capsys, *argv) -> tuple[int, str, str]:
    """fuzzyc's exit status (argparse's too), stdout and stderr; never a traceback."""
    try:
        status = main([str(a) for a in argv])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    assert "Traceback" not in err, err
    return status, out, err


def write(tmp_path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


# ------------------------------------------------------- rule conditions nested too deep

@pytest.mark.parametrize("fmt,source,rule,template,line", [
    ("fll", FLL, FLL_RULE, "if {open}service is poor{close} then tip is cheap", 38),
    ("fcl", FCL, FCL_RULE, "IF {open}service IS poor{close} THEN tip IS cheap;", 42),
])
def test_a_rule_in_250_parentheses_is_a_located_error(tmp_path, capsys, fmt, source, rule,
                                                      template, line):
    deep = template.format(open="(" * 250, close=")" * 250)
    path = write(tmp_path, f"deep.{fmt}", source.replace(rule, deep))
    status, _, err = run(capsys, "check", path)
    assert status == 2
    head = err.splitlines()[0]
    # the caret stands where the group nested 201 deep starts, just inside its `(`
    column = source.splitlines()[line - 1].index(rule.split()[0]) + 1 + len("IF ") + 201
    assert head == (f"{path}:{line}:{column}: error: a rule condition nested more than "
                    f"{MAX_NESTING} parentheses deep (fuzzyc.language.limits.MAX_NESTING); write it with "
                    "fewer, or as several rules")


@pytest.mark.parametrize("template", [
    "if {o}service is poor{c} then tip is cheap",
    "if {nots}service is poor{c} then tip is cheap",
    "if {ands}food is rancid{c} then tip is cheap",
])
def test_a_rule_at_the_nesting_limit_reads(tmp_path, template):
    # 200 levels of parentheses, of `not (`, of `x and (`: no RecursionError anywhere
    n = MAX_NESTING
    deep = template.format(o="(" * n, nots="not (" * n, ands="service is poor and (" * n,
                           c=")" * n)
    model = fuzzyc.load(write(tmp_path, "at_limit.fll", FLL.replace(FLL_RULE, deep)))
    assert model.rulebase.n_rules == 4


def test_a_clause_with_1000_hedges_is_a_located_error(tmp_path, capsys):
    rule = "if service is " + "very " * 1000 + "poor then tip is cheap"
    path = write(tmp_path, "hedges.fll", FLL.replace(FLL_RULE, rule))
    status, _, err = run(capsys, "check", path)
    assert status == 2
    # at the first hedge past the limit
    column = len("  rule: if service is ") + len("very ") * MAX_HEDGES + 1
    assert err.splitlines()[0] == (f"{path}:38:{column}: error: 1000 hedges on one clause: at "
                                   f"most {MAX_HEDGES} (fuzzyc.language.limits.MAX_HEDGES)")


def test_hedges_at_the_limit_read_and_conclusions_carry_at_most_the_limit(tmp_path, capsys):
    at_limit = "if service is " + "very " * MAX_HEDGES + "poor then tip is cheap"
    fuzzyc.load(write(tmp_path, "ok.fll", FLL.replace(FLL_RULE, at_limit)))
    # each conclusion's hedges carry on to the next ones (fuzzylite): together at most the limit
    two = FLL.replace("OutputVariable: tip", "OutputVariable: tip2\n  range: 0 30\n"
                      "  term: cheap Triangle 0 5 10\nOutputVariable: tip")
    carried = ("if service is poor then tip is " + "very " * 10 + "cheap and tip2 is "
               + "very " * 10 + "cheap")
    path = write(tmp_path, "carried.fll", two.replace(FLL_RULE, carried))
    status, _, err = run(capsys, "check", path)
    assert status == 2
    assert (f"error: the conclusions of a rule carry more than {MAX_HEDGES} hedges in all"
            in err)


# ------------------------------------------------------------------- --batch bounded

@pytest.mark.parametrize("batch", ["99999999999", "30000000", str(MAX_BATCH + 1)])
def test_batch_past_its_bound_is_refused_before_any_work(tmp_path, capsys, batch):
    start = time.perf_counter()
    status, _, err = run(capsys, "simulate", "--scenario", "fopdt_step", "--batch", batch,
                         "-o", tmp_path / "out")
    assert status == 2
    assert (f"argument --batch: must be at most {MAX_BATCH:,}, got {int(batch):,}" in err)
    assert time.perf_counter() - start < 5      # 3e7 loops used to allocate 2 GB first
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("batch", ["1_000", "１０", "1e3", "0"])
def test_batch_is_a_plain_whole_number(tmp_path, capsys, batch):
    status, _, err = run(capsys, "simulate", "--scenario", "fopdt_step", "--batch", batch,
                         "-o", tmp_path / "out")
    assert status == 2 and "argument --batch:" in err


def test_the_api_bounds_batch_too():
    with pytest.raises(ValueError, match="batch must be a whole number of loops from 1 to"):
        fuzzyc.simulate("fopdt_step", batch=30_000_000)


def test_the_batch_bound_is_documented():
    assert f"{MAX_BATCH:,}".replace(",", " ") in (ROOT / "docs" / "limits.md").read_text()


# ---------------------------------------------------------- a model name too long for a file

def test_a_model_name_too_long_for_a_file_name_is_refused(tmp_path, capsys):
    name = "n" * 261
    path = write(tmp_path, "long.fll", FLL.replace("Engine: tipper", f"Engine: {name}"))
    out = tmp_path / "out"
    status, _, err = run(capsys, "compile", path, "-o", out)
    assert status == 2
    assert err.splitlines()[0].startswith(
        f"{path}:3:9: error: the model name (261 characters) would make the header's file "
        "name 263 bytes long: at most 239")
    assert "give the model a shorter name" in err
    assert not out.exists() or list(out.iterdir()) == []


# ------------------------------------------------------------------- let expressions

LET = """\
controller lets {{
  input a in [-1, 1]
  let b in [0, 3] = {expr}
  terms b : uniform N ZO P
  var du in [-1, 1] default 0
  terms du : uniform N ZO P
  rule if b is P then du is P
  output u in [-1, 1] = du
}}
"""


def test_abs_of_exp_compiles_as_exp(tmp_path, capsys):
    # sympy used to make exp(re(a)) of it, which the C back end cannot translate
    model = fuzzyc.parse(LET.format(expr="abs(exp(a))"))
    (step,) = model.steps
    assert str(step.expr) == "exp(a)"
    assert all(s.is_real is None for s in step.expr.free_symbols)   # plain symbols outside
    c = fuzzyc.Controller(model)
    c.step({"a": np.array([0.5])})
    assert c.signals["b"][0] == pytest.approx(math.exp(0.5))
    path = write(tmp_path, "lets.fz", LET.format(expr="abs(exp(a))"))
    status, out, _ = run(capsys, "compile", path, "-o", tmp_path)
    assert status == 0 and "wrote" in out


def test_a_let_that_is_no_real_number_is_located(tmp_path, capsys):
    path = write(tmp_path, "lets.fz", LET.format(expr="log(-1) + a"))
    status, _, err = run(capsys, "check", path)
    assert status == 2
    assert err.splitlines()[0] == (f"{path}:3:21: error: this expression makes `I*pi` (sympy's "
                                   "value of it), which is not a real number")


def test_a_param_still_works_as_a_lowpass_coefficient():
    # the builder's symbols are real inside, plain outside: a param is still substituted
    text = LET.format(expr="lowpass(a, k, 0.5) + 1").replace(
        "  input a", "  param k = 0.5\n  input a")
    fuzzyc.parse(text)


# ------------------------------------------------------------ one number syntax everywhere

ACCEPTED = {"4": 4.0, "4.": 4.0, "4.0": 4.0, "+4": 4.0, "-4": -4.0, ".5": 0.5, "-.5": -0.5,
            "4e0": 4.0, "4E+00": 4.0, "40e-1": 4.0, "0.4e1": 4.0, "007": 7.0, " 4": 4.0,
            "4 ": 4.0, "1e400": math.inf, "inf": math.inf, "-inf": -math.inf,
            "INF": math.inf, "Infinity": math.inf, "nan": math.nan, "NaN": math.nan}
REFUSED = ["0_5", "1_000", "\uff15", "\u0664", "4\u00a0", "", " ", ".", "e5", "4e", "4e+",
           "--4", "+-4", "4.0.0", "infinit", "inf4", "4d", "4f", "1e5.5", "nan4"]
# strtod reads these too; fuzzyc refuses them by design (decimal only)
C_ONLY = ["0x10", "0x1p3", "nan(1)"]


def same(a: float, b: float) -> bool:
    return a == b or (math.isnan(a) and math.isnan(b))


@pytest.mark.parametrize("text", list(ACCEPTED))
def test_accepted_spellings(text):
    assert same(parse_number(text), ACCEPTED[text])


@pytest.mark.parametrize("text", REFUSED + C_ONLY)
def test_refused_spellings(text):
    assert parse_number(text) is None


def shown(text: str) -> str:
    return f"`{text}` is not a number"


@pytest.mark.parametrize("text", REFUSED + C_ONLY)
def test_eval_refuses_them_in_name_value_and_in_a_csv_cell(tmp_path, capsys, text):
    path = str(CORPUS / "tipper.fll")
    status, _, err = run(capsys, "eval", path, f"service={text}", "food=5")
    assert status == 2 and shown(text) in err and f"(in `service={text}`)" in err
    csv = write(tmp_path, "in.csv", f"food,service\n5,5\n5,{text}\n")
    status, _, err = run(capsys, "eval", path, "--csv", csv)
    assert status == 2
    assert err.startswith(f"error: {csv}:3:2: {shown(text)}"), err


@pytest.mark.parametrize("text", list(ACCEPTED))
def test_eval_reads_them_in_name_value_and_in_a_csv_cell(tmp_path, capsys, text):
    path = str(CORPUS / "tipper.fll")
    status, _, _ = run(capsys, "eval", path, f"service={text}", "food=5")
    assert status == 0
    csv = write(tmp_path, "in.csv", f"food,service\n5,{text}\n")
    status, out, _ = run(capsys, "eval", path, "--csv", csv)
    assert status == 0
    header, row = (line.split(",") for line in out.splitlines()[:2])
    assert same(float(row[header.index("service")]), ACCEPTED[text])


FINITE_FOURS = [t for t, v in ACCEPTED.items() if v == 4.0 and t.strip() == t]


@pytest.mark.parametrize("text", FINITE_FOURS + ["0_5", "1_000", "\uff15", "\u0664", "4e",
                                                 "inf4", "4d"] + C_ONLY)
def test_fll_and_fis_numeric_fields(text):
    fll = FLL.replace("term: poor Ramp 4.000 0.000", f"term: poor Ramp {text} 0.000")
    fis = (CORPUS / "tipper.fis").read_text()
    mf = next(line for line in fis.splitlines() if line.startswith("MF1="))
    params = mf[mf.index("[") + 1:mf.index("]")].split()
    fis = fis.replace(mf, mf.replace(params[0], text, 1))
    if text in FINITE_FOURS:
        assert np.array_equal(fuzzyc.parse(fll, "fll").rulebase.inputs[0].params,
                              fuzzyc.parse(FLL, "fll").rulebase.inputs[0].params)
        fuzzyc.parse(fis, "fis")
        return
    with pytest.raises(FuzzycError) as info:
        fuzzyc.parse(fll, "fll", "t.fll")
    assert str(info.value).startswith(f"t.fll:9:19: error: {shown(text)}")
    with pytest.raises(FuzzycError):
        fuzzyc.parse(fis, "fis")


@pytest.mark.parametrize("text", ["\uff14", "4\u0664", "1_0"])
def test_fcl_numbers_are_ascii(text):
    with pytest.raises(FuzzycError, match="unexpected"):
        fuzzyc.parse(FCL.replace("GAUSS 6 1.5", f"GAUSS {text} 1.5"), "fcl")


@pytest.mark.parametrize("text,value", [("1e3", "1000.0"), ("010", "10"), ("inf", ".inf"),
                                        ("1.5", "1.5"), ("plain", "plain")])
def test_set_values_reach_yaml_in_the_one_syntax(text, value):
    assert parse_sets([f"plant.k={text}"]) == {"plant.k": value}


@pytest.mark.parametrize("text", ["1_000", ".inf", "0x10", "1:30"])
def test_set_refuses_numbers_only_yaml_reads(capsys, text):
    with pytest.raises(FuzzycError, match="is not a number"):
        parse_sets([f"plant.k={text}"])


@pytest.mark.parametrize("text", ["food=0_5", "food=\uff15"])
def test_plot_at_refuses_them(tmp_path, capsys, text):
    status, _, err = run(capsys, "plot", CORPUS / "tipper.fll", "--at", text, "-o", tmp_path)
    assert status == 2 and "is not a number" in err


STRTOD_CELL = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
/* Each line is one cell: 1 when strtod, as examples/c/main.c calls it, reads all of it (spaces
 * around aside), else 0. */
int main(void) {
    char line[256];
    while (fgets(line, sizeof line, stdin)) {
        char *end;
        line[strcspn(line, "\n")] = 0;
        (void)strtod(line, &end);
        int read = end != line;
        while (*end == ' ') ++end;
        printf("%d\n", read && *end == 0);
    }
    return 0;
}
"""


@pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc")
def test_strtod_reads_exactly_the_accepted_spellings_as_whole_cells(tmp_path):
    (tmp_path / "cell.c").write_text(STRTOD_CELL)
    subprocess.run(["gcc", "-std=c99", "-o", str(tmp_path / "cell"), str(tmp_path / "cell.c")],
                   check=True)
    spellings = list(ACCEPTED) + REFUSED + C_ONLY
    out = subprocess.run([str(tmp_path / "cell")], capture_output=True, check=True,
                         input="".join(f"{t}\n" for t in spellings).encode()).stdout.split()
    assert len(out) == len(spellings)
    for text, read in zip(spellings, out):
        assert (read == b"1") == (text in ACCEPTED or text in C_ONLY), repr(text)


@pytest.mark.skipif(shutil.which("gcc") is None, reason="no gcc")
def test_the_c_example_reads_each_accepted_spelling_as_fuzzyc_does(tmp_path, capsys):
    # examples/c/main.c on rows `SPELLING,5` gives the outputs fuzzyc eval gives
    model = fuzzyc.load(CORPUS / "tipper.fll")
    fuzzyc.compile_c(model, "double").write(tmp_path)
    exe = tmp_path / "controller"
    subprocess.run(["gcc", "-std=c99", "-O2", "-I", str(tmp_path), "-DFZ_MODEL=tipper",
                    "-DFZ_UPPER=TIPPER", str(ROOT / "examples" / "c" / "main.c"), "-lm",
                    "-o", str(exe)], check=True)
    rows = "".join(f"{t},5\n" for t in ACCEPTED)
    c_out = subprocess.run([str(exe), "-r"], input=rows.encode(), capture_output=True,
                           check=True).stdout.decode().split()
    csv = write(tmp_path, "in.csv", "service,food\n" + rows)
    status, out, _ = run(capsys, "eval", CORPUS / "tipper.fll", "--core", "--csv", csv)
    assert status == 0
    ours = [float(line.split(",")[2]) for line in out.splitlines()[1:]]
    assert len(c_out) == len(ours) == len(ACCEPTED)
    for text, c_value, value in zip(ACCEPTED, c_out, ours):
        assert float(c_value) == pytest.approx(value, rel=1e-8), repr(text)


# ------------------------------------------------------------------- the Python API

BAD_VALUES = {
    "None": (None, "None, not a number"),
    "datetime64": (np.datetime64("2024-01-01"), "of type datetime64"),
    "timedelta64": (np.timedelta64(3, "s"), "of type timedelta64"),
    "masked array": (np.ma.masked_array([1.0, 2.0], [False, True]), "a masked array"),
    "10**400": (10 ** 400, "an integer of 401 digits, too large for a float"),
    "complex": (1 + 2j, "of type complex"),
    "complex array": (np.array([1 + 1j]), "an array of dtype complex128"),
    "object array": (np.array([1.0, None], dtype=object), "None, not a number"),
    "list with None": ([1.0, None], "None, not a number"),
    "list with 10**400": ([1, 10 ** 400], "too large for a float"),
    "string": ("1.5", "of type str"),
    "bool": (True, "the boolean True"),
    "bool array": (np.array([True, False]), "an array of dtype bool"),
}


@pytest.mark.parametrize("kind", list(BAD_VALUES))
def test_api_refuses_what_is_not_a_real_number(kind):
    value, message = BAD_VALUES[kind]
    model = fuzzyc.load(CORPUS / "tipper.fll")
    with pytest.raises(ValueError, match="^input `service`: ") as info:
        fuzzyc.evaluate(model, {"service": value, "food": 5.0})
    assert message in str(info.value)
    controller = fuzzyc.Controller(model, batch=2)
    with pytest.raises(ValueError, match="^input `service`: ") as info:
        controller.step({"service": value, "food": np.array([5.0, 5.0])})
    assert message in str(info.value)


@pytest.mark.parametrize("value", [3, 3.0, np.float32(3), np.int64(3), [3, 3], (3.0, 3.0),
                                   np.array([3, 3], dtype=np.uint8), np.array(3.0), 2 ** 1000,
                                   math.nan, math.inf])
def test_api_takes_real_numbers_and_numeric_arrays(value):
    model = fuzzyc.load(CORPUS / "tipper.fll")
    fuzzyc.evaluate(model, {"service": value, "food": 5.0})
    fuzzyc.Controller(model, batch=2).step({"service": value, "food": np.array([5.0, 5.0])})


def test_explain_refuses_them_too():
    model = fuzzyc.load(CORPUS / "tipper.fll")
    with pytest.raises(ValueError, match="input `food`: None"):
        fuzzyc.explain(model, {"service": 3.0, "food": None})
