"""FCL as jFuzzyLogic writes it (issue 28): each construct of its dialect in a small hand-written
file (inline: nothing here is copied from jFuzzyLogic's files) with a hand-computed number, the
arithmetic in a comment, or the located refusal.  What jFuzzyLogic means was read from its
grammar (Fcl.g) and sources (MembershipFunction*.estimateUniverse, RuleBlock, the
defuzzifiers); docs/formats.md, "jFuzzyLogic's FCL", says what is read and what is refused."""
from __future__ import annotations

import math
import shutil
import subprocess

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl
from fuzzyc.formats.fcl import check_fcl
from fuzzyc.semantics.model import Aggregation, Defuzzifier, TermKind


def messages(exc: pytest.ExceptionInfo) -> list[str]:
    return [d.format().splitlines()[0] for d in exc.value.diagnostics]


def value(model, *inputs: float) -> float:
    return float(evaluate(model.rulebase, np.array([inputs], dtype=float))[0, 0])


# x in [0, 10]: low (10 - x) / 10, mid TRIAN 0 5 10, high x / 10
INPUT = """
VAR_INPUT
  x : REAL;
END_VAR
FUZZIFY x
  TERM low := TRIAN 0 0 10;
  TERM mid := TRIAN 0 5 10;
  TERM high := TRIAN 0 10 10;
  RANGE := (0 .. 10);
END_FUZZIFY
"""


def mamdani(defuzzify: str, rules: str) -> str:
    return f"""FUNCTION_BLOCK m
{INPUT}
VAR_OUTPUT
  y : REAL;
END_VAR
DEFUZZIFY y
  TERM p := TRAPE 0 0 6 6;
  TERM q := TRAPE 4 4 10 10;
  TERM c := TRIAN 0 5 10;
  {defuzzify}
  RANGE := (0 .. 10);
END_DEFUZZIFY
RULEBLOCK r
  {rules}
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


# ---------------------------------------------------------------------- RANGE left out
def test_universe_from_the_terms_as_jfuzzylogic_estimates_it():
    text = """FUNCTION_BLOCK u
VAR_INPUT
  x : REAL;
END_VAR
VAR_OUTPUT
  y : REAL;
END_VAR
FUZZIFY x
  TERM low := TRIAN 0 0 4;
  TERM high := GAUSS 6 1;
END_FUZZIFY
DEFUZZIFY y
  TERM a := 2;
  TERM b := 8;
  METHOD : COGS;
END_DEFUZZIFY
RULEBLOCK r
  AND : MIN;
  ACCU : MAX;
  RULE 1 : IF x IS low THEN y IS a;
  RULE 2 : IF x IS high THEN y IS b;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""
    model = read_fcl(text, "u.fcl")
    x, = model.rulebase.inputs
    y, = model.rulebase.outputs
    # x: TRIAN 0 0 4 spans [0, 4], GAUSS 6 1 spans 6 -+ 4*1 = [2, 10]: [min 0, max 10]
    assert (x.lo, x.hi) == (0.0, 10.0)
    # y: the singletons' places, [2, 8]
    assert (y.lo, y.hi) == (2.0, 8.0)
    assert any("no RANGE: took [0, 10]" in n for n in model.notes)
    # x = 6: low 0, high 1 -> y = 8
    assert value(model, 6.0) == pytest.approx(8.0, abs=1e-12)


def test_universe_of_the_smooth_shapes():
    text = """FUNCTION_BLOCK u
VAR_INPUT
  a : REAL; b : REAL; c : REAL; d : REAL;
END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY a TERM t := GBELL 2 1 5; END_FUZZIFY
FUZZIFY b TERM t := SIGM 3 1; END_FUZZIFY
FUZZIFY c TERM t := COSINE 2 3; END_FUZZIFY
FUZZIFY d TERM t := (1, 0) (2, 1) (7, 0); END_FUZZIFY
DEFUZZIFY y TERM one := 1; TERM two := 2; METHOD : COGS; END_DEFUZZIFY
RULEBLOCK r ACCU : MAX; RULE 1 : IF a IS t THEN y IS one; END_RULEBLOCK
END_FUNCTION_BLOCK
"""
    inputs = {v.name: v for v in read_fcl(text, "u.fcl").rulebase.inputs}
    # GBELL a=2 b=1 mean=5: 5 -+ 999^(1/(2*1)) * 2 = 5 -+ 31.60696 * 2 = 5 -+ 63.21392
    assert inputs["a"].lo == pytest.approx(5 - 2 * math.sqrt(999))
    assert inputs["a"].hi == pytest.approx(5 + 2 * math.sqrt(999))
    # SIGM gain 3, t0 1: 1 -+ 9/3 = [-2, 4]
    assert (inputs["b"].lo, inputs["b"].hi) == pytest.approx((-2.0, 4.0))
    # COSINE net_max 2, offset 3: 3 -+ 2 = [1, 5]
    assert (inputs["c"].lo, inputs["c"].hi) == (1.0, 5.0)
    # a point list: its first and last x
    assert (inputs["d"].lo, inputs["d"].hi) == (1.0, 7.0)


def test_range_after_the_declaration():
    # jFuzzyLogic's `x : REAL; RANGE := (a .. b);`
    text = mamdani("METHOD : COG; ACCU : MAX;", "RULE 1 : IF x IS low THEN y IS c;").replace(
        "  x : REAL;\n", "  x : REAL; RANGE := (0 .. 20);\n").replace("  RANGE := (0 .. 10);\nEND_FUZZIFY", "END_FUZZIFY")
    x, = read_fcl(text, "r.fcl").rulebase.inputs
    assert (x.lo, x.hi) == (0.0, 20.0)


# ---------------------------------------------------------------------- several blocks, no outputs
TWO_BLOCKS = """FUNCTION_BLOCK first
VAR_INPUT x : REAL; RANGE := (0 .. 10); END_VAR
VAR_OUTPUT y : REAL; RANGE := (0 .. 10); END_VAR
FUZZIFY x TERM low := TRIAN 0 0 10; END_FUZZIFY
DEFUZZIFY y TERM one := 1; TERM nine := 9; METHOD : COGS; END_DEFUZZIFY
RULEBLOCK r ACCU : MAX; RULE 1 : IF x IS low THEN y IS one; END_RULEBLOCK
END_FUNCTION_BLOCK

FUNCTION_BLOCK second
VAR_INPUT x : REAL; RANGE := (0 .. 10); END_VAR
FUZZIFY x TERM low := TRIAN 0 0 10; TERM high := TRIAN 0 10 10; END_FUZZIFY
END_FUNCTION_BLOCK
"""


def test_several_blocks_checked_whole_and_a_block_without_outputs():
    checked = check_fcl(TWO_BLOCKS, "two.fcl")
    assert [label for label, _ in checked] == ["two.fcl::first", "two.fcl::second"]
    first, second = (read for _, read in checked)
    # first: x = 4, low 0.6 -> y = one = 1 (one rule fired)
    assert value(first, 4.0) == pytest.approx(1.0)
    # second has no output: a membership demo, its inputs and terms checked
    assert [(v.name, len(v.terms), v.lo, v.hi) for v in second] == [("x", 2, 0.0, 10.0)]


def test_several_blocks_each_error_reported(tmp_path, capsys):
    bad = TWO_BLOCKS.replace("THEN y IS one", "THEN y IS two").replace(
        "TERM high := TRIAN 0 10 10", "TERM high := TRIAN 0 11 10")
    path = tmp_path / "two.fcl"
    path.write_text(bad)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    # one error in each block, each at its line:col
    lines = bad.splitlines()
    two = lines[5].index("two") + 1
    trian = lines[10].index("TRIAN 0 11") + 1
    assert f"two.fcl:6:{two}: error: `y` has no term `two`" in err
    assert f"two.fcl:11:{trian}: error: degenerate TRIAN (0 11 10)" in err


def test_check_cli_membership_demo(tmp_path, capsys):
    path = tmp_path / "demo.fcl"
    path.write_text(TWO_BLOCKS[TWO_BLOCKS.index("FUNCTION_BLOCK second"):])
    assert main(["check", str(path)]) == 0
    assert "inputs x(2); no outputs (membership functions only" in capsys.readouterr().out


# ---------------------------------------------------------------------- DEFUZZIFY, ACT, ACCU
# low -> p (rectangle [0, 6]), mid -> q (rectangle [4, 10]).  At x = 2.5: low 0.75, mid 0.5.
# The aggregated set is 0.75 on [0, 4], v = ACCU(0.75, 0.5) on [4, 6], 0.5 on [6, 10]:
# area 0.75*4 + 2v + 0.5*4 = 5 + 2v, moment 0.75*4*2 + v*(36-16)/2 + 0.5*(100-36)/2 = 22 + 10v
ACCU_RULES = "ACT : MIN;\n  RULE 1 : IF x IS low THEN y IS p;\n  RULE 2 : IF x IS mid THEN y IS q;"


@pytest.mark.parametrize("accu, v, aggregation", [
    ("MAX", 0.75, Aggregation.MAX),
    ("SUM", 1.25, Aggregation.SUM),                 # unbounded
    ("BSUM", 1.0, Aggregation.BOUNDED_SUM),         # min(1, a + b)
    ("NSUM", 1.0, Aggregation.BOUNDED_SUM),         # (a + b) / max(1, a + b), folded: min(1, a+b)
    ("PROBOR", 0.875, Aggregation.PROBSUM),         # 0.75 + 0.5 - 0.375
])
def test_accu_variants_centroid(accu, v, aggregation):
    for where in ("rules", "defuzzify"):      # jFuzzyLogic: in the RULEBLOCK; fuzzylite: DEFUZZIFY
        if where == "rules":
            text = mamdani("METHOD : COG;", f"ACCU : {accu};\n  {ACCU_RULES}")
        else:
            text = mamdani(f"METHOD : COG; ACCU : {accu};", ACCU_RULES)
        model = read_fcl(text, "a.fcl")
        assert model.rulebase.inference.aggregation == aggregation
        # MAX 29.5/6.5 = 4.53846, SUM 34.5/7.5 = 4.6, BSUM 32/7 = 4.571429, PROBOR 30.75/6.75
        assert value(model, 2.5) == pytest.approx((22 + 10 * v) / (5 + 2 * v), abs=1e-9)


def test_method_coa_is_the_bisector():
    model = read_fcl(mamdani("METHOD : COA;", f"ACCU : MAX;\n  {ACCU_RULES}"), "a.fcl")
    assert model.rulebase.inference.defuzzifier == Defuzzifier.BISECTOR
    # area 6.5, half 3.25: [0, 4] holds 3, then 0.25 more at height 0.75 -> 4 + 1/3
    assert value(model, 2.5) == pytest.approx(4 + 1 / 3, abs=1e-6)


# high -> c (TRIAN 0 5 10) at x = 5: activation 0.5.  ACT MIN clips c to a plateau of 0.5 on
# [2.5, 7.5]; ACT PROD scales it, one peak at 5.
@pytest.mark.parametrize("method, act, expected", [
    ("LM", "MIN", 2.5), ("RM", "MIN", 7.5), ("MM", "MIN", 5.0),
    ("LM", "PROD", 5.0), ("RM", "PROD", 5.0), ("MM", "PROD", 5.0),
    ("COG", "MIN", 5.0), ("COG", "PROD", 5.0),
])
def test_methods_and_act(method, act, expected):
    text = mamdani(f"METHOD : {method};", f"ACT : {act}; ACCU : MAX;\n"
                                          "  RULE 1 : IF x IS high THEN y IS c;")
    assert value(read_fcl(text, "m.fcl"), 5.0) == pytest.approx(expected, abs=1e-6)


def test_cogs_over_singletons():
    text = sugeno("TERM s1 := 2; TERM s2 := 8;", "RULE 1 : IF x IS low THEN y IS s1;\n"
                  "  RULE 2 : IF x IS high THEN y IS s2;", method="COGS").replace(
        "ACCU : SUM;", "ACCU : MAX;")
    # x = 2.5: low 0.75, high 0.25: (0.75*2 + 0.25*8) / (0.75 + 0.25) = 3.5
    assert value(read_fcl(text, "s.fcl"), 2.5, 0.0) == pytest.approx(3.5, abs=1e-12)


def test_default_value():
    text = mamdani("METHOD : COG; DEFAULT := 7;", "ACCU : MAX;\n  RULE 1 : IF x IS mid THEN y IS c;")
    # x = 10: mid 0, no rule fires: the DEFAULT
    assert value(read_fcl(text, "d.fcl"), 10.0) == pytest.approx(7.0)


# ---------------------------------------------------------------------- Takagi-Sugeno
def sugeno(terms: str, rules: str, method: str = "COGF") -> str:
    return f"""FUNCTION_BLOCK ts
{INPUT}
VAR_INPUT z : REAL; RANGE := (0 .. 4); END_VAR
VAR_OUTPUT y : REAL; RANGE := (0 .. 100); END_VAR
FUZZIFY z TERM any := TRAPE 0 0 4 4; END_FUZZIFY
DEFUZZIFY y
  {terms}
  METHOD : {method};
END_DEFUZZIFY
RULEBLOCK r
  ACCU : SUM;
  {rules}
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_function_consequent_cogf():
    text = sugeno("TERM f := FUNCTION 2 * x + z ^ 2 * 3; TERM g := 10;",
                  "RULE 1 : IF x IS low THEN y IS f;\n  RULE 2 : IF x IS high THEN y IS g;")
    model = read_fcl(text, "ts.fcl")
    y, = model.rulebase.outputs
    assert TermKind(int(y.kinds[0])) == TermKind.FUNCTION
    # x = 2.5, z = 2: f = 2*2.5 + (2^2)*3 = 5 + 12 = 17 (^ binds before *, * before +);
    # low 0.75, high 0.25: (0.75*17 + 0.25*10) / 1 = 12.75 + 2.5 = 15.25
    assert value(model, 2.5, 2.0) == pytest.approx(15.25, abs=1e-12)


def test_function_precedence_and_remainder():
    # jFuzzyLogic: ^ and % on one level, left to right: 2 ^ 3 % 5 = (2^3) % 5 = 3;
    # ln(exp(z)) = z; abs(z - 4) at z = 1 is 3.  f = 3 + 1 + 3 = 7
    text = sugeno("TERM f := FUNCTION 2 ^ 3 % 5 + ln(exp(z)) + abs(z - 4);",
                  "RULE 1 : IF x IS low THEN y IS f;")
    assert value(read_fcl(text, "ts.fcl"), 2.5, 1.0) == pytest.approx(7.0, abs=1e-12)


def test_term_naming_a_variable_on_an_output_is_its_value():
    # `TERM v := z;`: a singleton at z's value.  x = 2.5, z = 3: low 0.75 -> v = 3,
    # high 0.25 -> g = 10: (0.75*3 + 0.25*10) / 1 = 4.75
    text = sugeno("TERM v := z; TERM g := 10;",
                  "RULE 1 : IF x IS low THEN y IS v;\n  RULE 2 : IF x IS high THEN y IS g;",
                  method="COGS")
    assert value(read_fcl(text, "ts.fcl"), 2.5, 3.0) == pytest.approx(4.75, abs=1e-12)


@pytest.mark.parametrize("terms, method, message", [
    ("TERM f := FUNCTION 2 * y;", "COGF", "`y` is an output: jFuzzyLogic refuses it"),
    ("TERM f := FUNCTION log(x);", "COGF", "jFuzzyLogic's `log` is not read"),
    ("TERM f := FUNCTION 2 * w;", "COGF", "`w` is not an input variable"),
    ("TERM f := FUNCTION 2 * x;", "COG", "needs METHOD COGF or COGS; `y` has COG"),
])
def test_function_refusals(terms, method, message):
    with pytest.raises(FuzzycError) as exc:
        read_fcl(sugeno(terms, "RULE 1 : IF x IS low THEN y IS f;", method), "ts.fcl")
    assert any(message in m and m.startswith("ts.fcl:") for m in messages(exc))


def test_function_refusal_is_located_at_the_name():
    text = sugeno("TERM f := FUNCTION 2 * w;", "RULE 1 : IF x IS low THEN y IS f;")
    with pytest.raises(FuzzycError) as exc:
        read_fcl(text, "ts.fcl")
    line = next(n for n, l in enumerate(text.splitlines(), 1) if "FUNCTION 2 * w" in l)
    col = text.splitlines()[line - 1].index("w;") + 1
    assert messages(exc)[0].startswith(f"ts.fcl:{line}:{col}: error: FUNCTION of term `f`")


# ---------------------------------------------------------------------- parameters naming variables
@pytest.mark.parametrize("term, word", [
    ("TERM mid2 := TRIAN 0 z 10;", "TRIAN parameter `z`"),
    ("TERM mid2 := (0, 0) (z, 1) (10, 0);", "point parameter `z`"),
    ("TERM mid2 := z;", "singleton at variable `z`"),
])
def test_parameter_naming_a_variable_on_an_input_is_refused(term, word):
    text = sugeno("TERM g := 10;", "RULE 1 : IF x IS low THEN y IS g;").replace(
        "TERM high := TRIAN 0 10 10;", "TERM high := TRIAN 0 10 10;\n  " + term)
    with pytest.raises(FuzzycError) as exc:
        read_fcl(text, "p.fcl")
    line = next(n for n, l in enumerate(text.splitlines(), 1) if "mid2" in l)
    col = text.splitlines()[line - 1].index("z", text.splitlines()[line - 1].index(":=")) + 1
    first = messages(exc)[0]
    assert first.startswith(f"p.fcl:{line}:{col}: error:") and word in first


# ---------------------------------------------------------------------- degenerate shapes
@pytest.mark.parametrize("term", ["TRIAN 5 5 5", "TRAPE 5 5 5 5", "(5, 0) (5, 1) (5, 0)"])
def test_degenerate_triangle_is_a_singleton(term):
    text = sugeno(f"TERM s := {term}; TERM g := 10;",
                  "RULE 1 : IF x IS low THEN y IS s;\n  RULE 2 : IF x IS high THEN y IS g;",
                  method="COGS")
    y, = read_fcl(text, "d.fcl").rulebase.outputs
    assert TermKind(int(y.kinds[0])) == TermKind.SINGLETON and y.params[0, 0] == 5.0
    # x = 2.5: (0.75*5 + 0.25*10) / 1 = 6.25
    assert value(read_fcl(text, "d.fcl"), 2.5, 0.0) == pytest.approx(6.25, abs=1e-12)


def test_degenerate_triangle_on_an_input_is_one_at_its_point():
    # jFuzzyLogic's TRIAN 3 3 3 is 1 where x == 3 exactly, else 0
    text = sugeno("TERM g := 10;", "RULE 1 : IF x IS three THEN y IS g;", "COGS").replace(
        "TERM high := TRIAN 0 10 10;", "TERM high := TRIAN 0 10 10; TERM three := TRIAN 3 3 3;")
    model = read_fcl(text.replace("DEFUZZIFY y", "DEFUZZIFY y\n  DEFAULT := 0;"), "d.fcl")
    assert value(model, 3.0, 0.0) == 10.0 and value(model, 3.001, 0.0) == 0.0


def test_cosine_membership():
    # COSINE net_max 4, offset 5: (1 + cos(pi (x - 5) / 4)) / 2; at x = 6:
    # (1 + cos(pi/4)) / 2 = (1 + 0.7071068) / 2 = 0.8535534 -> COGS of one singleton 10 is 10
    # whatever the degree, so read the degree through a weighted pair: c -> 10, low -> 0
    text = sugeno("TERM g := 10; TERM zero := 0;",
                  "RULE 1 : IF x IS bump THEN y IS g;\n  RULE 2 : IF x IS low THEN y IS zero;",
                  "COGS").replace("TERM high := TRIAN 0 10 10;",
                                  "TERM high := TRIAN 0 10 10; TERM bump := COSINE 4 5;")
    # x = 6: bump 0.8535534, low 0.4: y = 10 * 0.8535534 / (0.8535534 + 0.4)
    bump = (1 + math.cos(math.pi / 4)) / 2
    assert value(read_fcl(text, "c.fcl"), 6.0, 0.0) == pytest.approx(10 * bump / (bump + 0.4))


@pytest.mark.parametrize("term, message", [
    ("DSIGM 2 3 1 7", "DSIGM is read where s1 >= s2 everywhere"),     # unequal gains
    ("DSIGM 2 7 2 3", "DSIGM is read where s1 >= s2 everywhere"),     # s2 ahead of s1
    ("GAUSS2 5 1 3 1", "degenerate GAUSS2 (5 1 3 1)"),     # meanl > meanr: jFuzzyLogic refuses
    ("SINGLETONS (1, 0.5) (2, 1)", "SINGLETONS (jFuzzyLogic's generic singleton"),
])
def test_shapes_refused(term, message):
    text = sugeno("TERM g := 10;", "RULE 1 : IF x IS low THEN y IS g;", "COGS").replace(
        "TERM high := TRIAN 0 10 10;", f"TERM high := TRIAN 0 10 10; TERM odd := {term};")
    with pytest.raises(FuzzycError) as exc:
        read_fcl(text, "s.fcl")
    line = next(n for n, l in enumerate(text.splitlines(), 1) if "odd :=" in l)
    col = text.splitlines()[line - 1].index(term.split()[0]) + 1
    assert messages(exc)[0].startswith(f"s.fcl:{line}:{col}: error: {message}")


# ---------------------------------------------------------------------- jFuzzyLogic's defaults
# A block is read with jFuzzyLogic's defaults where the file uses a construct only its dialect
# has (TRIAN, TRAPE, GAUSS, GBELL, SIGM, COSINE, FUNCTION, COGF, a term naming a variable,
# RANGE after a declaration); an IEC file (point lists) keeps IEC's reading.
def test_accu_default_sum_in_jfuzzylogic_dialect_max_in_iec():
    jfl = mamdani("METHOD : COG;", ACCU_RULES)
    # SUM: v = 0.75 + 0.5 = 1.25 on [4, 6]: (22 + 12.5) / (5 + 2.5) = 34.5 / 7.5 = 4.6
    model = read_fcl(jfl, "j.fcl")
    assert model.rulebase.inference.aggregation == Aggregation.SUM
    assert value(model, 2.5) == pytest.approx(4.6, abs=1e-9)
    assert any("ACCU not given for `y`: SUM, jFuzzyLogic's default" in n for n in model.notes)
    iec = jfl.replace("TRAPE 0 0 6 6", "(0, 1) (6, 1) (6, 0)").replace(
        "TRAPE 4 4 10 10", "(4, 0) (4, 1) (10, 1)").replace("TRIAN 0 5 10", "(0, 0) (5, 1) (10, 0)")
    for word in ("TRIAN 0 0 10", "TRIAN 0 5 10", "TRIAN 0 10 10"):
        iec = iec.replace(word, {"TRIAN 0 0 10": "(0, 1) (10, 0)", "TRIAN 0 5 10":
                                 "(0, 0) (5, 1) (10, 0)", "TRIAN 0 10 10": "(0, 0) (10, 1)"}[word])
    # MAX: v = 0.75: 29.5 / 6.5
    model = read_fcl(iec, "i.fcl")
    assert model.rulebase.inference.aggregation == Aggregation.MAX
    assert value(model, 2.5) == pytest.approx(29.5 / 6.5, abs=1e-9)


OR_RULES = ("RULE 1 : IF x IS low OR x IS mid THEN y IS s1;\n"
            "  RULE 2 : IF x IS high THEN y IS s2;")


@pytest.mark.parametrize("operators, strength", [
    ("AND : PROD;", 0.875),                 # OR is PROD's pair ASUM: 0.75 + 0.5 - 0.375
    ("AND : MIN;", 0.75),                   # OR MAX
    ("AND : PROD; OR : MAX;", 0.75),        # the later line, OR MAX, sets AND MIN too
    ("OR : MAX; AND : PROD;", 0.875),       # the later line, AND PROD, sets OR ASUM
    ("OR : BSUM;", 1.0),                    # min(1, 0.75 + 0.5)
    ("AND : DMIN;", 1.0),                   # OR the drastic sum: neither is 0 -> 1
    ("OR : EINSTEIN;", 1.25 / 1.375),       # (a + b) / (1 + a b) = 1.25 / 1.375
    ("AND : NIPMIN;", 1.0),                 # OR the nilpotent maximum: a + b >= 1 -> 1
])
def test_and_or_set_as_a_pair(operators, strength):
    text = sugeno("TERM s1 := 2; TERM s2 := 8;", f"{operators}\n  {OR_RULES}", "COGS")
    # x = 2.5: low 0.75, mid 0.5 -> rule 1 at OR(0.75, 0.5); high 0.25 -> rule 2.
    # y = (2 s + 0.25*8) / (s + 0.25)
    assert value(read_fcl(text, "p.fcl"), 2.5, 0.0) == pytest.approx(
        (2 * strength + 2) / (strength + 0.25), abs=1e-12)


def test_no_default_is_nan_noted():
    text = mamdani("METHOD : COG; ACCU : MAX;", "RULE 1 : IF x IS mid THEN y IS c;")
    model = read_fcl(text, "n.fcl")
    # jFuzzyLogic gives NaN where no rule fires; the model needs a number and says so
    assert any("`y` default nan" in n for n in model.notes)
    assert value(model, 10.0) == 0.0


# ---------------------------------------------------------------------- fuzzylite as a second oracle
# Where jFuzzyLogic's and IEC's meanings agree and fuzzylite reads the file (point lists, ACCU
# in DEFUZZIFY where fuzzylite takes it, lower-case rule words, one declaration a line), the
# fuzzylite 6 CLI gives the hand-computed numbers of test_accu_variants_centroid.
ORACLE = """FUNCTION_BLOCK m
VAR_INPUT
  x : REAL;
END_VAR
VAR_OUTPUT
  y : REAL;
END_VAR
FUZZIFY x
  TERM low := (0, 1) (10, 0);
  TERM mid := (0, 0) (5, 1) (10, 0);
  RANGE := (0 .. 10);
END_FUZZIFY
DEFUZZIFY y
  TERM p := (0, 1) (6, 1) (6, 0);
  TERM q := (4, 0) (4, 1) (10, 1);
  METHOD : COG;
  ACCU : {accu};
  DEFAULT := 0;
  RANGE := (0 .. 10);
END_DEFUZZIFY
RULEBLOCK r
  AND : MIN;
  OR : MAX;
  ACT : MIN;
  RULE 1 : if x is low then y is p;
  RULE 2 : if x is mid then y is q;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


@pytest.mark.parametrize("accu, v", [("MAX", 0.75), ("BSUM", 1.0), ("NSUM", 1.0),
                                     ("ASUM", 0.875)])
def test_fuzzylite_cli_agrees_on_the_accu_variants(tmp_path, accu, v):
    if shutil.which("fuzzylite") is None:
        pytest.skip("the fuzzylite CLI is not installed (Debian package fuzzylite)")
    text = ORACLE.format(accu=accu)
    (tmp_path / "o.fcl").write_text(text)
    (tmp_path / "in.fld").write_text("2.5\n")
    subprocess.run(["fuzzylite", "-i", str(tmp_path / "o.fcl"), "-of", "fld", "-d",
                    str(tmp_path / "in.fld"), "-o", str(tmp_path / "out.fld"),
                    "-decimals", "9"], check=True, capture_output=True)
    theirs = float((tmp_path / "out.fld").read_text().split("\n")[1].split()[-1])
    hand = (22 + 10 * v) / (5 + 2 * v)         # as in test_accu_variants_centroid
    ours = value(read_fcl(text, "o.fcl"), 2.5)
    # fuzzylite samples the centroid on 100 points; on these rectangles it is exact
    assert ours == pytest.approx(hand, abs=1e-9)
    assert theirs == pytest.approx(hand, abs=1e-6)


# ---------------------------------------------------------------------- rules
def test_rule_names_and_not_without_parentheses():
    # jFuzzyLogic's grammar: `RULE name :` (an ID or a number), `NOT x IS a` without brackets.
    # x = 2.5: low 0.75, so NOT x IS low = 0.25 -> s2 = 8; x IS low -> s1 = 2:
    # (0.75*2 + 0.25*8) / (0.75 + 0.25) = 3.5
    text = sugeno("TERM s1 := 2; TERM s2 := 8;",
                  "RULE first : IF x IS low THEN y IS s1;\n"
                  "  RULE second : IF NOT x IS low AND z IS any THEN y IS s2;", "COGS")
    assert value(read_fcl(text, "n.fcl"), 2.5, 1.0) == pytest.approx(3.5, abs=1e-12)


@pytest.mark.parametrize("term, message", [
    ("FUNCTION " + "(" * 200 + "x" + ")" * 200, "brackets nested deeper than 64"),
    ("FUNCTION " + "x + " * 600 + "x", "longer than 2000 characters"),
    ("FUNCTION ", "it needs an expression"),
    ("FUNCTION (x + 1", "`)` expected"),
])
def test_hostile_functions_are_refused_not_crashed(term, message):
    text = sugeno(f"TERM f := {term};", "RULE 1 : IF x IS low THEN y IS f;")
    with pytest.raises(FuzzycError) as exc:
        read_fcl(text, "h.fcl")
    assert message in messages(exc)[0]


def test_bell_universe_of_a_tiny_slope_is_no_crash():
    # GBELL 1 0.0001 5: 999^(1/0.0002) overflows; the universe falls back to the break points
    text = sugeno("TERM g := 10;", "RULE 1 : IF x IS low THEN y IS g;", "COGS").replace(
        "  RANGE := (0 .. 10);\nEND_FUZZIFY", "END_FUZZIFY").replace(
        "TERM high := TRIAN 0 10 10;", "TERM high := TRIAN 0 10 10; TERM b := GBELL 1 0.0001 5;")
    x = read_fcl(text, "b.fcl").rulebase.inputs[0]
    assert (x.lo, x.hi) == (0.0, 10.0)


def test_rule_weight_scales_the_degree_of_support():
    # jFuzzyLogic's Rule.evaluate: degreeOfSupport *= weight.  x = 2.5: rule 1 0.75*0.5 = 0.375
    # on s1 = 2, rule 2 0.25 on s2 = 8: (0.375*2 + 0.25*8) / (0.375 + 0.25) = 2.75/0.625 = 4.4
    text = sugeno("TERM s1 := 2; TERM s2 := 8;",
                  "RULE 1 : IF x IS low THEN y IS s1 WITH 0.5;\n"
                  "  RULE 2 : IF x IS high THEN y IS s2;", "COGS")
    assert value(read_fcl(text, "w.fcl"), 2.5, 1.0) == pytest.approx(4.4, abs=1e-12)


def test_function_output_without_range_is_refused_where_declared():
    text = sugeno("TERM f := FUNCTION 2 * x;", "RULE 1 : IF x IS low THEN y IS f;").replace(
        "VAR_OUTPUT y : REAL; RANGE := (0 .. 100); END_VAR", "VAR_OUTPUT y : REAL; END_VAR")
    with pytest.raises(FuzzycError) as exc:
        read_fcl(text, "r.fcl")
    line = next(n for n, l in enumerate(text.splitlines(), 1) if l.startswith("VAR_OUTPUT"))
    assert messages(exc) == [f"r.fcl:{line}:12: error: `y` has no RANGE and FUNCTION terms: "
                             "jFuzzyLogic estimates no universe for them and does not clip a "
                             "COGF output; a fuzzyc output saturates to its range: declare a "
                             "RANGE"]


def test_a_jfuzzylogic_file_through_fll_and_fcl_gives_the_same_numbers(tmp_path):
    # COSINE, FUNCTION, a variable singleton, AND PROD (OR its pair ASUM), NOT, a weight:
    # x = 2.5, z = 2: rule 1 0.75 * 1 on f = 2*2.5 + 2^2*3 = 17; rule 2 high 0.25 ASUM
    # bump (1 + cos(-2.5 pi/4))/2 = 0.3086583 -> 0.25 + 0.3086583 - 0.0771646 = 0.4814937 on 10;
    # rule 3 (1 - 0.75) * 0.5 = 0.125 on v = z = 2:
    # y = (12.75 + 4.814937 + 0.25) / (0.75 + 0.4814937 + 0.125) = 17.814937 / 1.3564937
    text = sugeno("TERM f := FUNCTION 2 * x + z ^ 2 * 3; TERM g := 10; TERM v := z;",
                  "AND : PROD;\n  RULE 1 : IF x IS low AND z IS any THEN y IS f;\n"
                  "  RULE 2 : IF x IS high OR x IS bump THEN y IS g;\n"
                  "  RULE r3 : IF NOT x IS low THEN y IS v WITH 0.5;").replace(
        "TERM high := TRIAN 0 10 10;", "TERM high := TRIAN 0 10 10; TERM bump := COSINE 4 5;"
    ).replace("ACCU : SUM;\n", "")
    bump = (1 + math.cos(-2.5 * math.pi / 4)) / 2
    s2 = 0.25 + bump - 0.25 * bump
    hand = (0.75 * 17 + s2 * 10 + 0.125 * 2) / (0.75 + s2 + 0.125)
    model = read_fcl(text, "t.fcl")
    assert value(model, 2.5, 2.0) == pytest.approx(hand, abs=1e-12)
    from fuzzyc.formats import WRITERS, load_any
    for suffix in (".fll", ".fcl"):
        path = tmp_path / f"again{suffix}"
        path.write_text(WRITERS[suffix](model, []))
        assert value(load_any(path), 2.5, 2.0) == pytest.approx(hand, abs=1e-12)


def test_gauss2_membership_and_universe():
    # GAUSS2 meanl 3 sdl 1 meanr 5 sdr 2: at x = 1, exp(-(1-3)^2 / 2) = exp(-2) = 0.1353353;
    # 1 on [3, 5].  Universe 3 - 4*1 = -1 .. 5 + 4*2 = 13.  Through COGS against `low`:
    # x = 1: g2 0.1353353 on 10, low 0.9 on 0 -> 10 * 0.1353353 / (0.1353353 + 0.9)
    text = sugeno("TERM g := 10; TERM zero := 0;",
                  "RULE 1 : IF x IS g2 THEN y IS g;\n  RULE 2 : IF x IS low THEN y IS zero;",
                  "COGS").replace("TERM high := TRIAN 0 10 10;",
                                  "TERM high := TRIAN 0 10 10; TERM g2 := GAUSS2 3 1 5 2;")
    g2 = math.exp(-2)
    assert value(read_fcl(text, "g.fcl"), 1.0, 0.0) == pytest.approx(10 * g2 / (g2 + 0.9))
    assert value(read_fcl(text, "g.fcl"), 4.0, 0.0) == pytest.approx(10 * 1 / (1 + 0.6))
    lone = text.replace("  RANGE := (0 .. 10);\nEND_FUZZIFY", "END_FUZZIFY", 1)
    x = read_fcl(lone, "g.fcl").rulebase.inputs[0]
    assert (x.lo, x.hi) == (-1.0, 13.0)


def test_dsigm_a_bump_of_equal_gains():
    # DSIGM 2 3 2 7: s1 = 1/(1+exp(-2(x-3))), s2 = 1/(1+exp(-2(x-7))), s1 >= s2 everywhere.
    # At x = 5: s1 = 1/(1+e^-4) = 0.9820138, s2 = 1/(1+e^4) = 0.0179862: 0.9640276
    text = sugeno("TERM g := 10; TERM zero := 0;",
                  "RULE 1 : IF x IS d THEN y IS g;\n  RULE 2 : IF x IS low THEN y IS zero;",
                  "COGS").replace("TERM high := TRIAN 0 10 10;",
                                  "TERM high := TRIAN 0 10 10; TERM d := DSIGM 2 3 2 7;")
    d = 1 / (1 + math.exp(-4)) - 1 / (1 + math.exp(4))
    # low at 5 is 0.5: y = 10 d / (d + 0.5)
    assert value(read_fcl(text, "d.fcl"), 5.0, 0.0) == pytest.approx(10 * d / (d + 0.5))
