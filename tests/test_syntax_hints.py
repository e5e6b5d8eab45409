"""The parser's fixes for a newcomer's first mistakes (issue 30; fuzzyc/language/syntax_hints.py):
another format's shape names lead to ours through the shape registry, upper-case keywords are
refused with the lower-case word, and an unfinished statement is reported on its own line."""
from __future__ import annotations

import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import parse
from fuzzyc.language.syntax_hints import shape_suggestion
from fuzzyc.semantics.shapes import SHAPES

RULES = """\
controller demo {
  input a in [0, 10]
  var u in [0, 1]
  terms a : lo = SHAPE, hi = tri(5, 10, 10)
  terms u : singletons z=0 o=1
  rule if a is lo then u is z
}
"""


def messages(text: str) -> list[tuple[int, int, str]]:
    with pytest.raises(FuzzycError) as info:
        parse(text, "r.fz")
    return [(d.loc.line, d.loc.col, d.message) for d in info.value.diagnostics]


def test_every_format_name_in_the_registry_leads_to_a_word_of_its_own_shape():
    checked = 0
    for shape in SHAPES.values():
        for name in (shape.fll, shape.fcl, shape.fis):
            if name is None or not shape.words:
                continue
            words = {w.word for w in shape.words}
            suggestion = shape_suggestion(name)
            assert suggestion is not None, name
            named = {w for w in words if f"`{w}`" in suggestion}
            assert named, (name, suggestion)
            checked += 1
    assert checked == 39        # 21 shapes with a word, most in two or three formats


@pytest.mark.parametrize("foreign,ours", [
    ("trimf", "did you mean `tri`?"), ("Triangle", "did you mean `tri`?"),
    ("TRIAN", "did you mean `tri`?"), ("trapmf", "did you mean `trap`?"),
    ("Rectangle", "did you mean `trap`?"), ("Ramp", "did you mean `lshoulder` or `rshoulder`?"),
    ("dsigmf", "did you mean `sigmoid_difference`?"), ("Constant", "did you mean `singleton`?"),
    ("TRI", "did you mean `tri`?"), ("gausian", "did you mean `gauss`?"),
])
def test_foreign_and_misspelled_shape_names(foreign, ours):
    assert shape_suggestion(foreign).startswith(ours)


def test_matlab_order_of_numbers_is_pointed_out():
    # gaussmf [sigma c] is gauss(c, sigma): the order differs, the message says so
    assert "not MATLAB's" in shape_suggestion("gaussmf")
    assert "MATLAB" not in shape_suggestion("trimf")     # trimf [a b c] is tri(a, b, c)


def test_no_suggestion_for_a_word_like_no_shape():
    assert shape_suggestion("xyzzy") is None
    # "  terms a : lo = xyzzy(1)": `xyzzy` at 18; the plain message lists the shapes
    ((line, col, message),) = messages(RULES.replace("SHAPE", "xyzzy(1)"))
    assert (line, col) == (4, 18)
    assert message.startswith("unexpected `xyzzy`; expected a term shape (arc, bell, ")


def test_matlab_shape_name_in_a_file_is_one_error_with_the_fix():
    # "  terms a : lo = trimf(0, 0, 5)": `trimf` at 18; nothing else is reported (the rule on
    # `lo` neither: the statement is skipped, its terms unknown, but `a` has no terms at all)
    found = messages(RULES.replace("SHAPE", "trimf(0, 0, 5)"))
    assert found[0] == (4, 18, "unknown term shape `trimf`: did you mean `tri`?")
    assert all("`}`" not in m for _, _, m in found)


@pytest.mark.parametrize("line,col,word", [
    # "  rule IF a is lo then u is z": `IF` at 8 (read as the rule's name; `a` is the error)
    ("  rule IF a is lo then u is z", 8, "if"),
    # "  rule if a IS lo then u is z": `IS` at 13
    ("  rule if a IS lo then u is z", 13, "is"),
    # "  rule if a is lo then u is z WITH 0.5": `WITH` at 31
    ("  rule if a is lo then u is z WITH 0.5", 31, "with"),
    # "  Rule if a is lo then u is z": `Rule` at 3, where a statement starts
    ("  Rule if a is lo then u is z", 3, "rule"),
])
def test_upper_case_keywords_are_refused_with_the_lower_case_word(line, col, word):
    text = RULES.replace("SHAPE", "tri(0, 0, 5)").replace("  rule if a is lo then u is z", line)
    found = messages(text)
    assert len(found) == 1, found
    assert found[0][:2] == (6, col)
    assert f"keywords are lower case: write `{word}`" in found[0][2]


def test_a_name_in_upper_case_that_is_no_keyword_there_is_a_name():
    # `IF` as a rule's name is legal: `rule IF: if ...`
    text = RULES.replace("SHAPE", "tri(0, 0, 5)").replace("  rule if", "  rule IF: if")
    assert parse(text).rulebase.n_rules == 1


def test_an_input_without_terms_in_a_rule_says_how_to_declare_them():
    text = RULES.replace("  terms a : lo = SHAPE, hi = tri(5, 10, 10)\n", "")
    # "  rule if a is lo then u is z": `a` at 11 on line 5
    assert messages(text) == [(5, 11, "input `a` has no terms; declare them with `terms a : ...` "
                                      "(`terms a : uniform N Z P`, or `N = tri(a, b, c), ...`)")]


def test_a_var_without_range_is_reported_on_its_line():
    text = RULES.replace("SHAPE", "tri(0, 0, 5)").replace("var u in [0, 1]", "var u")
    # "  var u": `u` at 7, reported right after it (8), not at `terms` on line 4
    assert messages(text) == [(3, 8, "`var u` is unfinished: expected one of `:`, `in` after "
                                     "`u`; write `var u in [low, high]`")]


def test_a_broken_term_is_not_reported_again_where_a_rule_uses_it():
    # "  terms a : lo = tri(5, 0, 10)": 5 > 0 breaks a <= b, reported at the first number (22);
    # the rule on `lo` says nothing more
    found = messages(RULES.replace("SHAPE", "tri(5, 0, 10)"))
    assert [(line, col) for line, col, _ in found] == [(4, 22)]


def test_a_range_is_suggested_only_where_one_is_missing():
    # `terms a` lacks its `:` and terms, not a range (its range is optional): no range hint;
    # "  terms a": `a` at 9, reported after it
    text = RULES.replace("  terms a : lo = SHAPE, hi = tri(5, 10, 10)", "  terms a")
    found = messages(text)
    assert found[0] == (4, 10, "`terms a` is unfinished: expected one of `,`, `:`, `default`, "
                               "`in` after `a`")
    # `input a : kHz` has its unit: the range goes after it
    text = RULES.replace("SHAPE", "tri(0, 0, 5)").replace("input a in [0, 10]", "input a : kHz")
    # "  input a : kHz": `kHz` 13-15, reported after it
    assert messages(text)[0] == (2, 16, "`input a : kHz` is unfinished: expected `in` after "
                                        "`kHz`; write `input a : kHz in [low, high]`")
