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
}

PARAMS = [pytest.param(name, tool, id=f"{name}-{tool}")
          for name, (_, _, _, _, numbers) in CASES.items() for tool in numbers]


@pytest.mark.parametrize("name, tool", PARAMS)
def test_fuzzyc_gives_the_tools_numbers(name, tool):
    file, _, _, x, numbers = CASES[name]
    got = ours(FILES / file, np.array(x), tool)
    assert got.status == "imported", got.message
    np.testing.assert_allclose(got.y, np.array(numbers[tool]), rtol=0, atol=1e-9)


@pytest.mark.parametrize("name, tool", PARAMS)
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
