"""Malformed or unsupported files of each format: `fuzzyc convert` exits with 2 and says what is
wrong and where (file:line:col), never with a traceback; nothing unsupported is dropped."""
from __future__ import annotations

from pathlib import Path

import pytest

from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fis, read_fll

CORPUS = Path(__file__).parent / "format_corpus"

# file -> the diagnostics expected, as (line:col, words of the message)
EXPECTED = {
    "bad_syntax.fll": [("12:35", "ends too early")],
    "bad_unsupported.fll": [("4:30", "unexpected `/`: a formula takes"),
                            # LargestOfMaximum is read since issue 28; without an implication
                            # it has no fuzzy set to take the maximum of
                            ("9:16", "LargestOfMaximum needs an implication"),
                            ("12:15", "activation `Highest` is not supported"),
                            ("13:23", "hedge `rather` is not supported"),
                            ("14:23", "did you mean `good`?")],
    "bad_syntax.fcl": [("7:3", "unexpected `TERM`: expected `(`, `;`")],
    "bad_unsupported.fcl": [("9:15", "x values must ascend"),
                            ("19:9", "AND HAMACHER is not supported"),
                            ("20:41", "has no term `low`")],
    "bad_rules.fis": [("15:5", "membership function `my_custom_mf` is not supported"),
                      ("24:1", "expected a rule row"),
                      ("25:1", "`x` has 1 terms, no term 3")],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_convert_reports_every_problem_with_its_place(name, tmp_path, capsys):
    out = tmp_path / "out.fz"
    assert main(["convert", str(CORPUS / name), str(out)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and not out.exists()
    lines = [line for line in err.splitlines() if ": error: " in line]
    assert len(lines) == len(EXPECTED[name]), err
    for line, (where, words) in zip(lines, EXPECTED[name]):
        assert line.startswith(f"{CORPUS / name}:{where}: error: "), line
        assert words in line, line


@pytest.mark.parametrize("reader, text, words", [
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 1\n",
     "`Triangle` takes 3 parameters"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1 0.7\n",
     "a term height of 0.7 is not supported"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "OutputVariable: y\n  range: 0 1\n  defuzzifier: WeightedAverage\n"
               "  term: b Triangle 0 0.5 1\nRuleBlock:\n  rule: if x is a then y is b\n",
     "WeightedAverage needs Constant, Linear or Function terms"),
    # a Ramp is monotonic, but fuzzylite's Tsukamoto weighted sum is not in the model (the
    # message said `r` was not monotonic either)
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "OutputVariable: y\n  range: 0 1\n  defuzzifier: WeightedSum\n"
               "  term: r Triangle 0 0.5 1\nRuleBlock:\n  rule: if x is a then y is r\n",
     "WeightedSum needs Constant, Linear or Function terms or monotonic ones (Tsukamoto); "
     "`r` is neither"),
    (read_fcl, "FUNCTION_BLOCK f\nVAR_INPUT x: REAL; END_VAR\nVAR_OUTPUT y: REAL; END_VAR\n"
               "FUZZIFY x\n  RANGE := (0 .. 1);\n  TERM a := Triangle 0 0.5 1;\nEND_FUZZIFY\n"
               "DEFUZZIFY y\n  RANGE := (0 .. 1);\n  TERM r := Triangle 0 0.5 1;\n  METHOD : COGSS;\n"
               "END_DEFUZZIFY\nRULEBLOCK b\n  RULE 1 : if x is a then y is r;\nEND_RULEBLOCK\n"
               "END_FUNCTION_BLOCK\n",
     "COGSS needs singleton or Linear/Function terms or monotonic ones (Tsukamoto); `r` is "
     "neither"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Linear 0 1\n",
     "input `x` cannot have one"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "OutputVariable: y\n  range: 0 1\n  aggregation: Maximum\n"
               "  defuzzifier: Centroid\n  term: b Triangle 0 0.5 1\n"
               "RuleBlock:\n  conjunction: none\n  implication: Minimum\n"
               "  rule: if x is a and (x is a or x is not a) then y is b\n",
     "needs a conjunction"),   # a nested condition needs its norms as a flat rule does
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "InputVariable: w\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "OutputVariable: y\n  range: 0 1\n  aggregation: Maximum\n"
               "  defuzzifier: Centroid\n  term: b Triangle 0 0.5 1\n"
               "RuleBlock:\n  conjunction: none\n"
               "  rule: if x is a and w is any then y is b\n", "needs a conjunction"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "InputVariable: w\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "OutputVariable: y\n  range: 0 1\n  aggregation: Maximum\n"
               "  defuzzifier: Centroid\n  term: b Triangle 0 0.5 1\n"
               "RuleBlock:\n  conjunction: none\n  implication: Minimum\n"
               "  rule: if x is a and w is a then y is b\n", "rule block has `conjunction: none`"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  colour: red\n",
     "unknown key `colour`"),
    (read_fll, "Engine: e\nInputVariable: x\n  range: 0 1\n  term: a Triangle 0 0.5 1\n"
               "OutputVariable: y\n  range: 0 1\n  term: b Triangle 0 0.5 1\n"
               "RuleBlock:\n  rule: if x is a then y is b\n  rule: if x is not (a) then y is b\n",
     "expected"),
    (read_fcl, "FUNCTION_BLOCK f\nVAR_INPUT x : INT; END_VAR\nFUZZIFY x\n"
               "TERM a := (0,0) (1,1);\nEND_FUZZIFY\nEND_FUNCTION_BLOCK\n",
     "`x` is INT: fuzzy variables are REAL; declare it REAL"),
    (read_fcl, "FUNCTION_BLOCK f\nVAR_INPUT x : REAL; END_VAR\nFUZZIFY z\nEND_FUZZIFY\n"
               "END_FUNCTION_BLOCK\n", "`z` is not declared in VAR_INPUT; declare it there"),
    (read_fis, "[System]\nType='mamdani'\nDefuzzMethod='wtaver'\n", "cannot use weighted_average"),
    (read_fis, "[System]\nType='sugeno'\n[Input1]\nName='x'\nRange=[0 1]\n"
               "MF1='a':'linear',[1 0]\n", "cannot have one"),
    # files without variables loaded as empty models (fuzzing: StopIteration in eval --csv)
    (read_fll, "# nothing\n", "the file declares no input variable"),
    (read_fcl, "FUNCTION_BLOCK f\nEND_FUNCTION_BLOCK\n", "the file declares no output variable"),
    (read_fis, "[System]\nName='x'\n", "the file declares no input variable"),
])
def test_unsupported_constructs_are_reported(reader, text, words):
    with pytest.raises(FuzzycError) as info:
        reader(text, "t")
    assert words in str(info.value)
    assert all(d.loc is not None for d in info.value.diagnostics)


FIS_TWO_INPUTS = ("[System]\nName='t'\nType='mamdani'\nNumInputs=2\nNumOutputs=1\n"
                  "NumRules=1\n\n[Input1]\nName='a'\nRange=[0 10]\nNumMFs=1\n"
                  "MF1='lo':'trimf',[0 0 10]\n\n[Input2]\nName='b'\nRange=[0 10]\nNumMFs=1\n"
                  "MF1='lo':'trimf',[0 0 10]\n\n[Output1]\nName='y'\nRange=[0 30]\n"
                  "NumMFs=1\nMF1='lo':'trimf',[0 0 10]\n\n[Rules]\n")   # the rule: line 27


@pytest.mark.parametrize("row, words", [
    # found by the fuzzer: the weight pattern took `1e`, then float() raised ValueError
    ("1 1, 1 (1e) : 1", "expected a rule row"),
    ("1.2.3 1, 1 (1) : 1", "rule index `1.2.3` is not a number"),
    ("- 1, 1 (1) : 1", "rule index `-` is not a number"),
])
def test_a_fis_rule_row_with_a_malformed_number_is_located(row, words):
    with pytest.raises(FuzzycError) as info:
        read_fis(FIS_TWO_INPUTS + row + "\n", "t.fis")
    diagnostic = info.value.diagnostics[0]
    assert (diagnostic.loc.line, diagnostic.loc.col) == (27, 1)
    assert words in diagnostic.message


def test_unreadable_and_unknown_files(tmp_path, capsys):
    assert main(["convert", str(tmp_path / "missing.fll"), str(tmp_path / "o.fz")]) == 2
    assert "cannot read" in capsys.readouterr().err
    (tmp_path / "x.xml").write_text("<fis/>")
    assert main(["convert", str(tmp_path / "x.xml"), str(tmp_path / "o.fz")]) == 2
    assert "unknown extension `.xml`" in capsys.readouterr().err
