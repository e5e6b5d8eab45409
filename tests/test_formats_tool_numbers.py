"""Issue 28: constructs that crashed or were refused although fuzzylite, pyfuzzylite and Octave
give numbers.  Each file in tests/tool_numbers/ is evaluated by fuzzyc under the tool's
semantics (as `fuzzyc eval FILE --semantics TOOL`: tests/differential/compare.ours) against the
tool's numbers, worked out by hand below and recorded from the live tool with

    cd tests && ../.venv/bin/python -c "from differential import tools; ...
        tools.run(TOOL, [(path, x, inputs, outputs)])"

(the same harness as the differential fuzzer); the live tool is asked again where installed."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from tests.differential import tools
from tests.differential.compare import ours

FILES = Path(__file__).resolve().parent / "tool_numbers"
NAN = float("nan")

# (file, inputs, outputs, x, {tool: y}, semantics per tool)
CASES = {
    # WeightedAverage over Linear and Constant terms with aggregation Maximum: pyfuzzylite 8
    # groups the rules of a term with the aggregation (Aggregated.grouped_terms), fuzzylite 6
    # weights every rule.  Crashed with "need defuzzify = weighted_average" before.
    # a=2, b=6: a low 0.8, high 0.2; b low 0.4, high 0.6; rules lin 0.8, lin 0.4, c 0.2;
    #   lin = 2a + b + 3 = 13, c = 10.
    #   pyfuzzylite: lin max(0.8, 0.4) = 0.8 -> (0.8*13 + 0.2*10) / 1.0 = 12.4
    #   fuzzylite 6: (0.8*13 + 0.4*13 + 0.2*10) / 1.4 = 17.6 / 1.4 = 12.571428...
    # a=5, b=5: every degree 0.5, lin = 18:
    #   pyfuzzylite (0.5*18 + 0.5*10) / 1.0 = 14; fuzzylite 6 (9 + 9 + 5) / 1.5 = 15.333...
    "coa_linear": ("coa_linear.fll", ["a", "b"], ["y"], [[2.0, 6.0], [5.0, 5.0]],
                   {"pyfuzzylite": [[12.4], [14.0]],
                    "fuzzylite": [[17.6 / 1.4], [23 / 1.5]]}),
    # An output no rule concludes (z): its fuzzy set is empty, so the tools give its default
    # (3); crashed with "zero-size array to reduction operation maximum" before.
    # y at a=2: small clipped at 0.8 (area (4 + 0.8)/2 * 0.8 = 1.92 about 2), big at 0.2
    #   (area (4 + 3.2)/2 * 0.2 = 0.72 about 8): (1.92*2 + 0.72*8) / 2.64 = 3.6363...
    #   (the midpoint rule at 100 samples hits it: both pieces are symmetric about their
    #   centres, which fall on sample boundaries); a=5: symmetric, 5.
    "unconcluded": ("unconcluded.fll", ["a"], ["y", "z"], [[2.0], [5.0]],
                    {"pyfuzzylite": [[9.6 / 2.64, 3.0], [5.0, 3.0]],
                     "fuzzylite": [[9.6 / 2.64, 3.0], [5.0, 3.0]]}),
    # The file's settings (issue 28, items 1-3): `lock-range: true` clamps a (15 -> 10,
    # -5 -> 0), `Centroid 7` samples y at the 7 midpoints u_k = (k + 1/2) 10/7, z's numeric
    # default 4.5 replaces "no rule fired".  a=15 -> 10: high 1, big unclipped; its samples
    # 6.43, 7.86, 9.29 have membership 0.2143, 0.9286, 0.3571 (the others 0), so
    # y = (6.43*0.2143 + 7.86*0.9286 + 9.29*0.3571) / 1.5 = 7.9932; z: low 0, default 4.5.
    # a=-5 -> 0: y nothing fired (default nan); z the mirror image, 10 - 7.9932 = 2.0068.
    # Unclamped, a=15 gives high 0.5 and y = 7.86 + ... another number.
    "locked": ("locked.fll", ["a"], ["y", "z"], [[15.0], [-5.0]],
               {"pyfuzzylite": [[7.993197278911565, 4.5], [NAN, 2.006802721088435]],
                "fuzzylite": [[7.993197278911565, 4.5], [NAN, 2.006802721088435]]}),
    # SmallestOfMaximum / LargestOfMaximum (FLL), LM / RM (FCL), som / lom (FIS): refused
    # before.  small = Trapezoid 0 1 3 4, big = Triangle 6 8 10 on [0, 10], max-min.
    # a=2: small clipped at 0.8 on [0.8, 3.2] (exact); fuzzylite's 100 midpoints 0.05 + 0.1 k
    #   first reach 0.8 at 0.85 and last hold it at 3.15.  a=9: big clipped at 0.9 on
    #   [7.8, 8.2]: 7.85 and 8.15.  a=5: both at 0.5, small on [0.5, 3.5], big on [7, 9]:
    #   0.55 and 8.95.
    "extremes": ("extremes.fll", ["a"], ["first", "last"], [[2.0], [9.0], [5.0]],
                 {"pyfuzzylite": [[0.85, 3.15], [7.85, 8.15], [0.55, 8.95]],
                  "fuzzylite": [[0.85, 3.15], [7.85, 8.15], [0.55, 8.95]],
                  "exact": [[0.8, 3.2], [7.8, 8.2], [0.5, 9.0]]}),
    "extremes_LM": ("extremes_LM.fcl", ["a"], ["y"], [[2.0], [9.0], [5.0]],
                    {"fuzzylite": [[0.85], [7.85], [0.55]]}),
    "extremes_RM": ("extremes_RM.fcl", ["a"], ["y"], [[2.0], [9.0], [5.0]],
                    {"fuzzylite": [[3.15], [8.15], [8.95]]}),
    # Octave samples linspace(0, 10, 101), step 0.1, and takes samples equal to the maximum:
    # a=2: 0.8 (mu 0.8 exactly) and 3.1 (at 3.2, (4 - 3.2) / 1 = 0.7999999999999998 < 0.8);
    # a=9: 7.9 (Octave's 7.8 is 10 - 22 * 0.1 = 7.7999999999999998, mu 0.8999999999999999 <
    # 0.9) and 8.2; a=5: 0.5 and 9.  Both outputs use the system's DefuzzMethod.
    "extremes_som": ("extremes_som.fis", ["a"], ["first", "second"], [[2.0], [9.0], [5.0]],
                     {"octave": [[0.8, 0.8], [7.9, 7.9], [0.5, 0.5]]}),
    "extremes_lom": ("extremes_lom.fis", ["a"], ["first", "second"], [[2.0], [9.0], [5.0]],
                     {"octave": [[3.1, 3.1], [8.2, 8.2], [9.0, 9.0]]}),
    # Aggregation NormalizedSum (refused before): both tools fold it to min(1, a + b), as
    # BoundedSum.  a=0: low 1, both rules fire 1 on each output; small (Trapezoid 0 1 3 4) +
    # big (Triangle 2 5 8) exceed 1 on [2, 3.5], so the bounded set is 1 on [1, 3.5] and
    # below 1 elsewhere (0.983 at the samples 4.95 and 5.05 around big's peak): the mean of
    # maximum is the mean of the midpoints 1.05 ... 3.45, 2.25 (UnboundedSum: 2.95, the
    # peak of 1 + (x - 2) / 3 at x = 3).  The centroids are the tools' (recorded).
    "normalized_sum": ("normalized_sum.fll", ["a"], ["first", "last"], [[0.0], [2.0]],
                       {"pyfuzzylite": [[3.528985507246376, 2.25], [3.596448598130841, 3.05]],
                        "fuzzylite": [[3.528985507246376, 2.25], [3.596448598130841, 3.05]]}),
    # fuzzylite's FCL dialect (refused before): `LOCK : RANGE`, Binary terms written with
    # `inf` / `-inf`, METHOD COGSS (its WeightedSum), COGS with ACCU over Linear terms
    # (fuzzylite 6 weights every rule, as its WeightedAverage; before, fuzzyc grouped the
    # rules of an output with its own defuzzifier).  lin = 2a + b + 3, c = 10.
    # a=2, b=6: up (a >= 4) 0, down (b <= 5) 0: y nothing fired, nan; low 0.8, high 0.6:
    #   s = 0.8*13 + 0.6*13 = 18.2; g = (0.8*13 + 0.6*13) / 1.4 = 13.
    # a=5, b=5: up 1, down 1: y = big and small at 1, symmetric about 5: 5; low 0.5, high
    #   0.5, rule 5 min(1, 0.5) = 0.5: s = 9 + 9 + 5 = 23, g = 23 / 1.5 = 15.333...
    # a=6, b=2: up 1, down 1: y 5; low 0.4, high 0.2, rule 5 0.2; lin = 17:
    #   s = 6.8 + 3.4 + 2 = 12.2, g = 12.2 / 0.8 = 15.25.
    "fuzzylite_dialect": ("fuzzylite_dialect.fcl", ["a", "b"], ["y", "s", "g"],
                          [[2.0, 6.0], [5.0, 5.0], [6.0, 2.0]],
                          {"fuzzylite": [[NAN, 18.2, 13.0], [5.0, 23.0, 23 / 1.5],
                                         [5.0, 12.2, 15.25]]}),
    # Shapes with equal break points (refused before: the differential fuzzer's most common
    # refusal): a step, 0 up to the point and 1 above it for S, 1 up to it and 0 above for Z,
    # as both tools' branches compute (and the exact semantics: fuzzyc's own formula).
    # pi = PiShape 2 2 5 7 = S(2, 2) Z(5, 7), step = SShape 6 6, drop = ZShape 3 3; y the
    # weighted average of a = 1, b = 5, c = 9.
    # x=2: pi 0 (S(2, 2) is 0 at 2), step 0, drop 1: y = 9.
    # x=3: pi 1 (S 1 above 2, Z(5, 7) 1 up to 5), drop 1 (at its point): (1 + 9) / 2 = 5.
    # x=6: pi = Z(5, 7) at its middle 6: 2 ((6 - 7) / 2)^2 = 0.5; step 0 at 6, drop 0: y = 1.
    # x=6.5: pi 2 ((6.5 - 7) / 2)^2 = 0.125, step 1: (0.125 + 5) / 1.125 = 4.5555...
    # x=8: pi 0, step 1: y = 5.
    "degenerate_steps": ("degenerate_steps.fll", ["x"], ["y"],
                         [[2.0], [3.0], [6.0], [6.5], [8.0]],
                         {tool: [[9.0], [5.0], [1.0], [5.125 / 1.125], [5.0]]
                          for tool in ("exact", "pyfuzzylite", "fuzzylite")}),
}

PARAMS = [pytest.param(name, tool, id=f"{name}-{tool}")
          for name, (_, _, _, _, numbers) in CASES.items() for tool in numbers]
TOOL_PARAMS = [p for p in PARAMS if p.values[1] != "exact"]


@pytest.mark.parametrize("name, tool", PARAMS)
def test_fuzzyc_gives_the_tools_numbers(name, tool):
    file, _, _, x, numbers = CASES[name]
    got = ours(FILES / file, np.array(x), tool)
    assert got.status == "imported", got.message
    np.testing.assert_allclose(got.y, np.array(numbers[tool]), rtol=0, atol=1e-9)


@pytest.mark.parametrize("name, tool", TOOL_PARAMS)
def test_live_tool_gives_the_recorded_numbers(name, tool):
    why = tools.available(tool)
    if why:
        pytest.skip(why)
    file, inputs, outputs, x, numbers = CASES[name]
    (y,) = tools.run(tool, [(FILES / file, np.array(x), inputs, outputs)])
    assert not isinstance(y, Exception), y
    np.testing.assert_allclose(y, np.array(numbers[tool]), rtol=0, atol=1e-9)


@pytest.mark.parametrize("name, tool", PARAMS)
def test_fuzzyc_eval_applies_the_file_settings(name, tool, tmp_path, capsys):
    """`fuzzyc eval FILE --csv --semantics TOOL` gives the numbers the conversion path gives
    (lock-range, the file's resolution, numeric defaults; before, it ignored all three)."""
    file, inputs, outputs, x, numbers = CASES[name]
    csv = tmp_path / "x.csv"
    csv.write_text(",".join(inputs) + "\n" + "".join(",".join(repr(v) for v in row) + "\n"
                                                     for row in x))
    assert main(["eval", str(FILES / file), "--csv", str(csv), "--semantics", tool]) == 0
    rows = [line.split(",") for line in capsys.readouterr().out.strip().splitlines()]
    y = [[float(row[rows[0].index(n)]) for n in outputs] for row in rows[1:]]
    np.testing.assert_allclose(y, np.array(numbers[tool]), rtol=0, atol=1e-9)


def test_eval_says_a_locked_input_is_clamped(tmp_path, capsys):
    main(["eval", str(FILES / "locked.fll"), "a=15", "--semantics", "pyfuzzylite"])
    assert "(clamped: the file's lock-range)" in capsys.readouterr().err
    main(["eval", str(FILES / "locked.fll"), "a=15"])
    assert "(not clamped)" in capsys.readouterr().err


@pytest.mark.parametrize("file", ["extremes.fll", "extremes_LM.fcl", "extremes_som.fis"])
def test_the_c_back_ends_refuse_the_extremes_of_maximum(file, tmp_path, capsys):
    """No C emission for smallest/largest of maximum (their records have none): a refusal that
    names the defuzzifier, not a header computing something else."""
    for numeric in ("float", "q15"):
        assert main(["compile", str(FILES / file), "--numeric", numeric, "-o",
                     str(tmp_path)]) != 0
        assert "does not emit the smallest_of_maximum defuzzifier" in capsys.readouterr().err
    assert not list(tmp_path.glob("*.h"))


@pytest.mark.parametrize("word", ["smallest_of_maximum", "som", "largest_of_maximum", "lom"])
def test_fz_reads_the_extremes(word, tmp_path):
    """.fz says them too (the converted files read back): a=2 gives 0.8 / 3.2 exactly."""
    from fuzzyc.api import evaluate, load
    text = (FILES / "extremes.fll").read_text()
    fz = tmp_path / "extremes.fz"
    assert main(["convert", str(FILES / "extremes.fll"), str(fz)]) == 0
    fz.write_text(fz.read_text().replace("defuzzify = smallest_of_maximum", f"defuzzify = {word}")
                  .replace("defuzzify = largest_of_maximum", f"defuzzify = {word}"))
    y = evaluate(load(str(fz)), {"a": np.array([2.0])})
    expected = 0.8 if word in ("smallest_of_maximum", "som") else 3.2
    assert "LargestOfMaximum" in text
    np.testing.assert_allclose([y["first"][0], y["last"][0]], [expected, expected], atol=1e-12)


def test_extremes_under_probsum_are_exact():
    """AlgebraicSum aggregation (a piecewise polynomial set, fuzzyc.engine.defuzz): a=5 fires
    small and big at 0.5 each, apart (no overlap), so the set is small on [0.5, 3.5] and big on
    [7, 9] at 0.5: the smallest of maximum 0.5, the largest 9 (before, the probsum path took
    them for the bisector)."""
    from fuzzyc.formats import read_fll
    from fuzzyc.api import evaluate
    text = (FILES / "extremes.fll").read_text().replace("aggregation: Maximum",
                                                        "aggregation: AlgebraicSum")
    y = evaluate(read_fll(text), {"a": np.array([5.0, 2.0])})
    np.testing.assert_allclose(y["first"], [0.5, 0.8], atol=1e-12)
    np.testing.assert_allclose(y["last"], [9.0, 3.2], atol=1e-12)


def test_a_resolution_in_the_semantics_overrides_the_file():
    """`pyfuzzylite:1000` samples at 1000 midpoints 0.005 + 0.01 k whatever the file's 100:
    a=2 gives 0.805 and 3.195 (the samples nearest inside [0.8, 3.2]).  Crashed before (the
    differential harness's Chain took the name whole)."""
    got = ours(FILES / "extremes.fll", np.array([[2.0]]), "pyfuzzylite:1000")
    assert got.status == "imported", got.message
    np.testing.assert_allclose(got.y, [[0.805, 3.195]], rtol=0, atol=1e-9)


def test_degenerate_shapes_read_back_from_fz_and_stay_out_of_fis(tmp_path, capsys):
    """The steps above convert to .fz (`pishape(2, 2, 5, 7)`, read back with the same numbers);
    FIS cannot say them (the Octave toolkit's are_mf_params refuses smf/zmf/pimf with equal
    break points, MATLAB puts the step at the mean, inclusive): the export and the import
    refuse them with the term's name and place."""
    fz = tmp_path / "steps.fz"
    assert main(["convert", str(FILES / "degenerate_steps.fll"), str(fz)]) == 0
    assert "pishape(2, 2, 5, 7)" in fz.read_text()
    got = ours(fz, np.array(CASES["degenerate_steps"][3]), "exact")
    np.testing.assert_allclose(got.y, CASES["degenerate_steps"][4]["exact"], rtol=0, atol=1e-12)
    capsys.readouterr()
    assert main(["convert", str(fz), str(tmp_path / "steps.fis")]) != 0
    assert "term `pi` of `x` (`pishape` with equal break points) is a step that FIS cannot " \
        "say" in capsys.readouterr().err
    fis = tmp_path / "bad.fis"
    fis.write_text(FIS_WITH_A_STEP)
    assert main(["check", str(fis)]) != 0
    assert "bad.fis:11:5: error: degenerate smf [6 6]: smf [a b] needs a < b" \
        in capsys.readouterr().err


FIS_WITH_A_STEP = """[System]
Name='steps'
Type='sugeno'
NumInputs=1
NumOutputs=1
NumRules=1
[Input1]
Name='x'
Range=[0 10]
NumMFs=1
MF1='step':'smf',[6 6]
[Output1]
Name='y'
Range=[0 10]
NumMFs=1
MF1='b':'constant',[5]
[Rules]
1, 1 (1) : 1
"""
