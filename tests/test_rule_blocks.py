"""Several rule blocks chained through the signal chain, each with its own inference, and
per-output aggregation/defuzzifier: hand-computed values, the .fz language's checks, and the
back ends that refuse by name what they do not carry."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fll
from fuzzyc.formats.fcl import write_fcl
from fuzzyc.formats.fis import write_fis
from fuzzyc.formats.fll import write_fll
from fuzzyc.formats.fuzzylite_compat import evaluate_sampled
from fuzzyc.formats.fz import write_fz
from fuzzyc.semantics.model import Aggregation, Defuzzifier, TNorm
from fuzzyc.language.parser import parse

# L = tri(-1, 0, 1) = 1 - x and H = tri(0, 1, 2) = x on [0, 1].
CHAIN = """controller chain {
  input a in [0, 1]
  input b in [0, 1]
  terms a : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  terms b : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var m in [0, 1]
  terms m : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var y in [0, 10]
  terms y : singletons lo = 0 hi = 10
  var z in [0, 10]
  terms z : lo = tri(-10, 0, 10), hi = tri(0, 10, 20)
  inference implication = min
  block first {
    inference and = product, defuzzify = centroid
    rule if a is H and b is H then m is H
    rule if a is L or b is L then m is L
  }
  block second {
    inference defuzzify = coa
    inference z: defuzzify = mom
    rule if m is H then y is hi, z is hi
    rule if m is L then y is lo, z is lo
  }
  output u in [0, 10] = y
  output w in [0, 10] = z
}
"""
# Block `first` at a = .6, b = .5: H-rule .6 * .5 = .3, L-rule max(.4, .5) = .5; min
# implication, max aggregation on [0, 1]: M = .5 on [0, .5], 1 - u on [.5, .7], .3 on [.7, 1].
#   area   = .25 + (.455 - .375) + .09                      = .42
#   moment = .0625 + ((.245 - .343/3) - (.125 - .125/3)) + .3 * (.5 - .245)
#          = .0625 + .142/3 + .0765                        = .559/3
#   m = (.559/3) / .42 = .559/1.26
M = 0.559 / 1.26
# Block `second` reads m: H is m, L is 1 - m.  y, centre of area of singletons 0 and 10:
#   (m*10 + (1-m)*0) / 1 = 10 m.  z, mean of maximum: lo clipped at 1 - m > m is the maximum
#   where lo(u) = 1 - u/10 >= 1 - m, i.e. u in [0, 10 m]; its mean is 5 m.


def chain():
    return parse(CHAIN, "chain.fz")


def test_blocks_read_and_write_their_own_variables():
    blocks = chain().blocks
    assert [(b.name, [v.name for v in b.inputs], [v.name for v in b.outputs])
            for b in blocks] == [("first", ["a", "b"], ["m"]), ("second", ["m"], ["y", "z"])]
    first, second = blocks
    assert first.inference.and_.name == "PRODUCT" and second.inference.and_.name == "MIN"
    assert second.output_choices == {"z": (Aggregation.MAX, Defuzzifier.MEAN_OF_MAXIMUM)}
    assert second.inference_of(0).defuzzifier == Defuzzifier.CENTER_OF_AREA


def test_two_block_chain_by_hand():
    controller = Controller(chain(), batch=2)
    out = controller.step({"a": np.array([0.6, 0.6]), "b": np.array([0.5, 0.5])})
    np.testing.assert_allclose(controller.signals["m"], [M, M], rtol=1e-14)
    np.testing.assert_allclose(out["u"], [10 * M] * 2, rtol=1e-14)
    np.testing.assert_allclose(out["w"], [5 * M] * 2, rtol=1e-14)


def test_per_output_defuzzifiers_by_hand():
    second = chain().blocks[1]
    # m = .25: y = 10 * .25 = 2.5 (centre of area); z = mean of [0, 10 * .25] = 1.25
    np.testing.assert_allclose(evaluate(second, [[0.25]]), [[2.5, 1.25]], rtol=1e-14)


def errors_of(text: str) -> str:
    with pytest.raises(FuzzycError) as info:
        parse(text, "bad.fz")
    return str(info.value)


@pytest.mark.parametrize("old, new, words", [
    # the second block before the first: m is read before it is computed
    ("  block first {", "  block zeroth {\n    rule if m is H then y is hi\n  }\n  block first {",
     "block `zeroth` reads `m` before any block computes it; move block `first`, which "
     "computes it, before it"),
    ("    rule if m is L then y is lo, z is lo\n",
     "    rule if m is L then y is lo, z is lo, m is L\n",
     "block `second` concludes on `m`, which an earlier block computes"),
    ("  output u in", "  rule if a is H then y is hi\n  output u in",
     "a rule outside the blocks"),
    ("inference z: defuzzify = mom", "inference z: and = product",
     "an output has its own aggregation and defuzzify only"),
])
def test_block_mistakes_are_reported(old, new, words):
    assert words in errors_of(CHAIN.replace(old, new))


def test_outside_blocks_an_output_is_not_a_condition():
    text = CHAIN.replace("  block first {", "  rule if m is H then y is hi\n  block first {")
    assert "`m` is a rule-base output; conditions must name inputs" in errors_of(text)


def test_one_block_readers_refuse_by_name():
    # the C headers, verify and the lookup table take several blocks (tests/test_c_blocks.py,
    # tests/test_verify_blocks.py, tests/test_lut.py); a reader of one block refuses by name
    with pytest.raises(FuzzycError, match=r"`chain` has 2 rule blocks \(`first`, `second`\)"):
        chain().rulebase


ONE = """controller one {
  input a in [0, 1]
  terms a : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var y in [0, 10]
  terms y : lo = tri(-10, 0, 10), hi = tri(0, 10, 20)
  var z in [0, 10]
  terms z : lo = tri(-10, 0, 10), hi = tri(0, 10, 20)
  inference defuzzify = centroid
  inference z: aggregation = sum, defuzzify = mom
  rule if a is H then y is hi, z is hi
  rule if a is L then y is lo, z is lo
}
"""


def test_per_output_choices_in_one_rule_base():
    rb = parse(ONE, "one.fz").rulebase
    # a = .5: lo and hi clipped at .5.  y: the shape is symmetric about 5, centroid 5.
    # z sums: .5 + u/10 on [0, 5], .5 + (1 - u/10) on [5, 10]; the maximum 1 is at u = 5 only
    np.testing.assert_allclose(evaluate(rb, [[0.5]]), [[5.0, 5.0]], atol=1e-12)
    # a = .8: lo clipped at .2, hi at .8.  z: .2 + u/10 on [0, 8], (1 - u/10) + .8 on [8, 10]:
    # the maximum 1 at u = 8 only (a max aggregation would give the mean of [8, 10], 9)
    assert evaluate(rb, [[0.8]])[0, 1] == pytest.approx(8.0, abs=1e-12)


def test_per_output_choices_fz_fll_fcl_follow_c_and_fis_refuse():
    model = parse(ONE, "one.fz")
    x = np.linspace(0, 1, 11)[:, None]
    for again in (parse(write_fz(model), "again.fz"), read_fll(write_fll(model), "again.fll"),
                  read_fcl(write_fcl(model), "again.fcl")):
        assert again.rulebase.output_choices == model.rulebase.output_choices
        np.testing.assert_array_equal(evaluate(again.rulebase, x), evaluate(model.rulebase, x))
    with pytest.raises(FuzzycError, match="output `z` has its own sum aggregation"):
        write_fis(model)


CORPUS = Path(__file__).parent / "format_corpus"
TWO_BLOCKS = (CORPUS / "blocks_mamdani_sugeno.fll").read_text()
POINTS = np.array([[0.6, 0.5], [0.9, 0.8], [0.2, 0.7], [0.0, 1.0]])


def test_fll_rule_blocks_with_their_own_operators():
    model = read_fll(TWO_BLOCKS, "two.fll")
    mamdani, sugeno = model.blocks
    assert (mamdani.name, [v.name for v in mamdani.outputs]) == ("mamdani", ["y"])
    assert (sugeno.name, [v.name for v in sugeno.outputs]) == ("sugeno", ["z"])
    assert sugeno.inference.and_ == TNorm.PRODUCT and mamdani.inference.and_ == TNorm.MIN
    assert sugeno.inference_of(0).defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
    # z at (.6, .5): hi .6 * .5 = .3, lo .4 + .5 - .2 = .7 (probsum); (.3*10 + .7*0) / 1 = 3
    # y at (.6, .5): hi min(.6, .5) = .5, lo max(.4, .5) = .5: symmetric about 5, centroid 5
    out = Controller(model, batch=1).step({"a": np.array([0.6]), "b": np.array([0.5])})
    assert out["z_out"][0] == pytest.approx(3.0, abs=1e-12)
    assert out["y_out"][0] == pytest.approx(5.0, abs=1e-12)


def test_check_summarizes_every_block(capsys):
    # found by the fuzzer: check read model.rulebase, which refuses a model of several blocks.
    # a, b, y, z have 2 terms each (8); mamdani and sugeno have 2 rules each (4)
    from fuzzyc.cli import main
    assert main(["check", str(CORPUS / "blocks_mamdani_sugeno.fll")]) == 0
    assert "inputs a(2), b(2); outputs y(2), z(2); 8 terms; 2 rule blocks; 4 rules;" in \
        capsys.readouterr().out


def test_eval_csv_of_several_blocks(tmp_path, capsys):
    # the values of test_fll_rule_blocks_with_their_own_operators: y = 5, z = 3 at (.6, .5)
    from fuzzyc.cli import main
    (tmp_path / "in.csv").write_text("a,b\n0.6,0.5\n")
    assert main(["eval", str(CORPUS / "blocks_mamdani_sugeno.fll"), "--csv",
                 str(tmp_path / "in.csv")]) == 0
    header, row = capsys.readouterr().out.splitlines()
    values = dict(zip(header.split(","), map(float, row.split(","))))
    assert values["y"] == pytest.approx(5.0) and values["z"] == pytest.approx(3.0)


def test_fll_rule_blocks_agree_with_the_fuzzylite_cli(tmp_path):
    if shutil.which("fuzzylite") is None:
        pytest.skip("the fuzzylite CLI is not installed (Debian package fuzzylite)")
    (tmp_path / "two.fll").write_text(TWO_BLOCKS)
    (tmp_path / "in.fld").write_text("\n".join(" ".join(map(str, p)) for p in POINTS) + "\n")
    subprocess.run(["fuzzylite", "-i", str(tmp_path / "two.fll"), "-of", "fld", "-d",
                    str(tmp_path / "in.fld"), "-o", str(tmp_path / "out.fld"),
                    "-decimals", "9"], check=True, capture_output=True)
    rows = [r.split() for r in (tmp_path / "out.fld").read_text().split("\n")[1:] if r.strip()]
    theirs = np.array([[float(r[2]), float(r[3])] for r in rows])
    mamdani, sugeno = read_fll(TWO_BLOCKS, "two.fll").blocks
    # fuzzylite samples the centroid at 1000 midpoints: the compat path does the same
    np.testing.assert_allclose(evaluate_sampled(mamdani, POINTS, 1000)[:, 0], theirs[:, 0],
                               atol=1e-6)
    np.testing.assert_allclose(evaluate(sugeno, POINTS)[:, 0], theirs[:, 1], atol=1e-8)


def test_fll_one_block_per_output_defuzzifiers():
    one = TWO_BLOCKS.replace("RuleBlock: sugeno\n  enabled: true\n  conjunction: AlgebraicProduct\n"
                             "  disjunction: AlgebraicSum\n  implication: none\n"
                             "  activation: General\n", "")
    rb = read_fll(one, "one.fll").rulebase
    assert rb.output_choices == {"z": (Aggregation.MAX, Defuzzifier.WEIGHTED_AVERAGE)}
    # min/max now: z at (.6, .5): hi min(.6, .5) = .5, lo max(.4, .5) = .5 -> 5
    np.testing.assert_allclose(evaluate(rb, [[0.6, 0.5]]), [[5.0, 5.0]], atol=1e-12)


def test_fll_blocks_with_different_operators_on_one_output_are_refused():
    text = TWO_BLOCKS.replace("then z is hi", "then y is hi")
    with pytest.raises(FuzzycError, match="`y` is concluded in rule blocks `mamdani` and "
                                          "`sugeno`, whose operators differ"):
        read_fll(text, "bad.fll")
