"""Several syntax errors per .fz file through lark's error recovery (fuzzyc/language/recovery.py):
each independent mistake at its own line:col (columns counted by hand in the comments), no
follow-on errors after a skipped statement, at most MAX_SYNTAX_ERRORS of them, and hostile text
ends with located errors, never a traceback."""
from __future__ import annotations

import random
import re

import pytest
from hypothesis import given, settings, HealthCheck
from hypothesis import strategies as st
from lark.lexer import PatternStr

from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import MAX_SYNTAX_ERRORS, _lark, parse, shape_words
from fuzzyc.language.recovery import statement_starts

VALID = """\
controller demo {
  input e in [-1, 1]
  input ce in [-1, 1]
  terms e : N = tri(-2, -1, 0), Z = tri(-1, 0, 1), P = tri(0, 1, 2)
  terms ce : uniform N Z P
  var du in [-1, 1] default 0
  terms du : singletons N=-1 Z=0 P=1
  rule if e is N then du is N
  rule if e is P then du is P
  output u in [-1, 1] = du
}
"""


def replace(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


def errors(text: str) -> list[tuple[int, int, str]]:
    with pytest.raises(FuzzycError) as info:
        parse(text, "r.fz")
    return [(d.loc.line, d.loc.col, d.message) for d in info.value.diagnostics]


# line 2 "  input e in [-1 1]": `[` is column 14, `-1` 15-16, the `1` after the space 18
BAD_INPUT = ("  input e in [-1, 1]\n", "  input e in [-1 1]\n")
E_INPUT = (2, 18, "unexpected `1`; expected `,`")
# line 8 "  rule if e is N du is N": `rule` 3-6, `if` 8-9, `e` 11, `is` 13-14, `N` 16, `du` 18
BAD_RULE = ("is N then du is N", "is N du is N")
E_RULE = (8, 18, "unexpected `du`; expected one of `and`, `or`, `then`")
# line 10 "  output u in [-1, 1] du": `output` 3-8, `u` 10, `in` 12-13, `[-1, 1]` 15-21, `du` 23
BAD_OUTPUT = ("[-1, 1] = du\n", "[-1, 1] du\n")
E_OUTPUT = (10, 23, "unexpected `du`; expected `=`")


def test_the_valid_file_parses():
    assert parse(VALID).rulebase.n_rules == 2


def test_two_errors_in_different_statements():
    text = replace(replace(VALID, *BAD_INPUT), *BAD_RULE)
    assert errors(text) == [E_INPUT, E_RULE]


def test_three_errors_in_different_statements():
    text = replace(replace(replace(VALID, *BAD_INPUT), *BAD_RULE), *BAD_OUTPUT)
    assert errors(text) == [E_INPUT, E_RULE, E_OUTPUT]


def test_two_statements_on_one_line_are_checked_apart():
    # "  input a in [0 1]  input b in [0 1]": the first `1` at 17, `input b` at 21, its `1` 35
    text = replace(VALID, "  input ce in [-1, 1]\n",
                   "  input ce in [-1, 1]\n  input a in [0 1]  input b in [0 1]\n")
    assert [(line, col) for line, col, _ in errors(text)] == [(4, 17), (4, 35)]


def _inputs_file(broken: int) -> str:
    # "  input v00 in [0 1]": `input` 3-7, `v00` 9-11, `in` 13-14, `[` 16, `0` 17, `1` 19
    lines = [f"  input v{k:02d} in [0 1]" for k in range(broken)]
    return "controller many {\n" + "\n".join(lines) + "\n}\n"


def test_the_maximum_number_of_errors_is_reported_each_at_its_place():
    found = errors(_inputs_file(MAX_SYNTAX_ERRORS))
    assert found == [(2 + k, 19, "unexpected `1`; expected `,`")
                     for k in range(MAX_SYNTAX_ERRORS)]


def test_past_the_maximum_the_last_error_says_more_follow():
    found = errors(_inputs_file(MAX_SYNTAX_ERRORS + 5))
    assert len(found) == MAX_SYNTAX_ERRORS
    assert [(line, col) for line, col, _ in found] == [(2 + k, 19)
                                                       for k in range(MAX_SYNTAX_ERRORS)]
    assert found[-2][2] == "unexpected `1`; expected `,`"
    assert found[-1][2].startswith("unexpected `1`; expected `,`; more syntax errors follow")
    assert f"the first {MAX_SYNTAX_ERRORS}" in found[-1][2]


def test_an_error_inside_a_block_then_valid_statements_and_no_brace_error():
    rules = "  rule if e is N then du is N\n  rule if e is P then du is P\n"
    # line 9 "    rule if e is N then du = N": `du` 25-26, `=` 28
    block = "  block b {\n    rule if e is N then du = N\n    rule if e is P then du is P\n  }\n"
    text = replace(VALID, rules, block)
    assert errors(text) == [(9, 28, "unexpected `=`; expected `is`")]
    # the block closed where it should: an error after it is still found, alone
    text = replace(text, *BAD_OUTPUT)
    assert errors(text) == [(9, 28, "unexpected `=`; expected `is`"),
                            (12, 23, "unexpected `du`; expected `=`")]


def test_an_error_in_a_table_body_then_valid_statements():
    table = ("  table du (rows e: N Z P; cols ce: N Z P) {\n"
             "    N N Z\n"
             "    N , P\n"        # line 10: `N` 5, `,` 7
             "    Z P P\n"
             "  }\n")
    text = replace(VALID, "  rule if e is N then du is N\n  rule if e is P then du is P\n",
                   table)
    assert errors(text) == [(10, 7, "unexpected `,`; expected one of `-`, `}`, a name, "
                                    "a number")]
    text = replace(text, "[-1, 1] = du\n", "[-1, 1] du\n")
    # the output moved to line 13: "  output u in [-1, 1] du", `du` at 23
    assert [(line, col) for line, col, _ in errors(text)] == [(10, 7), (13, 23)]


def test_a_stray_closing_brace_in_a_table_ends_only_the_table():
    # line 10 "    N } Z P": the `}` at 7 ends the table early (the table is valid so far), the
    # `Z` at 9 is the error; the table's own `}` of line 12 is skipped, not taken as the
    # controller's, so the output of line 13 is no error
    table = ("  table du (rows e: N Z P; cols ce: N Z P) {\n"
             "    N N Z\n"
             "    N } Z P\n"
             "    Z P P\n"
             "  }\n")
    text = replace(VALID, "  rule if e is N then du is N\n  rule if e is P then du is P\n",
                   table)
    ((line, col, message),) = errors(text)
    assert (line, col) == (10, 9)
    assert message.startswith("unexpected `Z`; expected one of `block`, `fuzzylite`, "
                              "`inference`, `input`")


def test_a_table_whose_body_cannot_end_yet_is_dropped_whole():
    # line 8 "  table (e, ce -> du) { 1: N -> }": `{` 23, `1` 25, `:` 26, `N` 28, `->` 30-31,
    # `}` 33: a list table takes one row at least, so the `}` drops the table
    text = replace(VALID, "  rule if e is N then du is N\n",
                   "  table (e, ce -> du) { 1: N -> }\n")
    text = replace(text, *BAD_OUTPUT)
    assert errors(text) == [(8, 33, "unexpected `}`; expected a name"), E_OUTPUT]


def test_an_error_in_the_last_statement():
    # line 10 "  output u in [-1, 1] =" ends unfinished (the `=` at 23): reported right after
    # it on its own line, not at the `}` of line 11 (issue 30)
    text = replace(VALID, "[-1, 1] = du\n", "[-1, 1] =\n")
    assert errors(text) == [(10, 24, "`output u in [-1, 1] =` is unfinished: expected one of "
                                     "`(`, `-`, a name, a number after `=`")]
    text = replace(replace(VALID, *BAD_INPUT), "[-1, 1] = du\n", "[-1, 1] =\n")
    assert [(line, col) for line, col, _ in errors(text)] == [(2, 18), (10, 24)]


def test_an_error_in_the_last_statement_of_an_unclosed_file():
    text = replace(replace(VALID, *BAD_INPUT), "= du\n}\n", "= du +\n")
    # line 10 "  output u in [-1, 1] = du +": the `+` at 28, the file ends after it
    assert errors(text) == [E_INPUT, (10, 29, "`output u in [-1, 1] = du +` is unfinished: "
                                              "expected one of `(`, `-`, a name, a number "
                                              "after `+`; the file ends there")]


def test_a_stray_closing_brace_in_a_statement_does_not_close_the_controller():
    # line 2 "  input e in [-1} 1]": `}` at 17; it cannot end the file here, so it is skipped
    text = replace(replace(VALID, "  input e in [-1, 1]\n", "  input e in [-1} 1]\n"),
                   *BAD_OUTPUT)
    assert errors(text) == [(2, 17, "unexpected `}`; expected `,`"), E_OUTPUT]


def test_a_stray_opening_brace_opens_no_block():
    # line 2 "  input e in [-1, { 1]": `[` 14, `-1` 15-16, `,` 17, `{` 19; the `}` of the
    # controller still closes it
    text = replace(replace(VALID, "  input e in [-1, 1]\n", "  input e in [-1, { 1]\n"),
                   *BAD_OUTPUT)
    assert errors(text) == [(2, 19, "unexpected `{`; expected a number"), E_OUTPUT]


def test_a_keyword_inside_a_broken_statement_is_no_restart():
    # line 8 "  rule if e is is N then du is input": the second `is` at 16; `input` at 33
    # is followed by nothing a statement takes: no second error about it
    text = replace(VALID, "  rule if e is N then du is N\n",
                   "  rule if e is is N then du is input\n")
    assert errors(text) == [(8, 16, "`is` is a keyword, not a name; a name spelled like a "
                                    "keyword is written in backticks (`is` with the backticks "
                                    "typed)")]


def test_a_keyword_where_the_broken_statement_stands_is_no_restart():
    # line 8 "  rule if e rule N then du is N": `e` 11, `rule` 13; `rule N` would fit, then
    # `then` would not: no second error
    text = replace(VALID, "  rule if e is N then", "  rule if e rule N then")
    assert errors(text) == [(8, 13, "unexpected `rule`; expected `is`")]


def test_a_statement_on_the_next_line_is_checked_even_when_it_starts_wrong():
    # line 3 "  input 3 in [-1, 1]": `3` at 9, right after the broken line 2
    text = replace(replace(VALID, *BAD_INPUT), "  input ce in", "  input 3 in")
    assert errors(text) == [E_INPUT, (3, 9, "unexpected `3`; expected a name")]


def test_a_statement_the_block_cannot_hold_does_not_leave_the_block():
    # line 10 `input` is no block statement: skipped with the broken rule of line 9, so the
    # block's `}` still closes the block and the output after it is read as a statement
    block = ("  block b {\n    rule if e is N then du = N\n    input z in [0, 1]\n"
             "    rule if e is P then du is P\n  }\n")
    text = replace(VALID, "  rule if e is N then du is N\n  rule if e is P then du is P\n", block)
    assert errors(text) == [(9, 28, "unexpected `=`; expected `is`")]


def test_a_block_with_a_broken_header_is_skipped_whole():
    # line 8 "  block 3 {": `3` at 9; its rules and its `}` are skipped, the output's error
    # (line 12 now) is found
    block = "  block 3 {\n    rule if e is N then du is N\n    rule if e is P then du is P\n  }\n"
    text = replace(VALID, "  rule if e is N then du is N\n  rule if e is P then du is P\n", block)
    text = replace(text, *BAD_OUTPUT)
    assert errors(text) == [(8, 9, "unexpected `3`; expected a name"),
                            (12, 23, "unexpected `du`; expected `=`")]


def test_a_statement_after_an_unfinished_one_is_its_own():
    # line 2 "  input e in": the range is missing; reported after `in` (11-12) on line 2
    text = replace(VALID, "  input e in [-1, 1]\n", "  input e in\n")
    text = replace(text, "  input ce in [-1, 1]\n", "  input ce in [-1 1]\n")
    # line 3 "  input ce in [-1 1]": `[` 15, `-1` 16-17, `1` 19
    assert errors(text) == [(2, 13, "`input e in` is unfinished: expected `[` after `in`"),
                            (3, 19, "unexpected `1`; expected `,`")]


def test_an_error_in_the_controller_header_and_one_in_the_body():
    # line 1 "controller my-demo {": `my` 12-13, `-` 14
    text = replace(replace(VALID, "controller demo {", "controller my-demo {"), *BAD_OUTPUT)
    assert errors(text) == [(1, 14, "unexpected `-`; expected one of `{`, a quoted title"),
                            E_OUTPUT]


def test_a_header_without_its_brace_and_an_error_in_the_body():
    text = replace(replace(VALID, "controller demo {", "controller demo"), *BAD_OUTPUT)
    # line 1 "controller demo": `demo` 12-15, reported after it
    assert errors(text) == [(1, 16, "`controller demo` is unfinished: expected one of `{`, "
                                    "a quoted title after `demo`"), E_OUTPUT]


def test_the_shape_message_lists_every_shape_the_grammar_takes():
    # "  terms e : N = 3": the `3` at 17; the grammar's SHAPE terminal holds 22 words
    text = replace(VALID, "N = tri(-2, -1, 0), Z", "N = 3, Z")
    ((line, col, message),) = errors(text)
    assert (line, col) == (4, 17)
    listed = re.fullmatch(r"unexpected `3`; expected a term shape \((.*)\) or "
                          r"`formula\(\"\.\.\.\"\)`", message).group(1)
    shape = re.compile(_lark().get_terminal("SHAPE").pattern.to_regexp())
    assert len(shape_words()) == 22
    assert sorted(listed.split(", ")) == sorted(shape_words())
    assert all(shape.fullmatch(word) for word in listed.split(", "))


def test_statement_starts_come_from_the_grammar():
    starts = statement_starts(_lark())
    words = {t.name: t.pattern.value for t in _lark().terminals
             if isinstance(t.pattern, PatternStr)}
    assert {words[t] for t in starts} >= {"period", "param", "input", "let", "var", "terms",
                                          "inference", "rule", "table", "output", "note",
                                          "verify", "block"}
    assert "RBRACE" not in starts and "$END" not in starts


# ---- hostile text: located errors, within the limit, no traceback

def _located(found: list[tuple[int, int, str]]) -> None:
    assert 1 <= len(found) <= MAX_SYNTAX_ERRORS
    assert all(line >= 1 and col >= 1 for line, col, _ in found)


def test_ten_thousand_opening_braces():
    assert errors("{" * 10_000) == [(1, 1, "unexpected `{`; expected `controller`")]


def test_ten_thousand_opening_braces_in_a_controller():
    # "controller c {" is 14 characters: the second `{` at 15 (`}` sorts after the words)
    assert errors("controller c {" + "{" * 10_000) == [
        (1, 15, "unexpected `{`; expected one of `block`, `fuzzylite`, `inference`, `input`, "
                "`let`, `note`, ...")]


def test_ten_thousand_closing_braces_after_a_controller():
    # "controller c {}" closes at 15; the next `}` at 16 is the only error
    assert errors("controller c {" + "}" * 10_000) == [
        (1, 16, "unexpected `}`; expected the end of the file")]


def test_deep_nesting_ends_with_a_located_error():
    found = errors("controller c { let x in [0, 1] = " + "(" * 10_000)
    # the last `(` at 10,033: reported after it, the statement quoted by its last 40 characters
    assert found == [(1, 10_034, "`..." + "(" * 40 + "` is unfinished: expected one of `(`, "
                                 "`-`, a name, a number after `(`; the file ends there")]
    # "controller c { let x in [0, 1] = " is 33 characters; the `,` after 10,000 `(` at 10,034
    found = errors("controller c { let x in [0, 1] = " + "(" * 10_000 + ", }")
    assert found == [(1, 10_034, "unexpected `,`; expected one of `(`, `-`, a name, a number")]


@pytest.mark.parametrize("seed", range(5))
def test_random_bytes(seed):
    data = random.Random(seed).randbytes(20_000).decode("latin-1")
    _located(errors(data))
    _located(errors("controller c {\n" + data + "\n}\n"))


def test_characters_no_token_matches_are_skipped_with_the_broken_statement():
    # line 2 "  input e in [-1 1 $$]": the error at the `1` of 18; the `$$` after it go with
    # the skipped statement, and the output's error is still found
    text = replace(replace(VALID, "  input e in [-1, 1]\n", "  input e in [-1 1 $$]\n"),
                   *BAD_OUTPUT)
    assert errors(text) == [E_INPUT, E_OUTPUT]


def test_a_file_of_unmatched_characters_is_one_error():
    assert errors("controller c {\n" + "$" * 100_000 + "\n}\n") == [
        (2, 1, "unexpected character `$`")]


# ---- random token soups drawn from the grammar's own terminals

def _terminal_text() -> st.SearchStrategy[str]:
    texts = []
    for terminal in _lark().terminals:
        if isinstance(terminal.pattern, PatternStr):
            texts.append(st.just(terminal.pattern.value))
        else:
            texts.append(st.from_regex(terminal.pattern.to_regexp(), fullmatch=True))
    return st.one_of(texts)


SOUP = st.lists(st.tuples(_terminal_text(), st.sampled_from([" ", "\n", ""])), max_size=60)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(SOUP, st.booleans())
def test_token_soups_raise_only_fuzzyc_errors(soup, in_controller):
    body = "".join(text + gap for text, gap in soup)
    text = "controller c {\n" + body + "\n}\n" if in_controller else body
    try:
        parse(text, "soup.fz")
    except FuzzycError as exc:
        assert len(exc.diagnostics) >= 1
        syntax = [d for d in exc.diagnostics if d.loc is not None]
        assert all(d.loc.line >= 1 and d.loc.col >= 1 for d in syntax)
