"""q15 / q31 rule bases against the engine: within the stated bound (`ERROR_BOUND`, a fraction
of each output's range) on >= 100,000 random inputs plus every edge, for the engine evaluated
at the dequantized input (and clipped to the output's range, as the C saturates there); the
whole chain (q15/q31 step) against the Controller over 10,000 steps within
`CHAIN_ERROR_BOUND`.  Compiled with the strict flags (-Werror).  All four paper rule bases:
the corner controller's `*` rules and the milling controller's weighted sum included."""
from __future__ import annotations

import copy
import ctypes

import numpy as np
import pytest
import sympy

from fuzzyc.backends.c_fixed.header import (CHAIN_ERROR_BOUND, ERROR_BOUND, FORMATS,
                                     chain_error_bound, derived_error_bound,
                                     generate_fixed_header, io_frac)
from fuzzyc.backends.c_fixed.chain import const_error, drop_error
from fuzzyc.backends.c.load import compile_shared
from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.semantics.model import Aggregation, Connective, Defuzzifier, TNorm, set_entries

from fuzzyc.language.parser import load

from test_c_backend import ROOT, inputs_for, shipped, variant

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

def milling_weighted():
    """The milling controller with rule weights in [0.5, 2]: sum_j w_j mu_j z_j then leaves
    [-50, 50] (up to 2 x 40), so the saturation is exercised too."""
    model = shipped("milling_neurofuzzy")
    model.rulebase.weights = np.random.default_rng(3).uniform(0.5, 2.0, model.rulebase.n_rules)
    return model


def corner_catch_all():
    """The corner controller with rule 27 as `* * * -> M`: it fires 1 at every input, and
    every input gets its third (`*`) slot: 27 slot combinations per sample."""
    model = copy.deepcopy(shipped("wedm_corner"))
    set_entries(model.rulebase, "antecedents", 26, -1)
    return model


CASES = {
    "wedm_three_region": lambda: shipped("wedm_three_region"),
    "edm_sink_gap": lambda: shipped("edm_sink_gap"),
    "wedm_corner": lambda: shipped("wedm_corner"),
    "milling_neurofuzzy": lambda: shipped("milling_neurofuzzy"),
    # `*` rules under product and sum: a rule met twice per sample would show here
    "corner_product_sum": lambda: variant("wedm_corner", and_=TNorm.PRODUCT,
                                          aggregation=Aggregation.SUM),
    "milling_weighted": milling_weighted,
    "corner_catch_all": corner_catch_all,
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
    expected = np.clip(evaluate(rb, lo + np.clip(xq, 0, full) / full * (hi - lo)),
                       out_lo, out_lo + span)
    error = np.abs(out_lo + yq / full * span - expected) / span
    assert error.max() <= ERROR_BOUND[numeric]
    # The derived worst case holds too (it is looser: it assumes every rounding at its worst).
    derived = derived_error_bound(model, numeric)
    assert np.all(error.max(axis=0) <= derived)
    assert np.all((yq >= 0) & (yq <= full))


@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_stated_bound_is_derived_for_the_paper_rule_bases(numeric):
    # With the inputs' pieces at 2^-GI of an LSB and memberships rounded to nearest, the
    # derived worst case of every paper rule base lies within ERROR_BOUND, so the stated bound
    # holds for every input, not only the sampled ones.  (The product / sum variants count
    # every rule met per sample and stay looser: corner_product_sum q15 4.9e-3.)
    for name in ("wedm_three_region", "edm_sink_gap", "wedm_corner", "milling_neurofuzzy"):
        assert np.all(derived_error_bound(shipped(name), numeric) <= ERROR_BOUND[numeric]), name


def test_q15_hand_computed_point():
    # e1 = 1, e2 = 0.25, ce2 = 0 (see test_c_backend): du1 = du2 = 0.25, i.e. at 0.625 of
    # [-1, 1]: 0.625 * 32767 = 20479.4 -> 20479 (+- 1 LSB of rounding).
    run = fixed_point_runner(shipped("wedm_three_region"), "q15")
    xq = [[32767, round(0.625 * 32767), round(0.5 * 32767)]]
    assert np.all(np.abs(run(xq) - 20479) <= 1)


def test_saturation_is_exercised():
    # the weighted milling variant's engine output leaves [-50, 50], the C holds it at 0/FULL
    model = milling_weighted()
    rb = model.rulebase
    x = inputs_for(rb)
    y = evaluate(rb, x[np.all(np.isfinite(x), axis=1)])
    assert y.min() < -50 and y.max() > 50


def test_q15_corner_wildcard_hand_computed():
    # Corner controller: feedrate 20 (VS = 1: the shoulder's top reaches 40), thickness 35
    # (S = B = 0.5), angle 43.125 deg (S = (82.5 - 43.125) / 52.5 = 0.75, M = 0.25).  Only
    # rules 1 (VS * S -> S = 15) and 2 (VS * M -> VS = 5) fire, `*` = 1:
    # min(1, 1, 0.75) = 0.75 and min(1, 1, 0.25) = 0.25, y = (0.75 * 15 + 0.25 * 5) / 1 = 12.5,
    # yq = 12.5 / 100 * 32767 = 4095.9 -> 4096 (the quantized angle 7850 / 32767 * 180 =
    # 43.1226 gives 12.5005 -> 4096.04).  Were `*` min-ed with thickness's 0.5 instead, rule
    # 1 would fire 0.5: y = (0.5 * 15 + 0.25 * 5) / 0.75 = 11.67 -> 3823.
    xq = [[round(20 / 250 * 32767), round(35 / 100 * 32767), round(43.125 / 180 * 32767)]]
    assert xq == [[2621, 11468, 7850]]
    for numeric, full in (("q15", 32767), ("q31", 2 ** 31 - 1)):
        run = fixed_point_runner(shipped("wedm_corner"), numeric)
        scaled = np.array(xq) * full // 32767   # the same points on the q31 grid (to 1 LSB)
        assert abs(run(scaled)[0, 0] / full * 100 - 12.5) <= 1.5 / 32767 * 100


def test_q15_milling_weighted_sum_hand_computed():
    # Milling: every peak 0 but z(e ZE, cf ZE) = 40 (rule 3 * 7 + 3 = 24) and
    # z(e PS, cf ZE) = 30 (rule 31) with weight 0.5.  e = 1/6: ZE = PS = 0.5; cf = 0: ZE = 1.
    # du = 0.5 * 1 * 40 + 0.5 * (0.5 * 1) * 30 = 27.5 -- not normalised (a weighted average
    # would give 27.5 / 0.75 = 36.7); yq = (27.5 + 50) / 100 * 32767 = 25394.4.  On the grid:
    # e at 19114 is 19114 / 32767 * 2 - 1 = 0.1666616 (ZE 0.5000153, PS 0.4999847), cf at
    # 16384 is 3.05e-5 (ZE 0.9999085), so the engine gives 0.9999085 * (0.5000153 * 40 +
    # 0.5 * 0.4999847 * 30) = 0.9999085 * 27.50038 = 27.4979 -> 25393.7; C within 1 LSB.
    model = shipped("milling_neurofuzzy")
    rb = model.rulebase
    set_entries(rb.outputs[0], "params", np.s_[:, 0], 0.0)
    set_entries(rb.outputs[0], "params", np.s_[[24, 31], 0], [40.0, 30.0])
    set_entries(rb, "weights", 31, 0.5)
    xq = [[round((1 / 6 + 1) / 2 * 32767), round(32767 / 2)]]
    assert xq == [[19114, 16384]]
    assert abs(int(fixed_point_runner(model, "q15")(xq)[0, 0]) - 25394) <= 1
    expected = evaluate(rb, np.array(xq) / 32767 * 2 - 1)[0, 0]
    assert abs(expected - 27.4979) < 1e-4


@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_untrained_milling_gives_zero(numeric):
    # all 49 weights 0 (the shipped file): du = 0 everywhere, the middle of [-50, 50]
    model = load(ROOT / "rulebases" / "milling_neurofuzzy.fz")
    _, full, _ = FORMATS[numeric]
    yq = fixed_point_runner(model, numeric)([[0, 0], [full, full], [full // 3, full // 2]])
    assert np.all(np.abs(yq - full / 2) <= 0.5)


def test_rules_beyond_plain_and_are_a_diagnostic():
    model = copy.deepcopy(shipped("wedm_corner"))
    set_entries(model.rulebase, "connective", 3, Connective.OR)
    with pytest.raises(FuzzycError, match="plain AND"):
        generate_fixed_header(model, "q15")


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


def chain_errors(model) -> dict[str, np.ndarray]:
    """The largest error of each output, as a fraction of its range, of the q15 and q31 chains
    against the engine's Controller over 10,000 steps of random walks over the inputs' ranges
    (on the q15 grid, which q31 holds exactly too; the Controller fed the same dequantized
    inputs); checks first that the walk exercises the outputs."""
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
    # The outputs really move (not a saturated constant compared with itself), and at least
    # 10 % of the samples lie strictly inside the output's range (an integrator at its limit
    # forgets its error: milling's random-weight du drives the feed there 88 % of the time).
    assert np.all(expected.max(axis=(0, 1)) - expected.min(axis=(0, 1)) > 0.05 * span)
    out_lo = np.array([o.lo for o in model.outputs])
    inside = (expected > out_lo) & (expected < out_lo + span)
    assert np.all(inside.mean(axis=(0, 1)) >= 0.1)
    errors = {}
    for numeric in sorted(FORMATS):
        shift = np.array([io_frac(s.lo, s.hi, numeric) for s in model.signals]) - in_frac
        out_frac = np.array([io_frac(o.lo, o.hi, numeric) for o in model.outputs])
        got = chain_runner(model, numeric)(xq * 2.0 ** shift) / 2.0 ** out_frac
        errors[numeric] = (np.abs(got - expected) / span).max(axis=(0, 1))
    return errors


@pytest.mark.parametrize("name", ["wedm_three_region", "edm_sink_gap", "wedm_corner",
                                  "milling_neurofuzzy", "fopdt_pi"])
def test_fixed_point_chain_follows_the_controller(name):
    # every output within CHAIN_ERROR_BOUND of its range, for q15 and q31, and within the
    # bound derived from the rounding of every operation (no output is 'not derived' on the
    # paper chains)
    model = shipped(name)
    for numeric, error in chain_errors(model).items():
        assert error.max() <= CHAIN_ERROR_BOUND[numeric], numeric
        derived = np.array(list(chain_error_bound(model, numeric, CHAIN_STEPS).values()))
        assert np.all(np.isfinite(derived)) and np.all(error <= derived), \
            (numeric, error, derived)


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


def test_q15_chain_hand_computed_corner_and_milling():
    # Corner, first sample: the low-pass starts at the feed itself, so feedrate = 20 (in = 20 *
    # 2^7 = 2560), thickness 35 (35 * 2^8 = 8960), angle 43.125 (43.125 * 2^7 = 5520): the
    # rule-base point of test_q15_corner_wildcard_hand_computed, y = 12.5 %, reduction =
    # y * like 1 = 12.5, out = 12.5 * 2^8 = 3200.
    corner = chain_runner(shipped("wedm_corner"), "q15", batch=1)
    assert abs(int(corner([[[2560, 8960, 5520]]])[0, 0, 0]) - 3200) <= 1
    # Milling with every peak 0 but z(e ZE, cf ZE) = 20: force 300 N = Fr (in = 300 * 2^4 =
    # 4800), first delta 0: e = cf = 0, only rule 24 fires, with 1 * 1: du = 20, feed = 0 +
    # du * GU 0.1 = 2 mm/min, out = 2 * 2^8 = 512; held for a second sample, 4 mm/min = 1024.
    model = shipped("milling_neurofuzzy")
    set_entries(model.rulebase.outputs[0], "params", np.s_[:, 0], 0.0)
    set_entries(model.rulebase.outputs[0], "params", np.s_[24, 0], 20.0)
    milling = chain_runner(model, "q15", batch=1)
    out = milling([[[4800]], [[4800]]])[:, 0, 0]
    assert np.all(np.abs(out - [512, 1024]) <= 1)


def test_q15_chain_with_parameter_powers_hand_computed():
    # fopdt_pi: e = clamp((r - y) / GE) and ce = clamp(-delta(y) / GCE) divide by parameters,
    # which the header holds as constants.  y = 0.5 (in = 0.5 * 2^11 = 1024; y in [-10, 10]
    # has 11 fraction bits), r = 1, GE = 1: e = 0.5, halfway between Z and P; first delta 0:
    # ce = 0 (Z).  Product: (Z, Z) -> ZO = 0 and (P, Z) -> PS = 0.5 fire at 0.5 each; center
    # of area du = (0.5 * 0 + 0.5 * 0.5) / 1 = 0.25; u = 0 + du * GU 0.1 = 0.025, out = 0.025 *
    # 2^11 = 51.2 -> 51; y held, a second 0.025: 0.05 * 2^11 = 102.4 -> 102.
    fopdt = chain_runner(shipped("fopdt_pi"), "q15", batch=1)
    assert np.all(np.abs(fopdt([[[1024]], [[1024]]])[:, 0, 0] - [51, 102]) <= 1)
    # with GE = 0 the division has no value: a diagnostic naming it, not a header
    model = copy.deepcopy(shipped("fopdt_pi"))
    model.params["GE"].value = 0.0
    with pytest.raises(FuzzycError, match="`1/GE` in `let e` is not a finite real number"):
        generate_fixed_header(model, "q15")


def test_chain_rounding_errors_by_hand():
    # 0.1 at 4 fraction bits is round(1.6) = 2, 2/16 = 0.125: off by 0.025
    assert const_error(0.1, 4) == pytest.approx(0.025)
    # 10 -> 4 fraction bits rounds to nearest: half the new LSB, 0.5/16; adding bits is exact
    assert drop_error(10, 4) == 0.03125 and drop_error(4, 10) == 0.0


@pytest.mark.parametrize("numeric", sorted(FORMATS))
def test_derived_chain_bound_grows_with_the_run_only_through_integrators(numeric):
    # EDM sinking's velocity is a direct output (a low-pass and a delta before the rule
    # base): its bound does not depend on the run length.  Milling's feed integrates du:
    # init rounding + N x the increment's error, linear in N.
    edm = shipped("edm_sink_gap")
    assert chain_error_bound(edm, numeric, 1) == chain_error_bound(edm, numeric, 10_000)
    milling = shipped("milling_neurofuzzy")
    e1, e2, e3 = (chain_error_bound(milling, numeric, n)["feed"] for n in (1, 2, 3))
    assert e1 < e2 < e3 and e3 - e2 == pytest.approx(e2 - e1, rel=1e-9)


def test_helper_template_compiles_alone_and_each_header_holds_it():
    # fixed_helpers.c is C (strict flags, the macros a header defines given on the command
    # line), and a header holds its text under the header's own prefixes
    from importlib import resources
    template = resources.files("fuzzyc").joinpath("backends/c_fixed/fixed_helpers.c").read_text()
    for numeric, (_, _, mf) in FORMATS.items():
        compile_shared({"helpers.c": template}, "helpers.c",
                       (f"-DFUZZYC_FX_ONE={1 << mf}", f"-DFUZZYC_FX_MF={mf}"))
        header = generate_fixed_header(shipped("wedm_corner"), numeric)
        pasted = template.split("/* -- section: helpers -- */\n", 1)[1]
        assert pasted.replace("fuzzyc_fx_", f"wedm_corner_{numeric}_").replace(
            "FUZZYC_FX_", f"WEDM_CORNER_{numeric.upper()}_") in header
        assert f"#define WEDM_CORNER_{numeric.upper()}_MF {mf}\n" in header


def test_several_fixed_headers_share_a_translation_unit():
    # every helper is named with the header's prefix: q15 and q31 of one controller and a
    # second controller compile together
    headers = {f"{name}_{numeric}.h": generate_fixed_header(shipped(name), numeric)
               for name in ("wedm_corner", "edm_sink_gap") for numeric in FORMATS}
    unit = "".join(f'#include "{h}"\n' for h in headers)
    compile_shared({**headers, "unit.c": unit}, "unit.c")
