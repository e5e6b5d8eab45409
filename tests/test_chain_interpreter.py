"""The one chain walk (fuzzyc.semantics.chain_ops) in its four domains: floats (the engine's
Controller), C float/double text (the header, compiled), fixed point (the q15 header) and affine
sets (the reachability proofs), on hand-computed traces and on random chains.
"""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.backends.c.load import CController
from fuzzyc.backends.c_fixed.header import chain_error_bound, io_frac
from fuzzyc.engine.chain import Controller
from fuzzyc.language.parser import parse
from fuzzyc.semantics.chain_ops import OUTPUT_OPS, STEP_OPS
from fuzzyc.semantics.model import Op, OutputKind
from fuzzyc.verifier.reach.affine import Affine, Symbols
from fuzzyc.verifier.reach.chain import SetChain, SetController

from test_c_fixed import chain_runner

# One step of each kind and one output of each kind, fed by them.
HAND = """
controller hand {
  input x in [0, 10]
  let d = delta(x)
  let p = prev(x)
  let l = lowpass(x, 0.75, 0.25)
  let e in [-1, 1] = clamp(d, -1, 1)
  terms e : uniform N Z P
  var du in [-1, 1] default 0
  terms du : singletons NB=-1 ZO=0 PB=1
  inference and = min, aggregation = max, defuzzify = center_of_area
  rule if e is N then du is NB
  rule if e is Z then du is ZO
  rule if e is P then du is PB
  output od in [-5, 5] = d
  output op in [0, 10] = p
  output ol in [0, 10] = l
  output oi in [0, 4] = integrate(d) from 2
  output ou in [1, 10] = 1 / integrate(d * 0.2) from 2
}
"""
OUTPUTS = ["od", "op", "ol", "oi", "ou"]
# x = 1, 3, NaN, 4:
#  d = delta(x): 0 (first), 3 - 1 = 2, NaN (the NaN is not stored), 4 - 3 = 1
#  p = prev(x): 1 (first: x itself), 1, 3, 3 (the memory still holds 3)
#  l = 0.75 l + 0.25 x: 1 (first: x), 0.75*1 + 0.25*3 = 1.5, NaN (memory stays 1.5),
#      0.75*1.5 + 0.25*4 = 2.125
#  od = clamp(d, -5, 5), held where d is NaN: 0, 2, 2, 1
#  op = p: 1, 1, 3, 3;  ol = l held: 1, 1.5, 1.5, 2.125
#  oi = clamp(oi + d, 0, 4) from 2 (NaN adds 0): 2 + 0 = 2, 2 + 2 = 4, 4, 4 + 1 = 5 -> 4
#  ou = 1 / v, v = clamp(v + 0.2 d, 1/10, 1/1) from 1/2: v = 0.5, 0.5 + 0.4 = 0.9, 0.9,
#       0.9 + 0.2 = 1.1 -> 1: ou = 2, 1/0.9 = 1.1111, 1.1111, 1
HAND_X = [1.0, 3.0, np.nan, 4.0]
HAND_TRACE = np.array([[0, 1, 1, 2, 2],
                       [2, 1, 1.5, 4, 1 / 0.9],
                       [2, 3, 1.5, 4, 1 / 0.9],
                       [1, 3, 2.125, 4, 1]], dtype=float)
HAND_SIGNALS = {"d": [0, 2, np.nan, 1], "p": [1, 1, 3, 3], "l": [1, 1.5, np.nan, 2.125]}
# the same without the NaN sample, for the domains whose values are always finite
FINITE_X = [1.0, 3.0, 4.0]
FINITE_TRACE = HAND_TRACE[[0, 1, 3]]
FINITE_TRACE[2] = [1, 3, 2.125, 4, 1]   # 4 - 3 = 1; prev 3; 0.75*1.5 + 0.25*4; 4 + 1 -> 4; 1


def trace(controller, xs) -> np.ndarray:
    rows = []
    for x in xs:
        y = controller.step({"x": np.array([x])})
        rows.append([y[name][0] for name in OUTPUTS])
    return np.array(rows)


def test_every_op_and_output_kind_has_one_record():
    assert set(STEP_OPS) == set(Op) and set(OUTPUT_OPS) == set(OutputKind)
    for rule in STEP_OPS.values():
        assert rule.stateful == (rule.when_seen is not None) == (rule.memory_bounds is not None)
        assert rule.keeps in (("argument", "value") if rule.stateful else ("",))
    # lowpass: the hull of [lo, hi] and gain b/(1-a) = 0.5/0.5 = 1 times it, or none for a >= 1
    assert STEP_OPS[Op.LOWPASS].memory_bounds((0.5, 1.5), -1.0, 2.0) == (-3.0, 6.0)
    assert STEP_OPS[Op.LOWPASS].memory_bounds((1.0, 0.5), -1.0, 2.0) is None


def test_hand_trace_in_the_float_domain():
    c = Controller(parse(HAND))
    rows, signals = [], {name: [] for name in HAND_SIGNALS}
    for x in HAND_X:
        y = c.step({"x": np.array([x])})
        rows.append([y[name][0] for name in OUTPUTS])
        for name in signals:
            signals[name].append(c.signals[name][0])
    np.testing.assert_allclose(rows, HAND_TRACE, rtol=1e-15, atol=1e-15)
    for name, expected in HAND_SIGNALS.items():
        np.testing.assert_allclose(signals[name], expected, rtol=0, atol=1e-15)


@pytest.mark.parametrize("numeric, tolerance", [("double", 1e-15), ("float", 1e-6)])
def test_hand_trace_in_the_c_header(numeric, tolerance):
    got = trace(CController(parse(HAND), 1, numeric), HAND_X)
    np.testing.assert_allclose(got, HAND_TRACE, rtol=tolerance, atol=tolerance)


def test_hand_trace_in_the_q15_header():
    model = parse(HAND)
    fin = io_frac(0.0, 10.0, "q15")
    xq = np.array(FINITE_X)[:, None, None] * 2.0 ** fin      # 1, 3, 4 are on the grid
    outs = [o for o in model.outputs]
    frac = np.array([io_frac(o.lo, o.hi, "q15") for o in outs])
    got = chain_runner(model, "q15", batch=1)(xq)[:, 0, :] / 2.0 ** frac
    span = np.array([o.hi - o.lo for o in outs])
    bound = np.array(list(chain_error_bound(model, "q15", len(FINITE_X)).values()))
    assert np.all(np.isfinite(bound)) and np.all(bound < 2.0 ** -10)
    assert np.all(np.abs(got - FINITE_TRACE) <= bound * span), (got, FINITE_TRACE)


def set_trace(model, xs, width: float, batch: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (steps, batch, outputs) of the set chain on the boxes
    [x - width, x + width] (xs (steps, batch, signals))."""
    sym = Symbols(batch)
    c = SetController(model, sym, model.symbol_values())
    lows, highs = [], []
    for x in xs:
        y = c.step({s.name: Affine.interval(sym, x[:, i] - width, x[:, i] + width)
                    for i, s in enumerate(model.signals)})
        bounds = [y[o.name].bounds() if isinstance(y[o.name], Affine)
                  else (np.full(batch, y[o.name]),) * 2 for o in model.outputs]
        lows.append(np.stack([b[0] for b in bounds], axis=1))
        highs.append(np.stack([b[1] for b in bounds], axis=1))
    return np.array(lows), np.array(highs)


def test_hand_trace_inside_the_affine_sets():
    model = parse(HAND)
    lo, hi = set_trace(model, np.array(FINITE_X)[:, None, None], 0.01)
    assert np.all(lo[:, 0] <= FINITE_TRACE) and np.all(FINITE_TRACE <= hi[:, 0])
    # and tight: x moves by at most 0.01, so every output by at most a few hundredths
    assert np.all(hi - lo < 0.2)


def test_set_domain_reads_a_possibly_non_finite_value_as_may_hold():
    sym = Symbols(2)
    chain = SetChain.__new__(SetChain)
    chain.c = SetController(parse(HAND), sym, {})
    anything = Affine(sym, [np.inf, 0.5])       # box 0 unbounded, box 1 the point 0.5
    # clamp: box 0 anywhere in [0, 4], box 1 the point
    lo, hi = chain.clamp(anything, 0.0, 4.0).bounds()
    assert lo[0] <= 0 and hi[0] >= 4 and lo[1] == hi[1] == 0.5
    # a direct output either takes the new value (3) or holds its state (1) in box 0
    held = chain.if_finite(anything, Affine(sym, 3.0), Affine(sym, 1.0))
    lo, hi = held.bounds()
    assert lo[0] <= 1 and hi[0] >= 3 and lo[1] == hi[1] == 3.0
    assert chain.if_finite(float("nan"), 3.0, 1.0) == 1.0   # a NaN number surely holds


def random_fz(seed: int) -> str:
    """A random chain: 1-2 inputs, 1-5 steps of every kind (let, delta, prev, lowpass with
    0 <= a < 1), one rule block on a clamped step, 1-3 outputs of random kinds."""
    rng = np.random.default_rng(seed)
    lines = [f"controller rand{seed} {{", "  param g = 0.5"]
    names = []
    for i in range(int(rng.integers(1, 3))):
        lo = float(rng.choice([-10.0, -1.0, 0.0]))
        lines.append(f"  input x{i} in [{lo:g}, {lo + float(rng.choice([1.0, 5.0, 20.0])):g}]")
        names.append(f"x{i}")
    n_in = len(names)
    for k in range(int(rng.integers(1, 6))):
        src = str(rng.choice(names))
        expr = [f"{src} * {rng.uniform(-2, 2):.3f} + {rng.uniform(-1, 1):.3f}",
                f"delta({src}) * {rng.uniform(0.5, 3):.3f}",
                f"prev({src}) - {src} * g",
                f"lowpass({src}, {float(rng.choice([0.0, 0.25, 0.5, 0.9])):g}, "
                f"{rng.uniform(0.1, 1.5):.3f})"][int(rng.integers(0, 4))]
        lines.append(f"  let s{k} = {expr}")
        names.append(f"s{k}")
    lines += [f"  let e in [-1, 1] = clamp({rng.choice(names[n_in:])} * "
              f"{rng.uniform(0.1, 2):.3f}, -1, 1)",
              "  terms e : uniform N Z P", "  var du in [-1, 1] default 0",
              "  terms du : singletons NB=-1 ZO=0 PB=1",
              "  inference and = min, aggregation = max, defuzzify = center_of_area",
              "  rule if e is N then du is NB", "  rule if e is Z then du is ZO",
              "  rule if e is P then du is PB"]
    for j in range(int(rng.integers(1, 4))):
        inc = f"du * {rng.uniform(0.05, 2):.3f}" + (f" + {names[-1]} * 0.01"
                                                     if rng.random() < 0.5 else "")
        kind = int(rng.integers(0, 3))
        if kind == 0:
            lo = float(rng.choice([-2.0, -0.5, 0.0]))
            lines.append(f"  output o{j} in [{lo:g}, {lo + 3:g}] = {inc}")
        elif kind == 1:
            lines.append(f"  output o{j} in [-1, 4] = integrate({inc}) from "
                         f"{rng.uniform(-1, 4):.3f}")
        else:
            lo = float(rng.choice([0.5, 1.6, 2.0]))
            lines.append(f"  output o{j} in [{lo:g}, {lo * float(rng.choice([3.0, 30.0])):g}] "
                         f"= 1 / integrate({inc} * 0.01) from {rng.uniform(lo, 2 * lo):.3f}")
    return "\n".join(lines + ["}"]) + "\n"


N_STEPS, BATCH = 25, 3


@pytest.mark.parametrize("seed", range(6))
def test_random_chains_agree_in_every_domain(seed):
    model = parse(random_fz(seed))
    ops = {s.op for s in model.steps} | {o.kind for o in model.outputs}
    assert len(ops) >= 3       # the chains mix kinds (not a let and a direct output only)
    rng = np.random.default_rng(seed)
    lo = np.array([s.lo for s in model.signals])
    hi = np.array([s.hi for s in model.signals])
    fin = np.array([io_frac(s.lo, s.hi, "q15") for s in model.signals])
    # inputs on the q15 grid, inside the ranges (where the fixed point's bound holds)
    xq = np.round((lo + (hi - lo) * rng.uniform(0, 1, (N_STEPS, BATCH, len(lo)))) * 2.0 ** fin)
    x = xq / 2.0 ** fin
    names = [o.name for o in model.outputs]
    span = np.array([o.hi - o.lo for o in model.outputs])

    def run(controller) -> np.ndarray:
        """(steps, batch, outputs)"""
        rows = []
        for k in range(N_STEPS):
            y = controller.step({s.name: x[k, :, i] for i, s in enumerate(model.signals)})
            rows.append(np.stack([y[n] for n in names], axis=1))
        return np.array(rows)
    expected = run(Controller(model, BATCH))
    assert np.all(np.isfinite(expected))
    # C: double is the engine's arithmetic; float rounds each operation to 6e-8 relative
    for numeric, tolerance in (("double", 1e-12), ("float", 1e-4)):
        error = np.abs(run(CController(model, BATCH, numeric)) - expected)
        assert np.all(error <= tolerance * (span + np.abs(expected))), (numeric, error.max())
    # q15: within the derived bound (a fraction of the range) where it is derived
    frac = np.array([io_frac(o.lo, o.hi, "q15") for o in model.outputs])
    got = chain_runner(model, "q15", batch=BATCH)(xq) / 2.0 ** frac
    bound = np.array(list(chain_error_bound(model, "q15", N_STEPS).values()))
    derived = np.isfinite(bound)
    assert np.all(np.abs(got - expected)[..., derived] <= bound[derived] * span[derived])
    # sets: point boxes contain the float trace (up to the float64 rounding of the forms)
    low, high = set_trace(model, x, 0.0, BATCH)
    slack = 1e-9 * (1 + np.abs(expected))
    assert np.all(low - slack <= expected) and np.all(expected <= high + slack)
