"""FCL files with several FUNCTION_BLOCKs: `FILE.fcl::NAME` chooses one wherever a rule file is
named; the corpus file blocks_tipper_fan.fcl holds two blocks with different variables, each
evaluated at one input to a hand-computed value; the errors give their places."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any, read_fcl, split_block

CORPUS = Path(__file__).parent / "format_corpus"
TWO = CORPUS / "blocks_tipper_fan.fcl"


def messages(exc: pytest.ExceptionInfo) -> list[str]:
    return [d.format().splitlines()[0] for d in exc.value.diagnostics]


# ---------------------------------------------------------------------- choosing a block
def test_tipper_block_hand_value():
    model = load_any(f"{TWO}::tipper")
    assert (model.name, model.source_path) == ("tipper", f"{TWO}::tipper")
    assert [v.name for v in model.rulebase.inputs] == ["service"]
    # service 3: poor (0,1)(10,0) = (10-3)/10 = 0.7, good (0,0)(10,1) = 3/10 = 0.3;
    # COGS over the singletons: (0.7*5 + 0.3*25) / (0.7 + 0.3) = (3.5 + 7.5) / 1 = 11
    assert evaluate(model.rulebase, np.array([[3.0]]))[0, 0] == pytest.approx(11.0, abs=1e-12)


def test_fan_block_hand_value():
    model = load_any(TWO.with_name(TWO.name + "::fan"))     # a Path works as well as a str
    rb = model.rulebase
    assert model.name == "fan" and [v.name for v in rb.inputs] == ["temp", "humidity"]
    # temp 15: cool (30-15)/20 = 0.75, hot 0.25; humidity 20: dry 0.8, humid 0.2.
    # rule 1 (AND PROD) 0.75*0.8 = 0.6 on slow, rule 2 (OR MAX) max(0.25, 0.2) = 0.25 on fast.
    # A triangle of base 40 clipped at h is a trapezoid of area h*(40 + 40*(1-h))/2 = 20h(2-h),
    # symmetric about its peak: slow 20*0.6*1.4 = 16.8 about 20, fast 20*0.25*1.75 = 8.75
    # about 80 (they do not overlap). COG = (16.8*20 + 8.75*80) / (16.8 + 8.75)
    # = (336 + 700) / 25.55 = 40.547945...
    expected = 1036 / 25.55
    assert evaluate(rb, np.array([[15.0, 20.0]]))[0, 0] == pytest.approx(expected, abs=1e-9)


def test_one_block_file_loads_with_or_without_its_name():
    plain, named = load_any(CORPUS / "valve.fcl"), load_any(f"{CORPUS / 'valve.fcl'}::valve")
    np.testing.assert_array_equal(plain.rulebase.antecedents, named.rulebase.antecedents)
    assert plain.source_path == str(CORPUS / "valve.fcl")


@pytest.mark.parametrize("ref, expected", [
    ("a/b.fcl::fan", (Path("a/b.fcl"), "fan")),
    ("a/b.fcl", (Path("a/b.fcl"), None)),
    ("a::b/c.fcl", (Path("a::b/c.fcl"), None)),    # `::` in a folder name is part of the path
])
def test_split_block(ref, expected):
    assert split_block(ref) == expected


# ---------------------------------------------------------------------- errors
def test_several_blocks_and_none_chosen_lists_them():
    with pytest.raises(FuzzycError) as exc:
        load_any(TWO)
    # the second FUNCTION_BLOCK keyword is line 36 col 1; the names sit at col 16
    assert messages(exc) == [
        f"{TWO}:36:1: error: 2 FUNCTION_BLOCKs in this file and none chosen: name one as "
        f"`{TWO}::NAME`; the blocks are `tipper` at {TWO}:3:16, `fan` at {TWO}:36:16"]


def test_unknown_block_lists_the_names():
    with pytest.raises(FuzzycError) as exc:
        load_any(f"{TWO}::Fan")
    assert messages(exc) == [f"error: no FUNCTION_BLOCK `Fan` in {TWO}: the blocks are "
                             f"`tipper` at {TWO}:3:16, `fan` at {TWO}:36:16"]


# Small files; each line shown with its number to read the line:col off.
A = "FUNCTION_BLOCK a\nEND_FUNCTION_BLOCK\n"                    # lines 1-2
BAD_A = ("FUNCTION_BLOCK a\n"                                    # 1
         "VAR_INPUT x : INT; END_VAR\n"                          # 2: INT at col 15
         "END_FUNCTION_BLOCK\n")                                 # 3
GOOD_B = ("FUNCTION_BLOCK b\n"
          "VAR_INPUT x : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
          "FUZZIFY x\nTERM lo := (0, 1) (1, 0);\nRANGE := (0 .. 1);\nEND_FUZZIFY\n"
          "DEFUZZIFY y\nTERM one := 1;\nMETHOD : COGS;\nDEFAULT := 0;\nRANGE := (0 .. 2);\n"
          "END_DEFUZZIFY\n"
          "RULEBLOCK r\nRULE 1 : IF x IS lo THEN y IS one;\nEND_RULEBLOCK\n"
          "END_FUNCTION_BLOCK\n")


def test_duplicate_block_name_at_the_second_one():
    # second `a` starts line 3 ("FUNCTION_BLOCK " is 15 characters: the name at col 16)
    with pytest.raises(FuzzycError) as exc:
        read_fcl(A + A, "dup.fcl", "a")
    assert messages(exc) == ["dup.fcl:3:16: error: FUNCTION_BLOCK `a` again (first at "
                             "dup.fcl:1:16): block names must differ"]


def test_nameless_block_among_several():
    with pytest.raises(FuzzycError) as exc:
        read_fcl(A + "FUNCTION_BLOCK\nEND_FUNCTION_BLOCK\n", "anon.fcl", "a")
    assert messages(exc) == ["anon.fcl:3:1: error: this FUNCTION_BLOCK has no name: in a file "
                             "with several, each needs one to be chosen as `FILE.fcl::NAME`"]


def test_syntax_error_in_a_block_not_chosen_is_reported():
    broken = "FUNCTION_BLOCK c\nVAR_INPUT x REAL; END_VAR\nEND_FUNCTION_BLOCK\n"
    # GOOD_B is 17 lines, so `broken`'s line 2 is line 19; `REAL` (no `:`) at col 13
    with pytest.raises(FuzzycError) as exc:
        read_fcl(GOOD_B + broken, "syn.fcl", "b")
    assert messages(exc)[0].startswith("syn.fcl:19:13: error: unexpected `REAL`")


def test_semantic_problem_in_a_block_not_chosen_is_not_reported():
    # BAD_A's INT variable would be an error (see test_formats_errors), but `b` is chosen
    model = read_fcl(BAD_A + GOOD_B, "sem.fcl", "b")
    # x = 0.25: lo = 0.75, the only rule: y = (0.75*1) / 0.75 = 1
    assert evaluate(model.rulebase, np.array([[0.25]]))[0, 0] == pytest.approx(1.0)
    with pytest.raises(FuzzycError) as exc:
        read_fcl(BAD_A + GOOD_B, "sem.fcl", "a")
    assert messages(exc) == ["sem.fcl:2:11: error: `x` has no range and its terms do not give "
                             "one: declare a range",
                             "sem.fcl:2:15: error: `x` is INT: fuzzy variables are REAL; "
                             "declare it REAL"]


@pytest.mark.parametrize("ref, words", [
    (f"{CORPUS / 'tipper.fll'}::tipper", "only an .fcl file has named blocks"),
    (f"{TWO}::", "after `::` comes a FUNCTION_BLOCK name (letters, digits, _), not ``"),
    (f"{TWO}::2x", "not `2x`"),
])
def test_bad_selection(ref, words):
    with pytest.raises(FuzzycError) as exc:
        load_any(ref)
    assert words in str(exc.value)


# ---------------------------------------------------------------------- the command line
def test_cli_convert_check_eval_compile_one_block(tmp_path, capsys):
    out = tmp_path / "fan.fz"
    assert main(["convert", f"{TWO}::fan", str(out)]) == 0
    assert "wrote" in capsys.readouterr().out
    back = load_any(out)
    # the .fz file evaluates like the block (same hand value as test_fan_block_hand_value)
    assert evaluate(back.rulebase, np.array([[15.0, 20.0]]))[0, 0] == pytest.approx(1036 / 25.55)

    assert main(["check", f"{TWO}::tipper"]) == 0
    assert capsys.readouterr().out.startswith(f"{TWO}::tipper: tipper: inputs service(2);")

    assert main(["eval", f"{TWO}::tipper", "service=3", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["outputs"]["tip_out"] == pytest.approx(11.0)

    assert main(["compile", f"{TWO}::fan", "--target", "lut", "-o", str(tmp_path)]) == 0
    assert (tmp_path / "fan_lut.h").exists()


def test_cli_several_blocks_none_chosen_exits_2(tmp_path, capsys):
    assert main(["convert", str(TWO), str(tmp_path / "x.fz")]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and not (tmp_path / "x.fz").exists()
    assert f"{TWO}:36:1: error: 2 FUNCTION_BLOCKs in this file and none chosen" in err

