"""q15 / q31 rule bases against the engine: within the stated bound (`ERROR_BOUND`, a fraction
of each output's range) on >= 100,000 random inputs plus every edge, for the engine evaluated
at the dequantized input; the whole chain (q15/q31 step) against the Controller over 10,000
steps within `CHAIN_ERROR_BOUND`.  Compiled with the strict flags (-Werror)."""
from __future__ import annotations

import copy
import ctypes

import numpy as np
import pytest
import sympy

from fuzzyc.backends.c_fixed import (CHAIN_ERROR_BOUND, ERROR_BOUND, FORMATS,
                                     derived_error_bound, generate_fixed_header, io_frac)
from fuzzyc.backends.cload import compile_shared
from fuzzyc.controller import Controller
from fuzzyc.engine import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.model import Defuzzifier, TNorm

from test_c_backend import inputs_for, shipped, variant

SHIM = """\
#include "fixed.h"
void run(int n, const long long *x, long long *y) {{
    int b, k;
    for (b = 0; b < n; ++b) {{
        {io} xq[{n_in}], yq[{n_out}];
        for (k = 0; k < {n_in}; ++k) xq[k] = ({io})x[b * {n_in} + k];
        {name}_{numeric}_rulebase(xq, yq);
        for (k = 0; k < {n_out}; ++k) y[b * {n_out} + k] = yq[k];
    }}
}}
"""

CASES = {
    "wedm_three_region": lambda: shipped("wedm_three_region"),
    "edm_sink_gap": lambda: shipped("edm_sink_gap"),
    "wedm_product": lambda: variant("wedm_three_region", and_=TNorm.PRODUCT),
    "edm_weighted_average": lambda: variant("edm_sink_gap",
                                            defuzzifier=Defuzzifier.WEIGHTED_AVERAGE),
}


def fixed_point_runner(model, numeric):
    rb = model.rulebase
    io, full, _ = FORMATS[numeric]
    shim = SHIM.format(io=io, n_in=len(rb.inputs), n_out=len(rb.outputs), name=model.name,
                       numeric=numeric)
    lib = ctypes.CDLL(str(compile_shared({"fixed.h": generate_fixed_header(model, numeric),
                                          "shim.c": shim}, "shim.c")))
    ptr = ctypes.POINTER(ctypes.c_longlong)
    lib.run.argtypes = [ctypes.c_int, ptr, ptr]

    def run(xq: np.ndarray) -> np.ndarray:
        xq = np.ascontiguousarray(xq, dtype=np.int64)
        y = np.empty((len(xq), len(rb.outputs)), dtype=np.int64)
        lib.run(len(xq), xq.ctypes.data_as(ptr), y.ctypes.data_as(ptr))
        return y
    return run


@pytest.mark.parametrize("numeric", sorted(FORMATS))
@pytest.mark.parametrize("case", sorted(CASES))
def test_fixed_point_within_stated_bound(case, numeric):
    model = CASES[case]()
    rb = model.rulebase
    _, full, _ = FORMATS[numeric]
    lo = np.array([v.lo for v in rb.inputs])
    hi = np.array([v.hi for v in rb.inputs])
    x = inputs_for(rb)
    x = x[np.all(np.isfinite(x), axis=1)]        # integers have no NaN or infinity
    xq = np.clip(np.round((x - lo) / (hi - lo) * full), 0, full).astype(np.int64)
    xq = np.concatenate([xq, [[-100] * len(lo)]])   # below the scale: saturated to 0
    yq = fixed_point_runner(model, numeric)(xq)
    out_lo = np.array([v.lo for v in rb.outputs])
    span = np.array([v.hi - v.lo for v in rb.outputs])
    expected = evaluate(rb, lo + np.clip(xq, 0, full) / full * (hi - lo))
    error = np.abs(out_lo + yq / full * span - expected) / span
    assert error.max() <= ERROR_BOUND[numeric]
    # The derived worst case holds too (it is looser: it assumes every rounding at its worst).
    derived = derived_error_bound(model, numeric)
    assert np.all(error.max(axis=0) <= derived)
    assert np.all((yq >= 0) & (yq <= full))


def test_q15_hand_computed_point():
    # e1 = 1, e2 = 0.25, ce2 = 0 (see test_c_backend): du1 = du2 = 0.25, i.e. at 0.625 of
    # [-1, 1]: 0.625 * 32767 = 20479.4 -> 20479 (+- 1 LSB of rounding).
    run = fixed_point_runner(shipped("wedm_three_region"), "q15")
    xq = [[32767, round(0.625 * 32767), round(0.5 * 32767)]]
    assert np.all(np.abs(run(xq) - 20479) <= 1)


def test_weighted_sum_is_a_diagnostic():
    with pytest.raises(FuzzycError, match="weighted_sum"):
        generate_fixed_header(shipped("milling_neurofuzzy"), "q15")


# -- the whole chain in fixed point ------------------------------------------------------------

CHAIN_SHIM = """\
#include "fixed.h"
void run(int steps, int batch, const long long *x, long long *y) {{
    {p}state s[{batch}];
    int k, b, i;
    for (b = 0; b < batch; ++b) {p}init(&s[b]);
    for (k = 0; k < steps; ++k) for (b = 0; b < batch; ++b) {{
        {io} in[{ns}], out[{no}];
        for (i = 0; i < {ns}; ++i) in[i] = ({io})x[(k * batch + b) * {ns} + i];
        {p}step(&s[b], in, out);
        for (i = 0; i < {no}; ++i) y[(k * batch + b) * {no} + i] = out[i];
    }}
}}
"""
CHAIN_STEPS, CHAIN_BATCH = 10_000, 4


def chain_runner(model, numeric, batch=CHAIN_BATCH):
    """Integer in-sequences (steps, batch, signals) -> integer out (steps, batch, outputs)."""
    shim = CHAIN_SHIM.format(p=f"{model.name}_{numeric}_", batch=batch, io=FORMATS[numeric][0],
                             ns=len(model.signals), no=len(model.outputs))
    lib = ctypes.CDLL(str(compile_shared({"fixed.h": generate_fixed_header(model, numeric),
                                          "shim.c": shim}, "shim.c")))
    ptr = ctypes.POINTER(ctypes.c_longlong)
    lib.run.argtypes = [ctypes.c_int, ctypes.c_int, ptr, ptr]

    def run(xq) -> np.ndarray:
        xq = np.ascontiguousarray(xq, dtype=np.int64)
        y = np.empty(xq.shape[:2] + (len(model.outputs),), dtype=np.int64)
        lib.run(xq.shape[0], batch, xq.ctypes.data_as(ptr), y.ctypes.data_as(ptr))
        return y
    return run


@pytest.mark.parametrize("name", ["wedm_three_region", "edm_sink_gap"])
def test_fixed_point_chain_follows_the_controller(name):
    # 10,000 steps of random walks over the inputs' ranges (on the q15 grid, which q31 holds
    # exactly too), the engine's Controller fed the same dequantized inputs; every output
    # within CHAIN_ERROR_BOUND of its range, for q15 and q31.
    model = shipped(name)
    in_frac = np.array([io_frac(s.lo, s.hi, "q15") for s in model.signals])
    lo = np.array([s.lo for s in model.signals])
    hi = np.array([s.hi for s in model.signals])
    rng = np.random.default_rng(1)
    walk = np.cumsum(rng.normal(0.0, 0.006, (CHAIN_STEPS, CHAIN_BATCH, len(lo))), axis=0)
    xq = np.round((lo + (hi - lo) * np.clip(0.5 + walk, 0, 1)) * 2.0 ** in_frac)
    controller, x = Controller(model, CHAIN_BATCH), xq / 2.0 ** in_frac
    expected = np.empty((CHAIN_STEPS, CHAIN_BATCH, len(model.outputs)))
    for k in range(CHAIN_STEPS):
        y = controller.step({s.name: x[k, :, i] for i, s in enumerate(model.signals)})
        expected[k] = np.stack([y[o.name] for o in model.outputs], axis=1)
    span = np.array([o.hi - o.lo for o in model.outputs])
    # The outputs really move (not a saturated constant compared with itself).
    assert np.all(expected.max(axis=(0, 1)) - expected.min(axis=(0, 1)) > 0.05 * span)
    for numeric in sorted(FORMATS):
        shift = np.array([io_frac(s.lo, s.hi, numeric) for s in model.signals]) - in_frac
        out_frac = np.array([io_frac(o.lo, o.hi, numeric) for o in model.outputs])
        got = chain_runner(model, numeric)(xq * 2.0 ** shift) / 2.0 ** out_frac
        assert (np.abs(got - expected) / span).max() <= CHAIN_ERROR_BOUND[numeric], numeric


def test_q15_chain_hand_computed_first_steps():
    # EDM sinking, 70 V held (in = 70 * 2^8 = 17920): e = (70 - 50) / 20 = 1 (PB), first
    # delta 0 so ce = 0 (Z): rule PB, Z -> PB = 0.3, velocity = 0.3 * Vmax 2 = 0.6 mm/s,
    # out = 0.6 * 2^13 = 4915.2 -> 4915.
    edm = chain_runner(shipped("edm_sink_gap"), "q15", batch=1)
    assert abs(int(edm([[[17920]]])[0, 0, 0]) - 4915) <= 1
    # WEDM at the references, spark_freq 30 kHz (30 * 2^7 = 3840), abnormal ratio 0.4
    # (0.4 * 2^14 = 6553.6 -> 6554): e1 = e2 = ce2 = 0, du1 = ZO = 0 (feed stays 0.3 mm/min:
    # 0.3 * 2^13 = 2457.6 -> 2458), du2 = NS = -0.5: 1/t_off = 1/32 - 0.5 * 8e-5 = 0.03121,
    # t_off = 32.041 us, out = 32.041 * 2^9 = 16405.0.
    wedm = chain_runner(shipped("wedm_three_region"), "q15", batch=1)
    feed, t_off = wedm([[[3840, 6554]]])[0, 0]
    assert abs(int(feed) - 2458) <= 1 and abs(int(t_off) - 16405) <= 1


def test_chain_step_without_a_fixed_point_form_is_named():
    model = copy.deepcopy(shipped("edm_sink_gap"))
    step = next(s for s in model.steps if s.name == "e")
    step.expr = sympy.exp(step.expr)
    with pytest.raises(FuzzycError, match="`let e`"):
        generate_fixed_header(model, "q15")
