"""Malformed rule files: each must give file:line:col, the line with a caret, and a message
that names the mistake (and the fix where it can). No traceback, exit status 2 from the CLI."""

import pytest

from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import parse

BASE = """\
controller demo {
  param Yr = 30 kHz
  input f : kHz in [0, 100]
  input r in [0, 1]  input h in [0, 1]
  let e in [-1, 1] = clamp((Yr - f) * 0.1, -1, 1)
  let ce in [-1, 1] = clamp(delta(r) * 8, -1, 1)
  terms e : N = tri(-2, -1, 0), ZO = tri(-1, 0, 1), P = tri(0, 1, 2)
  terms ce : uniform NB NS ZO PS PB  terms h : L = lshoulder(0.2, 0.8), H = rshoulder(0.2, 0.8)
  var du in [-1, 1] default 0
  terms du : singletons NB=-1 NS=-0.5 ZO=0 PS=0.5 PB=1
  table du when h is H (rows ce: NB NS ZO PS PB; cols e: N ZO P) {
    NB NB NS
    NB NS ZO
    NS ZO PS
    ZO PS PB
    PS PB PB
  }
  output u : mm/min in [0, 3] = integrate(du * 0.01) from 0.3
}
"""


def errors_of(text: str) -> list:
    with pytest.raises(FuzzycError) as info:
        parse(text, "bad.fz")
    return info.value.diagnostics


def replace(old: str, new: str) -> str:
    assert old in BASE, old
    return BASE.replace(old, new, 1)


def test_base_file_is_valid():
    model = parse(BASE, "good.fz")
    assert model.rulebase.n_rules == 15


# (mutation of BASE, expected line, expected column, words the message must contain)
CASES = [
    # 1 unknown term in a table cell, with the known terms listed
    (replace("    NB NS ZO\n", "    NB PM ZO\n"), 13, 8, ["unknown term `PM`", "NB NS ZO PS PB"]),
    # 2 a close misspelling gets a suggestion
    (replace("    NB NS ZO\n", "    NB NSS ZO\n"), 13, 8, ["unknown term `NSS`", "did you mean `NS`"]),
    # 3 undefined name in an expression
    (replace("(Yr - f)", "(Yrr - f)"), 5, 29, ["unknown name `Yrr`", "did you mean `Yr`"]),
    # 4 duplicate declaration
    (replace("  input r in [0, 1]", "  input f in [0, 1]"), 4, 9, ["already declared", "line 3"]),
    # 5 table row with too few cells
    (replace("    NB NS ZO\n", "    NB NS\n"), 13, 5, ["2 cells", "3 columns"]),
    # 6 table with a missing row
    (replace("    PS PB PB\n", ""), 11, 3, ["4 rows", "declares 5"]),
    # 7 degenerate triangle (a > b)
    (replace("N = tri(-2, -1, 0)", "N = tri(-1, -2, 0)"), 7, 21, ["degenerate tri", "a <= b <= c"]),
    # 8 (a term peaking outside its range is a warning: test_a_term_peaking_outside_...)
    # 9 unit mismatch in a subtraction, at the operand that disagrees (`f` of `Yr - f`)
    (replace("input f : kHz", "input f : Hz"), 5, 34, ["unit mismatch", "kHz", "Hz"]),
    # 10 a conclusion that names an input
    (replace("  output u", "  rule if e is P then ce is PB\n  output u"), 18, 23,
     ["`ce` is an input", "conclusion must name an output"]),
    # 11 a condition that names an output
    (replace("  output u", "  rule if du is PB then du is NB\n  output u"), 18, 11,
     ["`du` is a rule-base output", "conditions must name inputs"]),
    # 12 syntax error: missing `=` in a let
    (replace("let e in [-1, 1] =", "let e in [-1, 1]"), 5, 20, ["unexpected", "`=`"]),
    # 13 unknown inference option with a suggestion
    (replace("  output u", "  inference defuzzify = centriod\n  output u"), 18, 25,
     ["unknown defuzzify `centriod`", "did you mean `centroid`"]),
    # 14 empty range
    (replace("input r in [0, 1]", "input r in [1, 0]"), 4, 15, ["range", "empty"]),
    # 15 an unknown term inside a nested condition
    (replace("  output u", "  rule if (e is P or ce is XX) and not h is L then du is NB\n"
                           "  output u"), 18, 28, ["unknown term `XX` of `ce`", "PB"]),
    # 16 unknown function
    (replace("clamp((Yr - f)", "clip((Yr - f)"), 5, 22, ["unknown function `clip`", "clamp"]),
    # 17 wrong number of shape arguments
    (replace("N = tri(-2, -1, 0)", "N = tri(-2, -1)"), 7, 21, ["`tri` takes 3 numbers", "got 2"]),
    # 18 rule weight outside [0, 1]
    (replace("  output u", "  rule if e is P then du is PB with 1.5\n  output u"), 18, 37,
     ["weight", "[0, 1]"]),
    # 19 the same variable twice in a table's guard
    (replace("when h is H", "when h is H and h is L"), 11, 28, ["`h` appears twice"]),
    # 20 a let without range that gets terms
    (replace("let ce in [-1, 1] =", "let ce ="), 8, 9, ["needs a range", "let ce in [lo, hi]"]),
    # 21 stateful function inside an output expression
    (replace("integrate(du * 0.01)", "integrate(delta(du) * 0.01)"), 18, 43,
     ["`delta` keeps state", "let"]),
    # 22 start value outside the output range
    (replace("from 0.3", "from 5"), 18, 59, ["start value 5", "outside"]),
    # 23 reciprocal output with a range through zero
    (replace("output u : mm/min in [0, 3] = integrate(du * 0.01)",
             "output u : mm/min in [0, 3] = 1 / integrate(du * 0.01)"), 18, 25,
     ["reciprocal output", "above 0"]),
    # 24 unexpected character
    (replace("let e in", "let e $ in"), 5, 9, ["unexpected character `$`"]),
    # 25 a period without a time unit
    (replace("  param Yr", "  period 40 kHz\n  param Yr"), 2, 10, ["period", "time unit"]),
    # 26 unknown variable in a `when` guard
    (replace("when h is H", "when x is H"), 11, 17, ["unknown input `x`"]),
    # 27 the file ends before the controller's closing brace
    (BASE.rstrip().rstrip("}"), 18, 1, ["ends too early"]),
]


@pytest.mark.parametrize("text,line,col,words", CASES, ids=[f"case{i + 1}" for i in range(len(CASES))])
def test_malformed_file_reports_location_and_message(text, line, col, words):
    diagnostics = errors_of(text)
    first = diagnostics[0]
    assert (first.loc.file, first.loc.line, first.loc.col) == ("bad.fz", line, col), first.format()
    for word in words:
        assert word in first.message, first.format()
    rendered = first.format()
    assert rendered.startswith(f"bad.fz:{line}:{col}: error: ")
    caret_line = rendered.splitlines()[2]
    assert caret_line.index("^") == 4 + col - 1


def test_several_independent_errors_are_reported_in_one_run():
    text = replace("    NB NS ZO\n", "    NB PM ZO\n").replace("du * 0.01", "du * k")
    lines = sorted(d.loc.line for d in errors_of(text))
    assert lines == [13, 18]


def test_a_broken_let_does_not_cascade_into_errors_where_it_is_used():
    diagnostics = errors_of(replace("(Yr - f)", "(Yrr - f)"))
    assert [(d.loc.line, d.loc.col) for d in diagnostics] == [(5, 29)]


def test_several_syntax_errors_are_reported_in_one_run():
    text = replace("let e in [-1, 1] =", "let e in [-1, 1]").replace("from 0.3", "from from")
    assert sorted(d.loc.line for d in errors_of(text)) == [5, 18]


def test_cli_prints_diagnostics_without_traceback_and_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.fz"
    bad.write_text(replace("    NB NS ZO\n", "    NB PM ZO\n"))
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:13:8: error: unknown term `PM`" in err
    assert "Traceback" not in err


def test_a_term_peaking_outside_its_range_is_read_with_a_located_warning(tmp_path, capsys):
    # legal in FLL, FCL and FIS, so .fz says it too (issue 28): the file is read, `check`
    # prints the warning at the term's name (line 7, column 53) and exits 0
    good = tmp_path / "good.fz"
    good.write_text(replace("P = tri(0, 1, 2)", "P = tri(1, 2, 3)"))
    assert main(["check", str(good)]) == 0
    out, err = capsys.readouterr()
    assert out.startswith(f"{good}: demo: ")
    assert err.startswith(f"{good}:7:53: warning: term `P` of `e` peaks at 2, outside the range "
                          "[-1, 1]: inputs inside the range meet only its flank; widen the "
                          "range if the term is meant\n")
    assert err.splitlines()[2].index("^") == 4 + 53 - 1
    # an output term: the defuzzifier reads the output's range only
    [warning] = parse(replace("PB=1", "PB=1.5"), "w.fz").warnings
    assert (warning.loc.line, warning.message.split(": ")[-1]) == (
        10, "the defuzzifier reads the output's range only; widen the range if the term is meant")


def test_unreadable_file_is_a_clean_error(tmp_path, capsys):
    assert main(["check", str(tmp_path / "missing.fz")]) == 2
    assert "cannot read" in capsys.readouterr().err
