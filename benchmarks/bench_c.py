"""ns per call of the generated C for each shipped rule base, beside two hand-written C versions
of the WEDM rule base and a batch-1 call of the numpy engine, all in the same run.

The timing loop is inside a C driver (gcc -O2, one translation unit per run): per function,
the median over REPEATS runs (in CPU time, so load from other processes does not count) of
ITERATIONS calls cycling through 4096 random inputs over the
rule base's input ranges; the runs go round-robin over all functions.  Writes benchmarks/results/c.md atomically.

    python3 benchmarks/bench_c.py
"""
from __future__ import annotations

import copy
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one
sys.path.insert(0, str(ROOT / "benchmarks"))

from common import markdown_table, median_seconds, write_result  # noqa: E402
from fuzzyc.backends.c.header import c_identifier, generate_header  # noqa: E402
from fuzzyc.backends.c_fixed.header import FORMATS, generate_fixed_header, io_frac  # noqa: E402
from fuzzyc.errors import FuzzycError  # noqa: E402
from fuzzyc.backends.lut import LookupTable, generate_lut_header  # noqa: E402
from fuzzyc.engine.inference import evaluate  # noqa: E402
from fuzzyc.semantics.model import Defuzzifier, set_entries  # noqa: E402
from fuzzyc.language.parser import load  # noqa: E402

RULEBASES = ["wedm_three_region", "wedm_corner", "milling_neurofuzzy", "edm_sink_gap"]
LUT_RESOLUTION = 33
ITERATIONS = 100_000
REPEATS = 21
FLAGS = ["-std=c99", "-O2"]

DRIVER_HEAD = """\
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
{includes}
#include <stdint.h>
void hand_wedm_all_rules(const float x[3], float y[2]);
void hand_wedm_active_rules(const float x[3], float y[2]);
#define N_POINTS 4096
typedef void (*fn_t)(const float *x, float *y);
static volatile float sink;

static double now_ns(void) {{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);   /* CPU time: another process on the core does not count */
    return (double)t.tv_sec * 1e9 + (double)t.tv_nsec;
}}
static int by_value(const void *a, const void *b) {{
    double d = *(const double *)a - *(const double *)b;
    return (d > 0) - (d < 0);
}}
static float *random_points(int n_in, const float *lo, const float *hi) {{
    float *x = malloc(sizeof(float) * N_POINTS * (size_t)n_in);
    unsigned state = 12345u;
    int k;
    for (k = 0; k < N_POINTS * n_in; ++k) {{
        state = state * 1664525u + 1013904223u;
        x[k] = lo[k % n_in] + (hi[k % n_in] - lo[k % n_in]) * (float)(state >> 8) / 16777216.0f;
    }}
    return x;
}}
#define MAX_ENTRIES 64
typedef struct {{ const char *label; fn_t fn; int n_in; float *x; double times[{repeats}]; }} entry_t;
static entry_t entries[MAX_ENTRIES];
static int n_entries;

static void add(const char *label, fn_t fn, int n_in, const float *lo, const float *hi) {{
    entry_t *e = &entries[n_entries++];
    e->label = label; e->fn = fn; e->n_in = n_in; e->x = random_points(n_in, lo, hi);
}}
/* Round-robin over the functions, so a change of machine load hits all of them alike. */
static void run_all(void) {{
    int r, i, k;
    float y[8];
    for (r = 0; r < {repeats}; ++r)
        for (i = 0; i < n_entries; ++i) {{
            entry_t *e = &entries[i];
            double t0 = now_ns();
            float acc = 0;
            for (k = 0; k < {iterations}; ++k) {{
                e->fn(e->x + (k & (N_POINTS - 1)) * e->n_in, y);
                acc += y[0];
            }}
            sink = acc;
            e->times[r] = (now_ns() - t0) / {iterations};
        }}
    for (i = 0; i < n_entries; ++i) {{
        qsort(entries[i].times, {repeats}, sizeof(double), by_value);
        printf("%s\\t%.2f\\n", entries[i].label, entries[i].times[{repeats} / 2]);
        free(entries[i].x);
    }}
}}
"""


def variant(model, name: str, method: Defuzzifier):
    out = copy.deepcopy(model)
    out.name = f"{model.name}_{name}"
    out.rulebase.inference.defuzzifier = method
    return out


def entries(model):
    """(label, C header name, header text, wrapper code, n_in, lo, hi) for one rule base."""
    rb = model.rulebase
    shipped = rb.inference.defuzzifier
    ins = [(v.lo, v.hi) for v in rb.inputs]
    sig = [(s.lo, s.hi) for s in model.signals]
    out = []

    def rulebase_entry(m, label):
        n = c_identifier(m.name)
        wrap = f"static void run_{n}(const float *x, float *y) {{ {n}_rulebase(x, y); }}"
        out.append((label, f"{n}.h", generate_header(m), wrap, f"run_{n}", ins))

    rulebase_entry(model, f"C float, rule base ({shipped.name.lower()}, as shipped)")
    for method in (Defuzzifier.CENTER_OF_AREA, Defuzzifier.CENTROID):
        if method != shipped:
            rulebase_entry(variant(model, method.name.lower(), method),
                           f"C float, rule base ({method.name.lower()})")
    n = c_identifier(model.name)
    try:
        fixed = generate_fixed_header(model, "q15")
    except FuzzycError:       # a rule base the fixed-point back end does not emit
        fixed = None
    if fixed is not None:
        full = FORMATS["q15"][1]
        scale = ", ".join(f"{full / (b - a)!r}f" for a, b in ins)
        lows = ", ".join(f"{a!r}f" for a, _ in ins)
        wrap = (f"static void q15_{n}(const float *x, float *y) {{\n"
                f"    static const float lo[] = {{{lows}}}, scale[] = {{{scale}}};\n"
                f"    int16_t xq[{len(ins)}], yq[{len(rb.outputs)}]; int k;\n"
                f"    for (k = 0; k < {len(ins)}; ++k) xq[k] = (int16_t)((x[k] - lo[k]) * scale[k]);\n"
                f"    {n}_q15_rulebase(xq, yq);\n"
                f"    y[0] = (float)yq[0];\n}}")
        out.append(("C q15 rule base (incl. float to q15 input conversion)", f"{n}_q15.h",
                    fixed, wrap, f"q15_{n}", ins))
        fracs = ", ".join(f"{float(2 ** io_frac(s.lo, s.hi, 'q15'))!r}f" for s in model.signals)
        wrap = (f"static void q15_step_{n}(const float *x, float *y) {{\n"
                f"    static {n}_q15_state s; static int ready;\n"
                f"    static const float scale[] = {{{fracs}}};\n"
                f"    int16_t in[{len(sig)}], out[{len(model.outputs)}]; int k;\n"
                f"    if (!ready) {{ {n}_q15_init(&s); ready = 1; }}\n"
                f"    for (k = 0; k < {len(sig)}; ++k) in[k] = (int16_t)(x[k] * scale[k]);\n"
                f"    {n}_q15_step(&s, in, out);\n"
                f"    y[0] = (float)out[0];\n}}")
        out.append(("C q15, whole chain step (incl. float to q15 input conversion)", None, None,
                    wrap, f"q15_step_{n}", sig))
    table = LookupTable(rb, LUT_RESOLUTION)
    wrap = f"static void lut_{n}(const float *x, float *y) {{ {n}_lut(x, y); }}"
    out.append((f"C lookup table ({LUT_RESOLUTION} points per input)", f"{n}_lut.h",
                generate_lut_header(model, table, table.measure_error()), wrap, f"lut_{n}",
                ins))
    wrap = (f"static void step_{n}(const float *x, float *y) {{\n"
            f"    static {n}_state s; static int ready;\n"
            f"    if (!ready) {{ {n}_init(&s); ready = 1; }}\n"
            f"    {n}_step(&s, x, y);\n}}")
    out.append(("C float, whole chain step", None, None, wrap, f"step_{n}", sig))
    return out


HAND = ("hand_wedm_all_rules", "hand_wedm_active_rules")
# the hand-written q15 version (hand_wedm_active_rules_q15.c) behind the float-to-q15 input
# conversion the generated q15 entries have: inputs 0..32767 over [-1, 1]
HAND_Q15_WRAP = """\
void hand_wedm_active_rules_q15(const int16_t x[3], int16_t y[2]);
static void q15_hand(const float *x, float *y) {
    static const float lo[] = {-1.0f, -1.0f, -1.0f}, scale[] = {%(scale)s};
    int16_t xq[3], yq[2]; int k;
    for (k = 0; k < 3; ++k) xq[k] = (int16_t)((x[k] - lo[k]) * scale[k]);
    hand_wedm_active_rules_q15(xq, yq);
    y[0] = (float)yq[0];
}
"""


def hand_q15_entry():
    """(label, header, text, wrapper, function, ranges) of the hand-written q15 version."""
    scale = ", ".join(f"{FORMATS['q15'][1] / 2.0!r}f" for _ in range(3))
    return ("hand-written C q15, active rules only (incl. float to q15 input conversion)",
            None, None, HAND_Q15_WRAP % {"scale": scale}, "q15_hand", [(-1.0, 1.0)] * 3)


def run_driver(all_entries, work: Path, repeats: int = REPEATS, iterations: int = ITERATIONS,
               hand: tuple[str, ...] = HAND, extra_sources: tuple[str, ...] = ()
               ) -> dict[str, float]:
    """ns per call of each entry and of the `hand` functions (float x[3] -> float y[2], in
    benchmarks/hand_*.c); extra_sources: more files of benchmarks/ compiled in."""
    includes, wrappers, calls = [], [], []
    for key, (label, header, text, wrap, fn, ranges) in all_entries:
        if header is not None:
            (work / header).write_text(text)
            includes.append(f'#include "{header}"')
        wrappers.append(wrap)
        lo = ", ".join(f"{a!r}f" for a, _ in ranges)
        hi = ", ".join(f"{b!r}f" for _, b in ranges)
        calls.append(f"    {{ const float lo[] = {{{lo}}}, hi[] = {{{hi}}}; "
                     f"add(\"{key}\", {fn}, {len(ranges)}, lo, hi); }}")
    wedm = [(-1.0, 1.0)] * 3
    for fn in hand:
        calls.append(f"    {{ const float lo[] = {{-1.0f, -1.0f, -1.0f}}, "
                     f"hi[] = {{1.0f, 1.0f, 1.0f}}; add(\"{fn}\", {fn}, {len(wedm)}, lo, hi); }}")
    source = (DRIVER_HEAD.format(includes="\n".join(includes), repeats=repeats,
                                 iterations=iterations)
              + "\n".join(wrappers) + "\nint main(void) {\n" + "\n".join(calls)
              + "\n    run_all();\n    return 0;\n}\n")
    (work / "driver.c").write_text(source)
    exe = work / "driver"
    subprocess.run(["gcc", *FLAGS, "-I", str(work), str(work / "driver.c"),
                    str(ROOT / "benchmarks" / "hand_wedm_all_rules.c"),
                    str(ROOT / "benchmarks" / "hand_wedm_active_rules.c"),
                    *(str(ROOT / "benchmarks" / f) for f in extra_sources), "-lm", "-o", str(exe)],
                   check=True)
    result = subprocess.run([str(exe)], check=True, capture_output=True, text=True)
    return {k: float(v) for k, v in (line.split("\t") for line in result.stdout.splitlines())}


def engine_ns(model) -> float:
    rb = model.rulebase
    x = np.array([[0.5 * (v.lo + v.hi) + 0.1 * (v.hi - v.lo) for v in rb.inputs]])
    calls = 200
    return median_seconds(lambda: [evaluate(rb, x) for _ in range(calls)]) / calls * 1e9


def main() -> int:
    models = {name: load(ROOT / "rulebases" / f"{name}.fz") for name in RULEBASES}
    # The shipped milling controller starts unlearned (all 49 weights 0), which gcc folds away
    # in the fixed-point code: time it with weights a learned file could have (fixed seed).
    out = models["milling_neurofuzzy"].rulebase.outputs[0]
    set_entries(out, "params", np.s_[:, 0], np.random.default_rng(7).uniform(-40, 40, out.n_terms))
    all_entries = []
    for name, model in models.items():
        for k, entry in enumerate(entries(model)):
            all_entries.append((f"{name}/{k}", entry))
    all_entries.append(("wedm_three_region/hand_q15", hand_q15_entry()))
    with tempfile.TemporaryDirectory() as work:
        ns = run_driver(all_entries, Path(work),
                        extra_sources=("hand_wedm_active_rules_q15.c",))
    active = ns["hand_wedm_active_rules"]
    rows = []
    for key, (label, *_rest) in all_entries:
        rows.append([key.split("/")[0], label, f"{ns[key]:.1f}", f"{ns[key] / active:.2f}"])
    rows += [["wedm_three_region", "hand-written C, all 75 rules",
              f"{ns['hand_wedm_all_rules']:.1f}", f"{ns['hand_wedm_all_rules'] / active:.2f}"],
             ["wedm_three_region", "hand-written C, active rules only (baseline)",
              f"{active:.1f}", "1.00"]]
    for name, model in models.items():
        t = engine_ns(model)
        rows.append([name, "numpy engine, batch of 1", f"{t:.0f}", f"{t / active:.0f}"])
    text = ("# Generated C: ns per call\n\n"
            f"gcc {' '.join(FLAGS)}; median of {REPEATS} runs of {ITERATIONS} calls over 4096 "
            "random inputs in the rule base's (or the chain's) input ranges; timing loop in C. "
            "Ratio: against the hand-written WEDM active-rules version in the same run. "
            "milling_neurofuzzy with 49 fixed pseudo-random weights in [-40, 40] (the shipped "
            "file's are all 0, which the compiler folds away).\n\n"
            + markdown_table(["rule base", "code", "ns per call", "ratio"], rows))
    write_result(ROOT / "benchmarks" / "results" / "c.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
