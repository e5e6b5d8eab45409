"""Run-time-error freedom of the generated headers, proved with Frama-C's EVA (abstract
interpretation: every value the program can compute, over-approximated by intervals).

For a header, `harness` writes a C `main` that EVA analyses:

- the whole chain: NAME_init, then an unbounded loop of NAME_step on inputs whose bytes are
  arbitrary (`Frama_C_make_unknown`: every int16/int32 for q15/q31; for float every bit
  pattern, so NaN and +-inf too), so EVA's loop fixpoint covers every reachable state after any
  number of steps; after each step an ACSL assertion that every out[k] is finite (float) and
  within the output's declared range (at its I/O scale for q15/q31);
- the bare rule base (or the lookup table) on arbitrary inputs once, asserted within the
  output's scale for q15/q31 and finite for the lookup table.

EVA is run with -warn-signed-downcast (a narrowing conversion out of range is an alarm too,
not only signed overflow, division by zero, invalid memory access, uninitialized reads, shifts
out of width and float-to-int conversions out of range) and -warn-special-float none: the
float headers assume IEEE 754 arithmetic (C99 Annex F), where NaN and +-inf are values, and
handle them themselves (the assertions on out[] say that none reaches an output).  The proof
holds under the assumptions of docs/c-proofs.md (the machine model of EVA's default x86_64
target, which for these headers -- fixed-width types only -- is the one of every 32/64-bit
target; >> of a negative integer arithmetic).
"""
from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from ...errors import Diagnostic, FuzzycError
from ...escape import c_identifier
from ...semantics.model import Model
from ..rule_blocks import emitted_blocks

KINDS = ("float", "double", "q15", "q31", "lut")     # every header fuzzyc compile writes
FLOATING = ("float", "double")
# assumption: precision 3 (loops unrolled enough that a partition's break-point count and the
# 2**I term tuples stay exact) proves every shipped header in about a second each; higher
# costs more and proves nothing more on them.
EVA_FLAGS = ("-eva", "-eva-precision", "3", "-warn-special-float", "none",
             "-warn-signed-downcast", "-eva-no-show-progress")
LUT_RESOLUTION = 9    # the table's size changes no code path, only the constant data


@dataclass
class Proof:
    """What EVA said about one header."""
    header: str
    alarms: list[str] = field(default_factory=list)     # each "file:line: what"
    assertions: tuple[int, int] = (0, 0)                 # (valid, total) of the harness's
    claims: list[str] = field(default_factory=list)      # what the assertions say
    assumptions: list[str] = field(default_factory=list)  # what the proof takes as given
    seconds: float = 0.0

    @property
    def proved(self) -> bool:
        return not self.alarms and self.assertions[0] == self.assertions[1]

    def summary(self) -> str:
        if self.proved:
            return (f"{self.header}: PROVED by Frama-C EVA in {self.seconds:.1f} s: no run-time "
                    "error (overflow, division by zero, out-of-bounds access, uninitialized "
                    "read, invalid shift or conversion) for any input, and "
                    + "; ".join(self.claims) + ".\n  Assuming " + "; ".join(self.assumptions)
                    + " (docs/c-proofs.md)")
        lines = [f"{self.header}: NOT PROVED ({len(self.alarms)} alarm(s), "
                 f"{self.assertions[0]} of {self.assertions[1]} assertions valid)"]
        return "\n".join(lines + [f"  {a[:300]}" for a in self.alarms])


def frama_c() -> str | None:
    return shutil.which("frama-c")


def _lit(value: float, kind: str) -> str:
    return repr(float(value)) + ("" if kind == "double" else "f")


def header_for(model: Model, kind: str) -> tuple[str, str]:
    """(file name, text) of the header of this kind."""
    name = c_identifier(model.name)
    if kind == "lut":
        from ..lut import LookupTable, generate_lut_header
        table = LookupTable(model, LUT_RESOLUTION)
        return f"{name}_lut.h", generate_lut_header(model, table, table.measure_error())
    if kind in ("q15", "q31"):
        from ..c_fixed.header import generate_fixed_header
        return f"{name}_{kind}.h", generate_fixed_header(model, kind)
    from .header import generate_header
    return f"{name}.h", generate_header(model, kind)


def harness(model: Model, kind: str, header_name: str) -> tuple[str, list[str]]:
    """(the C main EVA analyses, the claims its assertions make)."""
    name = c_identifier(model.name)
    lines = ['#include "__fc_builtin.h"', f'#include "{header_name}"', "int main(void) {"]
    claims = []
    if kind == "lut":
        p, P = f"{name}_", f"{name.upper()}_LUT_"
        lines += [f"    float x[{P}N_INPUTS], y[{P}N_OUTPUTS];",
                  "    Frama_C_make_unknown((char *)x, sizeof x);",
                  f"    {p}lut(x, y);"]
        from ..lut import Core
        lines += [f"    /*@ assert \\is_finite(y[{o}]); */"
                  for o in range(len(Core(model.blocks).outputs))]
        claims.append("the table's outputs are finite for every input (NaN and +-inf too)")
    else:
        p = f"{name}_" if kind in FLOATING else f"{name}_{kind}_"
        P = p.upper()
        io = {"q15": "int16_t", "q31": "int32_t"}.get(kind, kind)
        # each rule block's bare rulebase on any input too (NAME_bK_ in a header of several)
        emitted = emitted_blocks(model)
        blocks = [(p, P)] if len(emitted) == 1 else \
            [(f"{p}b{k}_", f"{P}B{k}_") for k in range(len(emitted))]
        lines += [f"    {p}state s;",
                  f"    {io} in[{P}N_SIGNALS], out[{P}N_OUTPUTS];",
                  *(f"    {io} x{k}[{bP}N_RB_INPUTS], y{k}[{bP}N_RB_OUTPUTS];"
                    for k, (_, bP) in enumerate(blocks)),
                  f"    {p}init(&s);",
                  "    while (Frama_C_nondet(0, 1)) {",
                  "        Frama_C_make_unknown((char *)in, sizeof in);",
                  f"        {p}step(&s, in, out);"]
        for k, o in enumerate(model.outputs):
            lo, hi = _output_bounds(o, kind)
            finite = f"\\is_finite(out[{k}]) && " if kind in FLOATING else ""
            lines.append(f"        /*@ assert {finite}{lo} <= out[{k}] <= {hi}; */")
        lines.append("    }")
        for k, (bp, _) in enumerate(blocks):
            lines += [f"    Frama_C_make_unknown((char *)x{k}, sizeof x{k});",
                      f"    {bp}rulebase(x{k}, y{k});"]
        if kind not in FLOATING:
            from ..c_fixed.header import FORMATS
            full = FORMATS[kind][1]
            lines += [f"    /*@ assert 0 <= y{k}[{o}] <= {full}; */"
                      for k, block in enumerate(emitted) for o in range(len(block.outputs))]
            claims.append(f"the bare rule base's outputs stay in [0, {full}]"
                          + (" (each block's)" if len(blocks) > 1 else ""))
        inputs = "any bit pattern of every input (NaN, +-inf)" if kind in FLOATING else \
            f"any {io} input"
        claims.insert(0, f"after any number of steps on {inputs} every chain output is "
                         + ("finite and " if kind in FLOATING else "")
                         + "within its declared range")
    lines += ["    return 0;", "}", ""]
    return "\n".join(lines), claims


def assumptions(model: Model, kind: str) -> list[str]:
    """What a proof of this kind of header takes as given (docs/c-proofs.md says why)."""
    if kind == "lut":
        return ["IEEE 754 arithmetic (C99 Annex F: no -ffast-math or -ffinite-math-only)"]
    if kind in FLOATING:
        p = f"{c_identifier(model.name)}_"
        said = ["IEEE 754 arithmetic (C99 Annex F: no -ffast-math or -ffinite-math-only)",
                "<math.h> as Frama-C's libc specifies it"]
    else:
        p = f"{c_identifier(model.name)}_{kind}_"
        said = ["`>>` of a negative integer arithmetic (implementation-defined in C99 6.5.7; "
                "arithmetic on GCC, Clang, IAR and Keil)"]
    return said + [f"the state initialised by {p}init and written by nothing but {p}step"]


def _output_bounds(o, kind: str) -> tuple[str, str]:
    """The declared range of a chain output as C literals of out[]'s scale."""
    if kind in FLOATING:
        return _lit(o.lo, kind), _lit(o.hi, kind)
    from ..c_fixed.header import io_frac
    frac = io_frac(o.lo, o.hi, kind)
    return str(round(o.lo * 2.0 ** frac)), str(round(o.hi * 2.0 ** frac))


_ALARM = re.compile(r"^\[eva:alarm\] (\S+): Warning: *\n?((?:  .*\n?)*)", re.M)
_ASSERTIONS = re.compile(r"Assertions\s+(\d+) valid\s+(\d+) unknown\s+(\d+) invalid\s+(\d+) total")
_ALARM_COUNT = re.compile(r"(\d+) alarms? generated by the analysis")


def run_eva(header_name: str, header: str, main: str) -> tuple[list[str], tuple[int, int]]:
    """(alarms in the header, (valid, total) assertions of the harness)."""
    exe = frama_c()
    if exe is None:
        raise FuzzycError([Diagnostic(None, "--prove needs Frama-C (`frama-c` on PATH; Debian: "
                                            "apt-get install frama-c-base)")])
    with tempfile.TemporaryDirectory() as work:
        Path(work, header_name).write_text(header)
        Path(work, "harness.c").write_text(main)
        result = subprocess.run([exe, *EVA_FLAGS, str(Path(work, "harness.c"))],
                                capture_output=True, text=True, cwd=work)
    log = result.stdout + result.stderr
    if result.returncode != 0 or "ANALYSIS SUMMARY" not in log:
        raise FuzzycError([Diagnostic(None, f"Frama-C failed on {header_name}:\n{log[-2000:]}")])
    # the harness's own assertions are counted below, not as alarms of the header
    alarms = [f"{Path(where).name}: {' '.join(what.split())}"
              for where, what in _ALARM.findall(log) if not where.startswith(
                  str(Path(work, "harness.c")))]
    counted = _ALARM_COUNT.search(log)
    if counted and int(counted.group(1)) > len(alarms):    # never lose one to the parsing
        alarms.append(f"{int(counted.group(1)) - len(alarms)} more alarm(s) in EVA's report")
    found = _ASSERTIONS.search(log)
    valid, total = (int(found.group(1)), int(found.group(4))) if found else (0, 0)
    return alarms, (valid, total)


def prove(model: Model, kind: str, header: tuple[str, str] | None = None) -> Proof:
    """Analyse the header of this kind for model with EVA: `header` (file name, text) as
    written, else the one `header_for` writes."""
    header_name, header = header or header_for(model, kind)
    main, claims = harness(model, kind, header_name)
    start = time.perf_counter()
    alarms, assertions = run_eva(header_name, header, main)
    return Proof(header_name, alarms, assertions, claims, assumptions(model, kind),
                 time.perf_counter() - start)
