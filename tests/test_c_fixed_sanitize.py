"""The q15 / q31 headers under AddressSanitizer + UndefinedBehaviorSanitizer: the int64
arithmetic of every case of test_c_fixed (guard bits, weighted sums, `*` slots) must not
overflow or index out of bounds anywhere, including I/O integers far outside the scale (the
whole int16/int32 range), and the sanitized program gives the same integers as the plain one."""
from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from fuzzyc.backends.c_fixed.header import FORMATS, generate_fixed_header
from fuzzyc.backends.c.load import STRICT_FLAGS

from test_c_backend import inputs_for
from test_c_fixed import CASES, fixed_point_runner

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")

SANITIZE = ("-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-g")


@pytest.fixture(scope="module", autouse=True)
def sanitizers_work(tmp_path_factory):
    """gcc without its sanitizer runtimes (libasan, libubsan), or a sandbox where ASan cannot
    map its shadow memory, is a machine limit, not a defect of the header: skip there."""
    folder = tmp_path_factory.mktemp("probe")
    (folder / "probe.c").write_text("int main(void) { return 0; }\n")
    built = subprocess.run(["gcc", *SANITIZE, str(folder / "probe.c"), "-o",
                            str(folder / "probe")], capture_output=True, text=True)
    if built.returncode != 0:
        pytest.skip(f"gcc cannot build with sanitizers: {built.stderr.strip()[:200]}")
    ran = subprocess.run([str(folder / "probe")], capture_output=True, text=True, timeout=60)
    if ran.returncode != 0:
        pytest.skip(f"sanitized programs cannot run here: {ran.stderr.strip()[:200]}")

MAIN = """\
#include <stdio.h>
#include "fixed.h"
/* stdin: "r" then rows of rule-base inputs, or "s" then rows of chain inputs; one row out
   per row in. */
int main(void) {{
    char mode = 0;
    long long v;
    int k;
    {p}state s;
    if (scanf(" %c", &mode) != 1) return 2;
    {p}init(&s);
    for (;;) {{
        {io} xq[{n_in}], yq[{n_out}], in[{ns}], out[{no}];
        int n = mode == 'r' ? {n_in} : {ns};
        for (k = 0; k < n; ++k) {{
            if (scanf("%lld", &v) != 1) return 0;
            if (mode == 'r') xq[k] = ({io})v; else in[k] = ({io})v;
        }}
        if (mode == 'r') {{
            {p}rulebase(xq, yq);
            for (k = 0; k < {n_out}; ++k) printf("%lld ", (long long)yq[k]);
        }} else {{
            {p}step(&s, in, out);
            for (k = 0; k < {no}; ++k) printf("%lld ", (long long)out[k]);
        }}
        printf("\\n");
    }}
}}
"""


def build(model, numeric, folder):
    io = FORMATS[numeric][0]
    (folder / "fixed.h").write_text(generate_fixed_header(model, numeric))
    (folder / "main.c").write_text(MAIN.format(
        p=f"{model.name}_{numeric}_", io=io, n_in=len(model.rulebase.inputs),
        n_out=len(model.rulebase.outputs), ns=len(model.signals), no=len(model.outputs)))
    program = folder / "program"
    subprocess.run(["gcc", *STRICT_FLAGS, *SANITIZE, "-I", str(folder), str(folder / "main.c"),
                    "-o", str(program)], check=True, capture_output=True, text=True)
    return program


def run(program, mode: str, rows: np.ndarray) -> np.ndarray:
    text = mode + "\n" + "\n".join(" ".join(str(int(v)) for v in row) for row in rows) + "\n"
    result = subprocess.run([str(program)], input=text, capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0 and result.stderr == "", result.stderr[:2000]
    return np.array([[int(v) for v in line.split()] for line in result.stdout.splitlines()])


@pytest.mark.parametrize("numeric", sorted(FORMATS))
@pytest.mark.parametrize("case", sorted(CASES))
def test_fixed_point_clean_under_sanitizers(case, numeric, tmp_path):
    model = CASES[case]()
    rb = model.rulebase
    _, full, _ = FORMATS[numeric]
    lo = np.array([v.lo for v in rb.inputs])
    hi = np.array([v.hi for v in rb.inputs])
    x = inputs_for(rb, seed=5, n_random=2000)
    x = x[np.all(np.isfinite(x), axis=1)]
    xq = np.clip(np.round((x - lo) / (hi - lo) * full), 0, full).astype(np.int64)
    # the extremes of the I/O type, saturated on entry
    extreme = np.array([[-full - 1] * len(lo), [full] * len(lo), [-1] * len(lo)])
    xq = np.concatenate([xq, extreme])
    program = build(model, numeric, tmp_path)
    np.testing.assert_array_equal(run(program, "r", xq), fixed_point_runner(model, numeric)(xq))
    # the chain: 2000 steps of integers over the whole I/O type, every signal out of range too
    rng = np.random.default_rng(6)
    seq = rng.integers(-full - 1, full, (2000, len(model.signals)), endpoint=True)
    seq[::50] = -full - 1
    seq[25::50] = full
    out = run(program, "s", seq)
    assert out.shape == (2000, len(model.outputs))
    assert np.all(np.abs(out) <= full)
