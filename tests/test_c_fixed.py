"""q15 / q31 rule bases against the engine: within the stated bound (`ERROR_BOUND`, a fraction
of each output's range) on >= 100,000 random inputs plus every edge, for the engine evaluated
at the dequantized input.  Compiled with the strict flags (-Werror)."""
from __future__ import annotations

import ctypes

import numpy as np
import pytest

from fuzzyc.backends.c_fixed import ERROR_BOUND, FORMATS, generate_fixed_header
from fuzzyc.backends.cload import compile_shared
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
