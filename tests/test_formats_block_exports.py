"""Models of several rule blocks exported: .fz and FLL write every block (chains included), FCL
one RULEBLOCK per block, FIS merges the blocks where that is exact and refuses the rest by name.
Known answers: fuzzylite's own several-block examples read, written, read back, equal bit for
bit on random inputs; hand-computed values; the fuzzylite CLI reading our files live."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.conformance import oracles
from fuzzyc.conformance.roundtrip import round_trip
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import READERS, WRITERS, load_any, read_fll
from fuzzyc.formats.tool_semantics import Chain
from fuzzyc.language.parser import parse
from test_rule_blocks import CHAIN, M

EXAMPLES = Path("/usr/share/doc/fuzzylite/examples")
# fuzzylite's several-block engines: two blocks with their own operators (ObstacleAvoidance),
# two blocks merged into one with a defuzzifier per output (tipper), chains (the others)
SEVERAL = ["hybrid/ObstacleAvoidance.fll", "hybrid/tipper.fll", "mamdani/SimpleDimmerChained.fll",
           "mamdani/SimpleDimmerInverse.fll", "mamdani/Laundry.fll"]
CORPUS = Path(__file__).parent / "format_corpus"

# Two unchained blocks with the same operators, a Sugeno output with linear terms in the second
# (its linear terms read b, the block's only input).  L = 1 - x, H = x on [0, 1].
AB = CHAIN[CHAIN.index("  input a"):CHAIN.index("  var m")]    # inputs a and b, terms L, H
TWO = "controller two {\n" + AB + """  var y in [0, 10]
  terms y : singletons lo = 0 hi = 10
  var z in [0, 10]
  terms z : up = linear(1, 2), flat = linear(5, 0)
  inference and = min, defuzzify = weighted_average
  block first {
    rule if a is H then y is hi
    rule if a is L then y is lo
  }
  block second {
    rule if b is H then z is up
    rule if b is L then z is flat
  }
  output y_out in [0, 10] = y
  output z_out in [0, 10] = z
}
"""
# y = (a*10 + (1-a)*0) / 1 = 10 a;  z = (b (1 + 2b) + (1 - b) 5) / 1 = 5 - 4b + 2b^2:
# at (a, b) = (.3, .5): y = 3, z = 5 - 2 + .5 = 3.5
TWO_AT = ([0.3, 0.5], [3.0, 3.5])


def example(name: str):
    path = EXAMPLES / name
    if not path.exists():
        pytest.skip(f"{path} not installed (Debian package fuzzylite)")
    return load_any(path)


def random_rows(chain: Chain, n: int = 400) -> np.ndarray:
    lo = np.array([v.lo for v in chain.inputs])
    hi = np.array([v.hi for v in chain.inputs])
    return lo + (hi - lo) * np.random.default_rng(14).random((n, len(lo)))


def read_back(model, fmt: str, warnings: list[str] | None = None):
    text = WRITERS[fmt](model, warnings if warnings is not None else [])
    return parse(text, "again.fz") if fmt == ".fz" else READERS[fmt](text, f"again{fmt}")


def assert_same_numbers(model, again) -> None:
    ours, theirs = Chain(model), Chain(again)
    assert [v.name for v in theirs.inputs] == [v.name for v in ours.inputs]
    x = random_rows(ours)
    np.testing.assert_array_equal(theirs.evaluate(x), ours.evaluate(x))   # bit for bit


@pytest.mark.parametrize("name", SEVERAL)
@pytest.mark.parametrize("fmt", [".fz", ".fll"])
def test_several_blocks_round_trip_bit_for_bit(name, fmt):
    model = example(name)
    again = read_back(model, fmt)
    assert len(again.blocks) == len(model.blocks)
    assert_same_numbers(model, again)


@pytest.mark.parametrize("name", ["hybrid/ObstacleAvoidance.fll", "hybrid/tipper.fll",
                                  "mamdani/SimpleDimmerChained.fll",
                                  "mamdani/SimpleDimmerInverse.fll"])
def test_several_blocks_fcl_round_trip_bit_for_bit(name):
    # (Laundry's discrete terms come back from FCL point lists as trapezoids, integrated
    # exactly rather than on the grid: a difference of the FCL reading, not of the blocks)
    model = example(name)
    assert_same_numbers(model, read_back(model, ".fcl"))


def test_fz_blocks_keep_their_own_inference_and_rules():
    model = example("hybrid/ObstacleAvoidance.fll")
    text = WRITERS[".fz"](model, [])
    assert "  block mamdani {\n    inference and = min, or = max, implication = product" in text
    assert "  block takagiSugeno {\n    inference and = min, or = max, implication = min" in text
    assert "    inference tsSteer: aggregation = max, defuzzify = center_of_area" in text


def test_fz_chain_by_hand():
    # tests/test_rule_blocks.py's chain: block `second` reads m = .559/1.26 at (.6, .5), and
    # y = 10 m (its arithmetic there); the .fz written and read back gives it again
    again = read_back(parse(CHAIN, "chain.fz"), ".fz")
    y = Chain(again).evaluate([[0.6, 0.5]])[0]
    assert [v.name for v in Chain(again).outputs] == ["m", "y", "z"]
    assert y[1] == pytest.approx(10 * M, abs=1e-12)


def test_fll_one_rule_block_per_block_with_outputs_own_choices():
    model = example("hybrid/ObstacleAvoidance.fll")
    text = WRITERS[".fll"](model, [])
    assert "RuleBlock: mamdani\n  enabled: true\n  conjunction: Minimum\n  disjunction: " \
           "Maximum\n  implication: AlgebraicProduct" in text
    assert "RuleBlock: takagiSugeno" in text
    # tsSteer's center of area over its constants is fuzzylite's grouped weighted average
    assert "aggregation: Maximum\n  defuzzifier: WeightedAverage TakagiSugeno" in text


@pytest.mark.parametrize("fmt", [".fll", ".fcl"])
def test_chained_export_warns_that_fuzzylite_reads_activations(fmt):
    warnings: list[str] = []
    again = read_back(example("mamdani/SimpleDimmerChained.fll"), fmt, warnings)
    assert any(w.startswith("block `rules_2` reads `Power`, an output of block `rules`: fuzzyc "
                            "reads the output's value") and "reads each term's activation" in w
               for w in warnings), warnings
    assert len(again.blocks) == 2


def test_fis_merges_blocks_whose_operators_agree():
    model = parse(TWO, "two.fz")
    x, expected = TWO_AT
    np.testing.assert_allclose(Chain(model).evaluate([x])[0], expected, atol=1e-12)
    text = WRITERS[".fis"](model, [])
    # z's linear terms read b, the merged rule list's second input: [c_a c_b c0]
    assert "MF1='up':'linear',[0 2 1]" in text and "NumInputs=2" in text
    again = READERS[".fis"](text, "two.fis")
    assert len(again.blocks) == 1
    assert_same_numbers(model, again)
    assert_same_numbers(model, read_back(model, ".fll"))      # linear terms on [a, b] too


@pytest.mark.parametrize("name, words", [
    ("mamdani/SimpleDimmerChained.fll",
     "block `rules_2` reads `Power`, an output of block `rules`: FIS has no chained rules"),
    ("hybrid/ObstacleAvoidance.fll",
     r"rule blocks `mamdani` \(and=min or=max implication=product\) and `takagiSugeno` "
     r"\(and=min or=max implication=min\) differ in operators: FIS has one rule list"),
])
def test_fis_refuses_chains_and_differing_operators_by_name(name, words):
    with pytest.raises(FuzzycError, match=words):
        WRITERS[".fis"](example(name), [])


def test_linear_term_on_another_blocks_output_is_refused():
    text = TWO.replace("terms z : up = linear(1, 2), flat = linear(5, 0)",
                       "terms z : up = linear(1, 2), flat = linear(5, 0)\n"
                       "  var w in [0, 10]\n  terms w : p = linear(0, 1)") \
              .replace("  output y_out", "  block third {\n    rule if y is hi then w is p\n"
                                         "  }\n  output y_out")
    model = parse(text, "three.fz")
    assert_same_numbers(model, read_back(model, ".fz"))
    with pytest.raises(FuzzycError, match="a linear term of `w` has a coefficient on `y`"):
        WRITERS[".fll"](model, [])


def test_convert_then_eval_gives_the_same_numbers(tmp_path, capsys):
    source = EXAMPLES / "mamdani/Laundry.fll"
    if not source.exists():
        pytest.skip(f"{source} not installed (Debian package fuzzylite)")
    (tmp_path / "in.csv").write_text("Load,Dirt\n2.5,3.3\n1,5\n0.2,0.4\n")
    assert main(["convert", str(source), str(tmp_path / "l.fz")]) == 0
    assert "2 rule blocks, 6 rules, 2 inputs, 2 outputs" in capsys.readouterr().out
    printed = []
    for path in (source, tmp_path / "l.fz"):
        assert main(["eval", str(path), "--csv", str(tmp_path / "in.csv")]) == 0
        printed.append(capsys.readouterr().out)
    assert printed[0] == printed[1]
    # one point: every block's fired rules (numbered within the block), the same outputs
    row = dict(zip(*(line.split(",") for line in printed[0].splitlines()[:2])))
    for path in (source, tmp_path / "l.fz"):
        assert main(["eval", str(path), "Load=2.5", "Dirt=3.3"]) == 0
        out = capsys.readouterr().out
        assert "rules_2:1" in out and "rules:2" in out
        assert f"Detergent = {float(row['Detergent']):.6g}, Cycle = {float(row['Cycle']):.6g}" \
            in out


def _needs_fuzzylite():
    if shutil.which("fuzzylite") is None:
        pytest.skip("the fuzzylite CLI is not installed (Debian package fuzzylite)")


@pytest.mark.parametrize("name", SEVERAL)
@pytest.mark.parametrize("fmt", ["fll", "fcl"])
def test_fuzzylite_reads_our_several_block_export(name, fmt):
    # fuzzylite's numbers for our file, against fuzzyc's under the fuzzylite semantics (for the
    # chains: each term's activation read, as tool_semantics.Chain does)
    _needs_fuzzylite()
    done = round_trip(example(name), name, fmt, "fuzzylite")
    assert done.agrees, (done.message, done.worst)


@pytest.mark.parametrize("fmt, tool", [("fll", "fuzzylite"), ("fcl", "fuzzylite"),
                                       ("fis", "fuzzylite"), ("fis", "octave")])
def test_tools_read_our_merged_and_unmerged_blocks(fmt, tool):
    # TWO's linear terms make FCL refuse it: the unchained several-block FCL case is the hybrid
    # blocks file of the corpus, with their own operators
    model = read_fll((CORPUS / "blocks_mamdani_sugeno.fll").read_text(), "two.fll") \
        if fmt == "fcl" else parse(TWO, "two.fz")
    if not {"fuzzylite": oracles.have_fuzzylite, "octave": oracles.have_octave}[tool]():
        pytest.skip(f"{tool} is not installed (Debian packages fuzzylite, "
                    "octave-fuzzy-logic-toolkit)")
    done = round_trip(model, "two", fmt, tool)
    assert done.agrees, (done.message, done.worst)


@pytest.mark.parametrize("word", ["rule", "AND", "end_ruleblock"])
def test_fcl_block_named_by_a_keyword_is_renamed(word):
    # `RULEBLOCK rule` would read as the block's first rule (found trying FCL's keywords)
    text = (CORPUS / "blocks_mamdani_sugeno.fll").read_text()
    model = read_fll(text.replace("RuleBlock: mamdani", f"RuleBlock: {word}"), "kw.fll")
    again = read_back(model, ".fcl")
    assert [b.name for b in again.blocks] == ["rules", "sugeno"]
    assert_same_numbers(model, again)
