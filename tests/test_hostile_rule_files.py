"""Rule files a user did not mean to write (issue 13): odd line breaks, empty ranges, huge sums,
other encodings. Each gives file:line:col with the caret on the right line, never a traceback."""

import json
from pathlib import Path

import pytest

from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any
from fuzzyc.language.parser import parse

BASE = """\
controller demo {
  input e in [-1, 1]
  input ce in [-1, 1]
  terms e : uniform N ZO P
  terms ce : uniform N ZO P
  var du in [-1, 1] default 0
  terms du : uniform N ZO P
  rule if e is P and ce is P then du is P
  output u in [-1, 1] = du
}
"""


def diagnostics_of(text: str) -> list:
    with pytest.raises(FuzzycError) as info:
        parse(text, "bad.fz")
    return info.value.diagnostics


def rendered_lines(diagnostic) -> tuple[str, str, str]:
    head, shown, caret = diagnostic.format().split("\n")
    return head, shown, caret


def test_form_feed_is_whitespace_and_later_lines_keep_their_numbers():
    # lark counts lines at \n only; str.splitlines() also splits at \f, which used to show the
    # line above the rule (line 8 of lark is line 9 of splitlines) under the caret.
    text = BASE.replace("  input ce", "\f  input ce").replace("then du is P", "then du is Q")
    (first,) = diagnostics_of(text)
    head, shown, caret = rendered_lines(first)
    assert head.startswith("bad.fz:8:41: error: unknown term `Q`")
    assert shown == "      rule if e is P and ce is P then du is Q"
    assert caret.index("^") == 4 + 41 - 1


@pytest.mark.parametrize("char,name", [("\v", "U+000B"), ("\u2028", "U+2028")])
def test_vertical_tab_and_line_separator_are_located_characters(char, name):
    # Not whitespace to the grammar: an unexpected character at 3:1 (it used to be an
    # IndexError: the line lark named was a different, shorter line of splitlines()).
    (first,) = diagnostics_of(BASE.replace("  input ce", char + "  input ce"))
    head, shown, caret = rendered_lines(first)
    assert head == f"bad.fz:3:1: error: unexpected character {name}"
    assert shown == "       input ce in [-1, 1]"     # the character shows as one space
    assert caret == "    ^"


def test_carriage_return_line_feed_endings_read_like_line_feeds():
    text = BASE.replace("then du is P", "then du is Q").replace("\n", "\r\n")
    (first,) = diagnostics_of(text)
    assert first.format().split("\n")[1] == "      rule if e is P and ce is P then du is Q"


@pytest.mark.parametrize("text,line,col", [
    # the case: a second output with an empty range and nothing else
    (BASE.replace("  var du", "  var dv in [1, 1]\n  var du"), 6, 14),
    # the output of a table and a list table
    (BASE.replace("var du in [-1, 1]", "var du in [1, 1]").replace(
        "  rule if e is P and ce is P then du is P\n",
        "  table du (rows ce: N ZO P; cols e: N ZO P) {\n    N N ZO\n    N ZO P\n    ZO P P\n  }\n"
        "  table (e, ce -> du) {\n    1: N N -> N\n  }\n"), 6, 14),
    # an input
    (BASE.replace("input ce in [-1, 1]", "input ce in [1, 1]"), 3, 16),
])
def test_an_empty_range_is_one_error_without_follow_ons(text, line, col):
    (only,) = diagnostics_of(text)
    assert (only.loc.line, only.loc.col) == (line, col)
    assert "is empty: [1, 1]" in only.message


def test_a_sum_of_1000_terms_is_evaluated(tmp_path, capsys):
    path = tmp_path / "sum.fz"
    path.write_text(BASE.replace("= du", "= du + " + " + ".join(["e"] * 1000)))
    assert main(["eval", str(path), "e=0.0005", "ce=0", "--json"]) == 0
    outputs = json.loads(capsys.readouterr().out)["outputs"]
    # No rule fires (ce = 0 is not P), so du = its default 0; u = 0 + 1000 * 0.0005 = 0.5.
    assert outputs["du"] == 0.0
    assert outputs["u"] == pytest.approx(0.5, abs=1e-12)


def test_a_1000_deep_expression_is_a_located_error():
    text = BASE.replace("= du", "= du + " + "-(" * 1000 + "e" + ")" * 1000)
    (only,) = diagnostics_of(text)
    assert only.loc.line == 9
    assert "nested more than" in only.message and "`let`" in only.message


def test_a_90_deep_expression_is_fine():
    # e * (0.5 + e * (0.5 + ...)) 90 times: two tree levels per pair of brackets, under the limit.
    model = parse(BASE.replace("= du", "= du + " + "e*(0.5+" * 90 + "e" + ")" * 90), "deep.fz")
    assert model.outputs[0].name == "u"


def test_a_latin1_rule_file_is_reported_at_the_byte(tmp_path, capsys):
    path = tmp_path / "latin.fz"
    path.write_bytes(BASE.replace("{\n", "{\n  # caf\xe9\n", 1).encode("latin-1"))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    # line 2 is `  # café`: the é (byte 0xe9) is its 8th character
    assert f"{path}:2:8: error: byte 0xe9 is not UTF-8" in err
    assert "Traceback" not in err


def test_a_byte_order_mark_is_allowed(tmp_path, capsys):
    path = tmp_path / "bom.fz"
    path.write_bytes(b"\xef\xbb\xbf" + BASE.encode())
    assert main(["check", str(path)]) == 0


CORPUS = Path(__file__).parent / "format_corpus"


def test_an_fll_file_counts_lines_at_newlines_only(tmp_path):
    # U+2028 before `OutputVariable` (line 21): str.splitlines() made the rules one line later.
    text = (CORPUS / "tipper.fll").read_text()
    path = tmp_path / "ls.fll"
    path.write_text(text.replace("OutputVariable", "\u2028OutputVariable", 1)
                    .replace("then tip is cheap", "then tip is cheapo", 1))
    with pytest.raises(FuzzycError) as info:
        load_any(path)
    first = info.value.diagnostics[0]
    assert (first.loc.line, first.loc.col) == (38, 58)
    assert first.format().split("\n")[1].strip() == \
        "rule: if service is poor or food is rancid then tip is cheapo"


def test_an_fcl_file_locates_a_vertical_tab(tmp_path):
    text = (CORPUS / "tipper.fcl").read_text()
    path = tmp_path / "vt.fcl"
    path.write_text(text.replace("DEFUZZIFY", "\vDEFUZZIFY", 1))
    with pytest.raises(FuzzycError) as info:
        load_any(path)
    head, shown, caret = rendered_lines(info.value.diagnostics[0])
    assert head.endswith(":28:1: error: unexpected character U+000B")
    assert (shown, caret) == ("     DEFUZZIFY tip", "    ^")
