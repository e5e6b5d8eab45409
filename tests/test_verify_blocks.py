"""`verify` on a model of several rule blocks (issue 28): a rule-base property is checked on the
block it speaks of (its output's; the blocks reading all its inputs; every block for
consistent/complete), over that block's declared input ranges as a one-block rule base is; a
property that must hold in every block takes the weakest block's verdict; closed loops run the
whole chain (search and proof)."""
from __future__ import annotations

import numpy as np
import pytest

import fuzzyc
from fuzzyc.language.parser import parse
from fuzzyc.verifier.result import Evidence, Status
from fuzzyc.verifier.runner import _every_block, verify_model

from test_rule_blocks import CHAIN
from test_verify_own_plant import LAG_P, ProvedLag, lag_loop, own


def verdicts(model):
    return {r.name.split("::", 1)[1]: r for r in verify_model(model)}


def test_structural_defaults_per_block():
    got = verdicts(parse(CHAIN, "chain.fz"))
    assert {k: r.status for k, r in got.items()} == {
        "default: consistent": Status.PROVED,           # each block: no premise twice
        "default: complete": Status.PROVED,             # first: 4 cells, second: 2
        "default: covers a, b at least 0.25": Status.HELD,   # product on a partial table
        "default: covers m at least 0.5": Status.PROVED,
        "default: bounded m in [0, 1]": Status.PROVED,
        "default: bounded y in [0, 10]": Status.PROVED,
        "default: bounded z in [0, 10]": Status.PROVED}
    detail = got["default: complete"].evidence[0].detail
    assert "block `first`: proved (all 4 cells" in detail
    assert "block `second`: proved (all 2 cells" in detail


def test_a_violation_names_its_block():
    # `second` concludes y is hi and y is lo on the same premise m is H
    text = CHAIN.replace("rule if m is L then y is lo, z is lo",
                         "rule if m is H then y is lo, z is lo")
    got = verdicts(parse(text, "bad.fz"))["default: consistent"]
    assert got.status == Status.VIOLATED
    assert got.violation.detail.startswith("block `second`: ")


def test_every_block_takes_the_weakest_verdict():
    proved = [Evidence("proof", Status.PROVED, "exact")]
    held = [Evidence("proof", Status.UNDECIDED, "no method"),
            Evidence("grid", Status.HELD, "grid", cases=400)]
    both = _every_block([("a", proved), ("b", held)])
    assert (both.status, both.cases) == (Status.HELD, 400)
    assert both.detail == "block `a`: proved (exact); block `b`: held (grid)"
    assert _every_block([("a", proved), ("b", proved)]).status == Status.PROVED
    undecided = _every_block([("a", proved), ("b", held[:1])])
    assert undecided.status == Status.UNDECIDED


MONOTONE = CHAIN.replace("  output u in [0, 10] = y", """  output u in [0, 10] = y
  verify {
    monotone y increasing in m
    monotone y decreasing in m
    monotone y increasing in a
  }""")


def test_monotone_in_its_block_and_not_across_blocks():
    got = verdicts(parse(MONOTONE, "mono.fz"))
    # y = 10 m in block `second` (centre of area of singletons 0 and 10 at 1 - m and m): the
    # search holds increasing (no proof method for max-min centre of area) and breaks
    # decreasing, on the block's own input m over its declared range [0, 1]
    rising = got["monotone y increasing in m"]
    assert rising.status == Status.HELD and rising.summary() == \
        "held: grid 20000 points, search 100 examples"
    falling = got["monotone y decreasing in m"].violation
    assert falling is not None and set(falling.point) == {"m"}
    assert falling.to_point["m"] > falling.point["m"]
    across = got["monotone y increasing in a"]
    assert across.status == Status.UNDECIDED
    assert "does not read `a` itself" in across.evidence[0].detail


# test_verify_own_plant's fuzzy P controller for the lag in two blocks: uniform triangles and
# singletons at their peaks make each block the identity (centre of area = the input), so
# du = g = e and the loop is the one-block loop (lag_loop by hand).
RULES = """  rule if e is N then du is N
  rule if e is Z then du is Z
  rule if e is P then du is P
"""
BLOCKS = """  var g in [-1, 1] default 0
  terms g : uniform N Z P
  block copy {
    inference defuzzify = coa
    rule if e is N then g is N
    rule if e is Z then g is Z
    rule if e is P then g is P
  }
  block act {
    rule if g is N then du is N
    rule if g is Z then du is Z
    rule if g is P then du is P
  }
"""
assert RULES in LAG_P
LAG_BLOCKS = LAG_P.replace(RULES, BLOCKS).split("    closed_loop lag_gain")[0] + "  }\n}"


def test_closed_loop_through_two_blocks_is_proved():
    model = fuzzyc.parse(LAG_BLOCKS, name="lag_blocks.fz")
    ys = [fuzzyc.Controller(model).step({"y": np.array([y])})["u"] for y in (0.2, 0.9, 1.4)]
    np.testing.assert_allclose(np.ravel(ys), [1 + 2 * 0.8, 1 + 2 * 0.1, 1 - 2 * 0.4])
    report = fuzzyc.verify(model, scenarios={"lag_step": own(ProvedLag())["lag_step"]},
                           prove=True)
    results = {r.name.split("::", 1)[1]: r for r in report.results}
    always = results["closed_loop lag_step for 10 s :: always y < 1.2"]
    rises = results["closed_loop lag_step for 10 s :: eventually within 3 s: y > 0.9"]
    assert always.status == rises.status == Status.PROVED
    runs = np.array([lag_loop(y0, 1.0) for y0 in np.linspace(0, 0.5, 51)])
    assert runs.max() < 1.0 and (runs[:, :30] > 0.9).any(axis=1).all()


def test_cli_verify_of_several_blocks(tmp_path, capsys):
    path = tmp_path / "chain.fz"
    path.write_text(CHAIN)
    assert fuzzyc.cli.main(["verify", str(path)]) == 0
    out = capsys.readouterr().out
    assert "covers m at least 0.5" in out and "consistent" in out
