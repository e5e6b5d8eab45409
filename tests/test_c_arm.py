"""The generated C on a controller's CPU, run under QEMU: every shipped rule base's header with
its batch shim compiled by arm-none-eabi-gcc for the Cortex-M it targets (float: Cortex-M4F,
-mfloat-abi=hard -mfpu=fpv4-sp-d16; q15/q31: Cortex-M0, Thumb-1 only; -Os and the strict
flags, `c_arm.CORTEX_M`), partially linked with that CPU's libgcc (the M0's 64-bit multiply and
divide helpers, the M4F's software doubles), then linked into a static ARM Linux program
(arm-linux-gnueabihf-gcc: the reading and writing of the data) and run by qemu-arm, whose ARMv7
CPU executes the Cortex-M instructions unchanged.  The object's .ARM.attributes section goes
(the linker refuses to mix M- and A-profile objects by those tags alone; the interfaces pass
only pointers, and the M4F's hard-float calling convention is the program's).  Against the
x86-64 build and the engine: q15/q31 bit-exact with x86-64 (the bare rule base on random
inputs and every edge, the whole chain over 10,000 steps); float within the stated tolerances
of the engine (FLOAT_TOLERANCE of each output's range for the rule base, CHAIN_TOLERANCE for
the chain).  Skipped, each test with its reason, without the cross tools (Debian:
gcc-arm-none-eabi, libnewlib-arm-none-eabi, gcc-arm-linux-gnueabihf, qemu-user).
Debian's qemu-arm 7.2 cannot load an M-profile program itself (it aborts mapping its commpage),
hence the A-profile wrapper."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.backends.c.arm import CORTEX_M, TOOLCHAIN
from fuzzyc.backends.c_fixed.header import FORMATS, generate_fixed_header, io_frac
from fuzzyc.backends.c.load import STRICT_FLAGS, controller_sources
from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate

from test_c_backend import FLOAT_TOLERANCE, SHIPPED, inputs_for, shipped
from test_c_chain import BATCH, CHAIN_TOLERANCE, N_STEPS, random_sequences, run_chain
from test_c_fixed import CHAIN_SHIM, SHIM, chain_runner, fixed_point_runner

CROSS, QEMU = "arm-linux-gnueabihf-gcc", "qemu-arm"
TOOLS = (f"{TOOLCHAIN}gcc", f"{TOOLCHAIN}ld", f"{TOOLCHAIN}objcopy", CROSS, QEMU)
# every file of rulebases/ (the untrained milling one with test weights, see `shipped`)
ON_ARM = SHIPPED + ["milling_neurofuzzy_learned", "fopdt_pi"]
pytestmark = pytest.mark.skipif(
    any(shutil.which(tool) is None for tool in TOOLS),
    reason=f"needs {', '.join(TOOLS)} (Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi, "
           "gcc-arm-linux-gnueabihf, qemu-user)")

# Reads n x `inputs` values, calls CALL, writes n x `outputs` values (binary, the host's byte
# order: both are little-endian).
MAIN = """\
#include <stdio.h>
#include <stdlib.h>
typedef {value} value;
{declarations}
int main(int argc, char **argv) {{
    long n = atol(argv[1]), n_in = atol(argv[2]), n_out = atol(argv[3]);
    value *x = malloc((size_t)(n * n_in) * sizeof *x), *y = malloc((size_t)(n * n_out) * sizeof *y);
    FILE *f = fopen(argv[4], "rb");
    if (argc != 6 || !x || !y || !f || fread(x, sizeof *x, (size_t)(n * n_in), f) != (size_t)(n * n_in)) return 1;
    fclose(f);
    {call};
    f = fopen(argv[5], "wb");
    if (!f || fwrite(y, sizeof *y, (size_t)(n * n_out), f) != (size_t)(n * n_out)) return 1;
    return fclose(f) != 0;
}}
"""


def build_for_cortex_m(tmp: Path, numeric: str) -> Path:
    """shim.c (which includes the header) compiled for the Cortex-M of `numeric`, with the
    libgcc helpers it calls from that CPU's multilib, attributes dropped."""
    flags = CORTEX_M[numeric][1]
    gcc = f"{TOOLCHAIN}gcc"
    libgcc = subprocess.run([gcc, *flags, "-print-libgcc-file-name"], check=True,
                            capture_output=True, text=True).stdout.strip()
    for cmd in ([gcc, *STRICT_FLAGS, *flags, "-c", "-o", "shim.o", "shim.c"],
                [f"{TOOLCHAIN}ld", "-r", "-o", "cortex_m.o", "shim.o", libgcc],
                [f"{TOOLCHAIN}objcopy", "-R", ".ARM.attributes", "cortex_m.o"]):
        subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=tmp)
    return tmp / "cortex_m.o"


def run_on_arm(tmp: Path, numeric: str, sources: dict[str, str], value: str,
               declarations: str, call: str, x: np.ndarray, n_out: int) -> np.ndarray:
    """Build sources (shim.c and the header) for the Cortex-M of `numeric` and MAIN around it,
    run it under QEMU on x (n, n_in), return (n, n_out)."""
    for name, text in sources.items():
        (tmp / name).write_text(text)
    (tmp / "main.c").write_text(MAIN.format(value=value, declarations=declarations, call=call))
    exe = tmp / "arm.elf"
    subprocess.run([CROSS, *STRICT_FLAGS, "-static", "-Wl,-z,noexecstack", "-o", str(exe),
                    str(tmp / "main.c"), str(build_for_cortex_m(tmp, numeric)), "-lm"],
                   check=True, capture_output=True, text=True)
    dtype = np.int64 if value == "long long" else np.float64
    x = np.ascontiguousarray(x, dtype=dtype)
    x.tofile(tmp / "in.bin")
    subprocess.run([QEMU, str(exe), str(len(x)), str(x.shape[1]), str(n_out),
                    str(tmp / "in.bin"), str(tmp / "out.bin")], check=True)
    return np.fromfile(tmp / "out.bin", dtype=dtype).reshape(len(x), n_out)


def grid_inputs(rb, numeric):
    lo = np.array([v.lo for v in rb.inputs])
    hi = np.array([v.hi for v in rb.inputs])
    x = inputs_for(rb, n_random=20_000)
    x = x[np.all(np.isfinite(x), axis=1)]
    full = FORMATS[numeric][1]
    return np.concatenate([np.round((x - lo) / (hi - lo) * full).astype(np.int64),
                           [[-100] * len(lo), [full + 100] * len(lo)]])


@pytest.mark.parametrize("numeric", sorted(FORMATS))
@pytest.mark.parametrize("name", ON_ARM)
def test_fixed_point_rule_base_is_bit_exact_on_arm(name, numeric, tmp_path):
    model = shipped(name)
    rb = model.rulebase
    xq = grid_inputs(rb, numeric)
    shim = SHIM.format(io=FORMATS[numeric][0], n_in=len(rb.inputs), n_out=len(rb.outputs),
                       name=model.name, numeric=numeric)
    got = run_on_arm(tmp_path, numeric, {"fixed.h": generate_fixed_header(model, numeric), "shim.c": shim},
                     "long long", "void run(int n, const long long *x, long long *y);",
                     "run((int)n, x, y)", xq, len(rb.outputs))
    np.testing.assert_array_equal(got, fixed_point_runner(model, numeric)(xq))


@pytest.mark.parametrize("numeric", sorted(FORMATS))
@pytest.mark.parametrize("name", ON_ARM)
def test_fixed_point_chain_is_bit_exact_on_arm(name, numeric, tmp_path):
    model = shipped(name)
    x = random_sequences(model, seed=3)
    x = np.where(np.isfinite(x), x, 0.0)                 # integers have no NaN or infinity
    frac = np.array([io_frac(s.lo, s.hi, numeric) for s in model.signals])
    io_max = FORMATS[numeric][1]
    xq = np.clip(np.round(x * 2.0 ** frac), -io_max, io_max).astype(np.int64)
    shim = CHAIN_SHIM.format(p=f"{model.name}_{numeric}_", batch=BATCH, io=FORMATS[numeric][0],
                             ns=len(model.signals), no=len(model.outputs))
    flat = xq.reshape(N_STEPS * BATCH, -1)
    got = run_on_arm(tmp_path, numeric, {"fixed.h": generate_fixed_header(model, numeric), "shim.c": shim},
                     "long long", "void run(int steps, int batch, const long long *x, "
                     "long long *y);", f"run((int)n / {BATCH}, {BATCH}, x, y)", flat,
                     len(model.outputs))
    expected = chain_runner(model, numeric)(xq)
    np.testing.assert_array_equal(got.reshape(expected.shape), expected)
    assert len(np.unique(expected)) > 100                 # the outputs move


FLOAT_DECLARATIONS = """\
int fz_state_size(void);
void fz_init(void *s, int n);
void fz_step(void *s, int n, const double *in, double *out);
void fz_rulebase(int n, const double *in, double *out);"""


@pytest.mark.parametrize("name", ON_ARM)
def test_float_rule_base_on_arm_within_tolerance(name, tmp_path):
    model = shipped(name)
    rb = model.rulebase
    x = inputs_for(rb, n_random=20_000)
    got = run_on_arm(tmp_path, "float", controller_sources(model, "float"), "double",
                     FLOAT_DECLARATIONS, "fz_rulebase((int)n, x, y)", x, len(rb.outputs))
    span = np.array([v.hi - v.lo for v in rb.outputs])
    assert np.all(np.abs(got - evaluate(rb, x)) / span <= FLOAT_TOLERANCE)


@pytest.mark.parametrize("name", ON_ARM)
def test_float_chain_on_arm_within_tolerance(name, tmp_path):
    model = shipped(name)
    x = random_sequences(model, seed=len(name))
    call = (f"{{ void *s = malloc((size_t)fz_state_size() * {BATCH}); long k; "
            f"fz_init(s, {BATCH}); for (k = 0; k < n / {BATCH}; ++k) "
            f"fz_step(s, {BATCH}, x + k * {BATCH} * n_in, y + k * {BATCH} * n_out); }}")
    got = run_on_arm(tmp_path, "float", controller_sources(model, "float"), "double",
                     FLOAT_DECLARATIONS, call, x.reshape(N_STEPS * BATCH, -1),
                     len(model.outputs)).reshape(N_STEPS, BATCH, -1)
    expected = run_chain(Controller(model, BATCH), model, x)
    span = np.array([o.hi - o.lo for o in model.outputs])
    assert np.all(np.isfinite(got))
    assert (np.abs(got - expected) / span).max() <= CHAIN_TOLERANCE["float"]


@pytest.mark.parametrize("numeric", sorted(FORMATS))
@pytest.mark.parametrize("case", ["7 inputs with *", "9 inputs of 4 terms"])
def test_wide_fixed_point_rule_base_is_bit_exact_on_arm(case, numeric, tmp_path):
    # the cell table indexed directly (7 inputs, `*` on the last) and by binary search among
    # 32-bit codes (9 inputs of 4 terms: 4**9 codes, unsigned long is 32 bits on the M0 and
    # 64 on x86-64)
    from test_c_fixed_wide import CASES, grid_points
    model = CASES[case].build()
    rb = model.rulebase
    xq = np.concatenate([grid_points(model, numeric, 2_000), [[-100] * len(rb.inputs)]])
    shim = SHIM.format(io=FORMATS[numeric][0], n_in=len(rb.inputs), n_out=len(rb.outputs),
                       name=model.name, numeric=numeric)
    got = run_on_arm(tmp_path, numeric, {"fixed.h": generate_fixed_header(model, numeric),
                                         "shim.c": shim},
                     "long long", "void run(int n, const long long *x, long long *y);",
                     "run((int)n, x, y)", xq, len(rb.outputs))
    np.testing.assert_array_equal(got, fixed_point_runner(model, numeric)(xq))
