"""Keywords of the .fz language are whole words: `notch` is a name (not `not ch`), `veryhot` a
name (not `very hot`).  A name spelled like a keyword is written in backticks (`rule`); a bare
keyword where a name stands is a located error.  The .fz writer quotes such names, so a model
imported from FLL with names like `rule`, `if`, `notch` converts to a .fz file that reads back
and evaluates to the same numbers."""
from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fuzzyc.cli import main
from fuzzyc.engine.inference import activations, evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fis, read_fll, write_fz
from fuzzyc.language.parser import keywords, parse

SINGLETON_AVERAGE = ("inference and = min, or = max, implication = min, aggregation = max, "
                     "defuzzify = weighted_average")


def test_notch_is_a_name_not_not_ch():
    model = parse(f"""controller c {{
      input notch in [0, 10]
      terms notch : A = tri(0, 5, 10), B = tri(5, 10, 15)
      var y in [0, 10] default 0
      terms y : singletons lo=0 hi=10
      {SINGLETON_AVERAGE}
      rule if notch is A then y is hi
      rule if notch is not A then y is lo
      output y_out in [0, 10] = y
    }}""", "notch.fz")
    rb = model.rulebase
    assert [v.name for v in rb.inputs] == ["notch"]
    # notch = 2.5: A = 2.5/5 = 0.5, not A = 0.5 -> y = (0.5*10 + 0.5*0) / (0.5 + 0.5) = 5
    # notch = 1:   A = 0.2,         not A = 0.8 -> y = (0.2*10 + 0.8*0) / 1         = 2
    np.testing.assert_allclose(evaluate(rb, [[2.5], [1.0]]).ravel(), [5.0, 2.0], rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(activations(rb, [[1.0]]), [[0.2, 0.8]], rtol=0, atol=1e-12)


def test_veryhot_is_a_term_and_very_hot_is_still_the_hedge():
    rb = parse(f"""controller c {{
      input temp in [0, 150]
      terms temp : hot = tri(0, 50, 100), veryhot = tri(50, 100, 150)
      var y in [0, 10] default 0
      terms y : singletons lo=0 hi=10
      {SINGLETON_AVERAGE}
      rule if temp is veryhot then y is hi
      rule if temp is very hot then y is lo
      output y_out in [0, 10] = y
    }}""", "hot.fz").rulebase
    assert rb.inputs[0].names == ["hot", "veryhot"]
    # temp = 100: veryhot = 1 (its peak), hot = 0, very hot = 0^2 = 0
    # temp = 75:  veryhot = 0.5, hot = 0.5, very hot = 0.5^2 = 0.25
    np.testing.assert_allclose(activations(rb, [[100.0], [75.0]]), [[1.0, 0.0], [0.5, 0.25]],
                               rtol=0, atol=1e-12)
    # temp = 75: y = (0.5*10 + 0.25*0) / (0.5 + 0.25) = 5 / 0.75 = 6.666...
    np.testing.assert_allclose(evaluate(rb, [[75.0]]).ravel(), [20 / 3], rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["notch", "veryhot", "island", "order", "android", "within_",
                                  "iffy", "ruleset", "xnot", "thenx", "withs", "tri2",
                                  "learnables", "nanx"])
def test_keywords_with_letters_glued_on_are_names(name):
    rb = parse(f"""controller c {{
      input {name} in [0, 1]
      terms {name} : {name} = tri(0, 0.5, 1)
      var y in [0, 1] default 0
      terms y : singletons {name}=1
      rule if {name} is {name} then y is {name}
      output y_out in [0, 1] = y
    }}""", "glued.fz").rulebase
    assert (rb.inputs[0].name, rb.inputs[0].names, rb.outputs[0].names) == (name, [name], [name])
    # one rule, one singleton at 1: y = 1 wherever the rule fires (0.25 -> mu = 0.5)
    assert evaluate(rb, [[0.25]]).ravel().tolist() == [1.0]


def test_a_name_in_backticks_may_be_a_keyword():
    rb = parse("""controller `rule` {
      input `not` in [0, 10]
      terms `not` : `very` = tri(0, 5, 10), `is` = tri(5, 10, 15)
      var `then` in [0, 10] default 0
      terms `then` : singletons `if`=0 `with`=10
      rule if `not` is not very `very` then `then` is `with`
      rule if `not` is `is` then `then` is `if`
      output `then_out` in [0, 10] = `then`
    }""", "quoted.fz").rulebase
    assert [v.name for v in rb.inputs + rb.outputs] == ["not", "then"]
    assert rb.inputs[0].names == ["very", "is"]
    # x = 7.5: very = 0.5, very very = 0.25, not very very = 0.75; is = 0.5
    np.testing.assert_allclose(activations(rb, [[7.5]]), [[0.75, 0.5]], rtol=0, atol=1e-12)


@pytest.mark.parametrize("text, line, col, word", [
    ("  input rule in [0, 1]\n", 2, 9, "rule"),
    ("  input x in [0, 1]\n  terms x : very = tri(0, 0.5, 1)\n", 3, 13, "very"),
    ("  input x in [0, 1]\n  terms x : A = tri(0, 0.5, 1)\n  var in in [0, 1]\n", 4, 7, "in"),
])
def test_check_says_where_a_keyword_stands_as_a_name(tmp_path, capsys, text, line, col, word):
    bad = tmp_path / "bad.fz"
    bad.write_text("controller c {\n" + text + "}\n")
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:{line}:{col}: error: `{word}` is a keyword, not a name" in err
    assert "backticks" in err and "Traceback" not in err


def test_keyword_glued_to_a_name_is_not_split():
    """`x isA` was `x is A`: now `isA` is one name, and the rule is a located error."""
    with pytest.raises(FuzzycError) as info:
        parse("controller c {\n  input x in [0, 1]\n  terms x : A = tri(0, 0.5, 1)\n"
              "  var y in [0, 1]\n  terms y : singletons a=0\n  rule if x isA then y is a\n}\n",
              "glued.fz")
    assert str(info.value).startswith("glued.fz:6:13: error: unexpected `isA`; expected `is`")


def test_the_keyword_list_is_the_grammars():
    words = keywords()
    assert {"not", "very", "somewhat", "is", "and", "or", "if", "then", "with", "when", "in",
            "over", "rule", "terms", "input", "tri", "learnable", "rows", "nan",
            "increasing", "within", "closed_loop", "controller"} <= words
    assert not words & {"notch", "any", "min", "max", "centroid", "x"}


# ---- FLL models with hostile names, converted to .fz and read back

FZ_KEYWORDS = sorted(keywords())
FLL_WORDS = ["Engine", "InputVariable", "OutputVariable", "RuleBlock", "term", "range",
             "enabled", "lock", "any", "none", "Triangle", "Ramp", "Minimum", "Maximum",
             "Centroid", "General", "conjunction", "activation", "description", "default"]
FCL_WORDS = ["FUNCTION_BLOCK", "END_FUNCTION_BLOCK", "VAR_INPUT", "END_VAR", "FUZZIFY",
             "TERM", "RULEBLOCK", "RULE", "IF", "THEN", "IS", "AND", "OR", "NOT", "WITH",
             "DEFUZZIFY", "METHOD", "COG", "ACCU", "MAX", "MIN", "ACT", "RANGE"]
C_WORDS = ["int", "return", "for", "while", "static", "const", "struct", "void", "double",
           "float", "if", "else", "switch", "case", "goto", "sizeof", "main", "NULL"]
GLUED = ["notch", "xnot", "veryhot", "ruleset", "island", "order", "android", "within_x",
         "iffy", "inx", "isA", "thenx", "x_with", "tri_", "nanny", "anyx"]
names = st.one_of(
    st.sampled_from(FZ_KEYWORDS),
    st.builds(lambda w, pre, post: pre + w + post, st.sampled_from(FZ_KEYWORDS),
              st.sampled_from(["", "x", "_", "A"]), st.sampled_from(["", "x", "1", "_", "s"])),
    st.sampled_from(GLUED + FLL_WORDS + FCL_WORDS + C_WORDS),
    st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,7}", fullmatch=True))
LOCATED = re.compile(r"^hostile\.fll:\d+:\d+: error: ", re.M)
POINTS = np.array([[1.0, 2.0], [2.5, 7.5], [6.0, 4.0], [9.0, 9.5], [5.0, 0.5]])


def hostile_fll(x1, x2, y, a1, a2, b1, b2, c1, c2) -> str:
    def var(kind, name, terms, extra=""):
        return (f"{kind}: {name}\n  enabled: true\n  range: 0.000 10.000\n{extra}"
                + "".join(f"  term: {t} Triangle {lo} {lo + 5} {lo + 10}\n" for t, lo in terms))
    out = "  aggregation: Maximum\n  defuzzifier: Centroid 200\n  default: 0\n"
    return ("Engine: hostile\n" + var("InputVariable", x1, [(a1, -5), (a2, 5)])
            + var("InputVariable", x2, [(b1, -5), (b2, 5)])
            + var("OutputVariable", y, [(c1, -5), (c2, 5)], out)
            + "RuleBlock: rules\n  enabled: true\n  conjunction: Minimum\n"
            "  disjunction: Maximum\n  implication: Minimum\n  activation: General\n"
            f"  rule: if {x1} is {a1} and {x2} is not {b1} then {y} is {c1}\n"
            f"  rule: if {x1} is very {a2} or {x2} is {b2} then {y} is {c2}\n"
            f"  rule: if {x1} is somewhat {a1} then {y} is {c2} with 0.5\n")


def fll_to_fz(fll: str):
    """(imported model, model read back from its .fz), or None when the FLL import refuses
    the names (a located message, checked here)."""
    try:
        imported = read_fll(fll, "hostile.fll")
    except FuzzycError as refused:
        assert LOCATED.match(str(refused)), str(refused)
        return None
    text = write_fz(imported)     # identifier names are always sayable in .fz (quoted)
    return imported, parse(text, "hostile.fz")


@settings(max_examples=100, deadline=None)
@given(st.lists(names, min_size=9, max_size=9, unique=True))
def test_fll_names_convert_to_fz_that_reads_back_the_same(drawn):
    converted = fll_to_fz(hostile_fll(*drawn))
    if converted is None:
        return
    imported, back = converted
    a, b = imported.rulebase, back.rulebase
    assert [v.name for v in a.inputs + a.outputs] == [v.name for v in b.inputs + b.outputs]
    assert [v.names for v in a.inputs + a.outputs] == [v.names for v in b.inputs + b.outputs]
    np.testing.assert_array_equal(a.antecedents, b.antecedents)
    np.testing.assert_array_equal(a.hedges, b.hedges)
    np.testing.assert_array_equal(a.negated, b.negated)
    np.testing.assert_allclose(evaluate(a, POINTS), evaluate(b, POINTS), rtol=0, atol=1e-12)


def test_fll_keyword_names_are_quoted_in_the_fz_and_evaluate_as_imported():
    """Not vacuous: a model named with .fz keywords does convert, quoted, to the same numbers."""
    imported, back = fll_to_fz(hostile_fll("rule", "notch", "then", "if", "veryhot", "is",
                                           "with", "in", "terms"))
    text = write_fz(imported)
    assert "input `rule` in [0, 10]" in text and "input notch in [0, 10]" in text
    assert ("rule if `rule` is `if` and notch is not `is` then `then` is `in`" in text)
    # x = (2.5, 7.5): if = tri(-5, 0, 5) -> 0.5, veryhot = tri(0, 5, 10) -> 0.5,
    # is = tri(-5, 0, 5) -> 0, with = tri(0, 5, 10) -> 0.5:
    # rule 1 min(0.5, 1 - 0) = 0.5, rule 2 max(0.5^2, 0.5) = 0.5, rule 3 sqrt(0.5) * 0.5
    np.testing.assert_allclose(activations(back.rulebase, [[2.5, 7.5]]),
                               [[0.5, 0.5, 0.5 ** 0.5 * 0.5]], rtol=0, atol=1e-12)
    np.testing.assert_allclose(evaluate(back.rulebase, POINTS),
                               evaluate(imported.rulebase, POINTS), rtol=0, atol=1e-12)


# ---- any name a FIS file holds (`Food-Quality`, `a b`, `x*/`) is written in backticks

def fis_named(x: str, y: str, t1: str, t2: str) -> str:
    """One input x with terms t1 = trimf [0 0 10], t2 = trimf [0 10 10]; a Sugeno output y
    with constants t1 = 2 and t2 = 8; rules t1 -> t1, t2 -> t2."""
    return (f"[System]\nName='n'\nType='sugeno'\nNumInputs=1\nNumOutputs=1\nNumRules=2\n"
            "AndMethod='min'\nOrMethod='max'\nImpMethod='prod'\nAggMethod='sum'\n"
            f"DefuzzMethod='wtaver'\n\n[Input1]\nName='{x}'\nRange=[0 10]\nNumMFs=2\n"
            f"MF1='{t1}':'trimf',[0 0 10]\nMF2='{t2}':'trimf',[0 10 10]\n\n[Output1]\n"
            f"Name='{y}'\nRange=[0 10]\nNumMFs=2\nMF1='{t1}':'constant',[2]\n"
            f"MF2='{t2}':'constant',[8]\n\n[Rules]\n1, 1 (1) : 1\n2, 2 (1) : 1\n")


FIS_NAMES = st.text(st.characters(blacklist_characters="'", blacklist_categories=("Cs",)),
                    min_size=1, max_size=6)
UNQUOTABLE = re.compile(r"[`.\x00-\x1f\x7f\x85\u2028\u2029]")


@settings(max_examples=150, deadline=None)
@given(st.lists(FIS_NAMES, min_size=2, max_size=2, unique=True),
       st.lists(FIS_NAMES, min_size=2, max_size=2, unique=True))
def test_any_fis_name_converts_to_fz_in_backticks_or_is_refused_by_name(variables, terms):
    try:
        imported = read_fis(fis_named(*variables, *terms), "named.fis")
    except FuzzycError as refused:
        assert re.match(r"^named\.fis:\d+:\d+: error: ", str(refused)), str(refused)
        return
    names = [v.name for v in imported.rulebase.inputs + imported.rulebase.outputs] + \
        list(imported.rulebase.inputs[0].names)
    # what .fz cannot hold: an empty name, a backtick, a dot, a control character, a leading
    # `__` (fuzzyc's), and an output `_`, whose controller output would be `__out`
    unsayable = [n for n in names if not n or UNQUOTABLE.search(n) or n.startswith("__")]
    try:
        text = write_fz(imported)
    except FuzzycError as refused:
        assert unsayable or names[1] == "_", str(refused)
        assert f"the name {unsayable[0]!r} cannot be written in .fz" in str(refused) \
            if unsayable else "the controller output `__out`" in str(refused)
        return
    assert not unsayable and names[1] != "_", text
    back = parse(text, "named.fz").rulebase
    assert [v.name for v in back.inputs + back.outputs] == names[:2]
    assert list(back.inputs[0].names) == names[2:]
    # x = 2.5: t1 = 0.75, t2 = 0.25: y = (0.75*2 + 0.25*8) / 1 = 3.5
    assert evaluate(back, [[2.5]])[0, 0] == pytest.approx(3.5, abs=1e-12)


def test_octave_style_names_convert_to_fz_in_backticks():
    """Not vacuous: the Octave toolkit's `Food-Quality` and names with spaces and C comment
    marks come back as they were."""
    imported = read_fis(fis_named("Food-Quality", "Tip */ int", "a b", "x;y"), "named.fis")
    text = write_fz(imported)
    assert "input `Food-Quality` in [0, 10]" in text
    assert "terms `Food-Quality` : `a b` = tri(0, 0, 10), `x;y` = tri(0, 10, 10)" in text
    back = parse(text, "named.fz").rulebase
    assert [v.name for v in back.inputs + back.outputs] == ["Food-Quality", "Tip */ int"]
    assert evaluate(back, [[2.5]])[0, 0] == pytest.approx(3.5, abs=1e-12)
    with pytest.raises(FuzzycError, match=r"the name 'a\.b' cannot be written in \.fz \(a "
                                          "name there is in backticks any character but a "
                                          "backtick, a dot or a control character"):
        write_fz(read_fis(fis_named("x", "y", "a.b", "c"), "named.fis"))


def test_names_fuzzyc_reserves_are_refused_by_the_fz_writer():
    # `__x` starts like the names fuzzyc generates; an output `_` would give the controller
    # output `__out`: both refused by name instead of a .fz file that does not read back
    with pytest.raises(FuzzycError, match=r"the name '__x' cannot be written in \.fz"):
        write_fz(read_fis(fis_named("__x", "y", "a", "b"), "named.fis"))
    with pytest.raises(FuzzycError, match="the controller output `__out` made from `_` starts "
                                          "with __"):
        write_fz(read_fis(fis_named("x", "_", "a", "b"), "named.fis"))
