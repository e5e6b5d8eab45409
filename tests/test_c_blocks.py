"""Several rule blocks through the C back ends (float, double, q15, q31): one header, one
NAME_step that runs the blocks in order (each block's tables and rulebase under the prefix
NAME_bK_ or NAME_q15_bK_), against the engine's Controller by hand and step by step, and
proved free of run-time errors by EVA."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.load import CController
from fuzzyc.backends.c.proof import frama_c, prove
from fuzzyc.backends.c_fixed.header import (CHAIN_ERROR_BOUND, FORMATS, chain_error_bound,
                                            generate_fixed_header, io_frac)
from fuzzyc.engine.chain import Controller
from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import parse

from test_c_chain import CHAIN_TOLERANCE, run_chain, random_sequences
from test_c_fixed import chain_errors, chain_runner
from test_rule_blocks import CHAIN, M, ONE

# test_rule_blocks' two-block chain without its per-output defuzzifier for z (that one is
# test_an_output_with_its_own_defuzzifier_by_hand): z is then centre of area too.
TWO = CHAIN.replace("    inference z: defuzzify = mom\n", "")

# Three blocks, each through another path of the back end: a cell-table Mamdani block with a
# let step before it, a Takagi-Sugeno block reading its output, a bisector block over
# trapezoids reading both; an incremental output integrates the last block's output.
THREE = """controller three {
  input e in [-1, 1]
  input de in [-1, 1]
  let s in [-1, 1] = clamp((e + de) / 2, -1, 1)
  terms s : uniform N Z P
  terms de : uniform N Z P
  var g in [0, 1]
  terms g : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var k in [-1, 1]
  terms k : lo = tri(-2, -1, 0), mid = tri(-1, 0, 1), hi = tri(0, 1, 2)
  var du in [-1, 1]
  terms du : N = trap(-2, -1, -0.5, 0), Z = tri(-0.5, 0, 0.5), P = trap(0, 0.5, 1, 2)
  block mamdani {
    inference defuzzify = centroid
    rule if s is N then g is L
    rule if s is Z then g is H
    rule if s is P then g is L
  }
  block sugeno {
    inference and = product, defuzzify = weighted_average
    rule if g is H and de is N then k is lo
    rule if g is H and de is P then k is hi
    rule if g is L then k is mid
  }
  block bisect {
    inference defuzzify = bisector
    rule if k is hi then du is P
    rule if k is lo then du is N
    rule if g is H then du is Z
  }
  output u in [-5, 5] = integrate(du) from 0
  output kk in [-1, 1] = k
}
"""

# Two blocks the fixed-point back end takes (center of area, weighted average; partitions of
# triangles; plain AND rules, a wildcard in the second block's last rule).
FIXED = """controller fx {
  input e in [-1, 1]
  input de in [-1, 1]
  terms e : uniform N Z P
  terms de : uniform N Z P
  var g in [0, 1]
  terms g : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var du in [-1, 1]
  terms du : singletons N = -1 Z = 0 P = 1
  block first {
    inference defuzzify = coa
    rule if e is N then g is L
    rule if e is Z then g is H
    rule if e is P then g is L
  }
  block second {
    inference and = product, defuzzify = weighted_average
    rule if g is H and de is N then du is N
    rule if g is H and de is Z then du is Z
    rule if g is H and de is P then du is P
    rule if g is L then du is Z
  }
  output u in [-1, 1] = du
  output gg in [0, 1] = g
}
"""


def two():
    return parse(TWO, "two.fz")


@pytest.mark.parametrize("numeric, atol", [("float", 1e-5), ("double", 1e-12)])
def test_two_blocks_by_hand(numeric, atol):
    # test_rule_blocks' arithmetic: block `first` at a = .6, b = .5 gives m = .559/1.26 = M;
    # block `second`: y = centre of area of singletons 0 and 10 at levels 1 - m and m = 10 m;
    # z: triangles lo (peak 0) and hi (peak 10) at the same levels, centre of area = 10 m.
    out = CController(two(), 1, numeric).step({"a": np.array([0.6]), "b": np.array([0.5])})
    np.testing.assert_allclose(out["u"], [10 * M], atol=atol * 10)
    np.testing.assert_allclose(out["w"], [10 * M], atol=atol * 10)


@pytest.mark.parametrize("text", [TWO, THREE], ids=["two", "three"])
def test_blocks_agree_with_the_engine_step_by_step(text):
    model = parse(text, "blocks.fz")
    x = random_sequences(model, seed=len(model.blocks))
    expected = run_chain(Controller(model, 4), model, x)
    span = np.array([o.hi - o.lo for o in model.outputs])
    assert np.all(expected.max(axis=(0, 1)) - expected.min(axis=(0, 1)) > 1e-3 * span)
    for numeric, tolerance in CHAIN_TOLERANCE.items():
        got = run_chain(CController(model, 4, numeric), model, x)
        assert np.all(np.isfinite(got))
        error = np.abs(got - expected) / span
        assert error.max() <= tolerance, (numeric, np.unravel_index(error.argmax(), error.shape))


def test_header_runs_the_blocks_in_order_under_their_prefixes():
    header = generate_header(parse(THREE, "three.fz"))
    calls = [header.index(f"three_b{k}_rulebase(x{k}, y{k});") for k in range(3)]
    assert calls == sorted(calls)
    for k, name in enumerate(("mamdani", "sugeno", "bisect")):
        assert f"/* Rule block {k}: {name}. */" in header
        assert f"#define THREE_B{k}_N_RB_INPUTS" in header
    assert "THREE_N_RB_INPUTS" not in header    # no one-block size where there are several


@pytest.mark.parametrize("numeric, atol", [("float", 1e-5), ("double", 1e-12)])
def test_an_output_with_its_own_defuzzifier_by_hand(numeric, atol):
    # test_rule_blocks' CHAIN as written: z by mean of maximum in block `second`, which the
    # header emits as two rule bases (y, then z; fuzzyc.backends.rule_blocks): at a = .6,
    # b = .5, u = 10 m and w = 5 m (test_rule_blocks' arithmetic)
    model = parse(CHAIN, "chain.fz")
    header = generate_header(model, numeric)
    assert " *   1: second (y) (chain_b1_rulebase)" in header
    assert "defuzzify=mean_of_maximum" in header
    out = CController(model, 1, numeric).step({"a": np.array([0.6]), "b": np.array([0.5])})
    np.testing.assert_allclose([out["u"][0], out["w"][0]], [10 * M, 5 * M], atol=atol * 10)


ONE_OUT = ONE.replace("  rule if a is L then y is lo, z is lo\n",
                      "  rule if a is L then y is lo, z is lo\n"
                      "  output yy in [0, 10] = y\n  output zz in [0, 10] = z\n")


def test_one_rule_base_of_two_defuzzifiers_follows_the_engine():
    # test_rule_blocks' ONE (y by centroid, z by sum and mean of maximum): a = .5 gives 5 and
    # 5, a = .8 gives z = 8 (test_rule_blocks' arithmetic); every a against the engine
    model = parse(ONE_OUT, "one.fz")
    a = np.linspace(-0.1, 1.1, 121)
    expected = Controller(model, len(a)).step({"a": a})
    for numeric, tolerance in CHAIN_TOLERANCE.items():
        got = CController(model, len(a), numeric).step({"a": a})
        for name in ("yy", "zz"):
            np.testing.assert_allclose(got[name], expected[name], atol=tolerance * 10)
        np.testing.assert_allclose([got["yy"][60], got["zz"][60], got["zz"][90]], [5, 5, 8],
                                   atol=tolerance * 10)
    with pytest.raises(FuzzycError, match="has no one NAME_rulebase"):
        CController(model).evaluate([[0.5]])


@pytest.mark.skipif(frama_c() is None, reason="frama-c not installed (Debian: frama-c-base)")
@pytest.mark.parametrize("numeric", ["float", "double"])
def test_blocks_header_has_no_run_time_error(numeric):
    proof = prove(parse(THREE, "three.fz"), numeric)
    assert not proof.alarms, proof.summary()
    assert proof.assertions[1] > 0 and proof.assertions[0] == proof.assertions[1], \
        proof.summary()


@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_fixed_point_blocks_by_hand(numeric):
    # e = .5: Z and P at .5 each; block `first`, center of area of L (peak 0) and H (peak 1)
    # at .5 each: g = .5.  Block `second`, g = .5 (H and L at .5), de = -.5 (N and Z at .5),
    # product: H and N .25 -> -1, H and Z .25 -> 0, L .5 -> 0; weighted average
    # (-.25 + 0 + 0) / (.25 + .25 + .5) = -.25.  u = du = -.25, gg = g = .5: exact on both
    # grids (every membership and level is a power of two), so to the LSB.
    model = parse(FIXED, "fx.fz")
    frac_in = [io_frac(sig.lo, sig.hi, numeric) for sig in model.signals]
    frac_out = [io_frac(o.lo, o.hi, numeric) for o in model.outputs]
    xq = np.array([[[0.5 * 2 ** frac_in[0], -0.5 * 2 ** frac_in[1]]]])
    yq = chain_runner(model, numeric, batch=1)(xq)[0, 0]
    np.testing.assert_allclose(yq / 2.0 ** np.array(frac_out), [-0.25, 0.5],
                               atol=2.0 ** -min(frac_out))


def test_fixed_point_blocks_follow_the_controller():
    # q15 and q31 within the stated chain bound and within the bound derived from every
    # rounding, block 1's input error being block 0's output error
    model = parse(FIXED, "fx.fz")
    for numeric, error in chain_errors(model).items():
        assert error.max() <= CHAIN_ERROR_BOUND[numeric], numeric
        derived = np.array(list(chain_error_bound(model, numeric).values()))
        assert np.all(np.isfinite(derived)) and np.all(error <= derived), (numeric, error)


def test_fixed_point_header_names_each_block():
    header = generate_fixed_header(parse(FIXED, "fx.fz"), "q15")
    assert " *   0: first (fx_q15_b0_rulebase), inference:" in header
    assert "Derived worst case of block 1 (" in header
    calls = [header.index(f"fx_q15_b{k}_rulebase_wide(xg{k}, yw{k});") for k in range(2)]
    assert calls == sorted(calls)


@pytest.mark.skipif(frama_c() is None, reason="frama-c not installed (Debian: frama-c-base)")
@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_fixed_point_blocks_header_has_no_run_time_error(numeric):
    proof = prove(parse(FIXED, "fx.fz"), numeric)
    assert not proof.alarms, proof.summary()
    assert proof.assertions[1] > 0 and proof.assertions[0] == proof.assertions[1], \
        proof.summary()
