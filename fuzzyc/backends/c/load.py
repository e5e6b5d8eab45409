"""The generated C behind the Python `Controller` interface, so loops and the verifier can run
the exact code that ships.

`CController(model, numeric)` writes the header, compiles it with a small batch shim into a
shared library (gcc -shared -fPIC, cached under a key of the header text and the flags, in a
private per-user folder: see `cache_dir`) and loads it with ctypes.  A step of the whole batch
is one C call; the loop over the batch is in C.
The header is generated once, at construction: later changes to the model (learning) need a new
CController.
"""
from __future__ import annotations

import ctypes
import hashlib
import os
import platform
import stat
import subprocess
import tempfile
from pathlib import Path
from typing import Sequence

import numpy as np

from ...errors import Diagnostic, FuzzycError
from ...semantics.model import Model
from ...escape import c_identifier
from ..rule_blocks import emitted_blocks
from . import header as c_backend   # looked up at each call (a test may patch generate_header)

STRICT_FLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Wconversion",
                "-Wshadow", "-Werror")

SHIM = """\
#include "{name}.h"
/* Batch entry points for ctypes: doubles in and out, one call per step of the whole batch. */
int {entry}_state_size(void) {{ return (int)sizeof({name}_state); }}
void {entry}_init({name}_state *s, int n) {{
    int b;
    for (b = 0; b < n; ++b) {name}_init(&s[b]);
}}
void {entry}_step({name}_state *s, int n, const double *in, double *out) {{
    int b, k;
    for (b = 0; b < n; ++b) {{
        {real} x[{P}N_SIGNALS], y[{P}N_OUTPUTS];
        for (k = 0; k < {n_in}; ++k) x[k] = ({real})in[b * {n_in} + k];
        {name}_step(&s[b], x, y);
        for (k = 0; k < {n_out}; ++k) out[b * {n_out} + k] = (double)y[k];
    }}
}}
"""
# the bare rule base, where the model has one rule block (the header's NAME_rulebase)
SHIM_RULEBASE = """\
void {entry}_rulebase(int n, const double *in, double *out) {{
    int b, k;
    for (b = 0; b < n; ++b) {{
        {real} x[{P}N_RB_INPUTS], y[{P}N_RB_OUTPUTS];
        for (k = 0; k < {P}N_RB_INPUTS; ++k) x[k] = ({real})in[b * {P}N_RB_INPUTS + k];
        {name}_rulebase(x, y);
        for (k = 0; k < {P}N_RB_OUTPUTS; ++k) out[b * {P}N_RB_OUTPUTS + k] = (double)y[k];
    }}
}}
"""

REAL_OF = {"float": "float", "double": "double"}


def cache_dir() -> Path:
    """The per-user folder of compiled libraries: $FUZZYC_CACHE, else $XDG_CACHE_HOME/fuzzyc,
    else ~/.cache/fuzzyc, created with mode 0700.  A library found there is loaded and run, so
    the folder must be this user's and writable by nobody else (FuzzycError otherwise)."""
    root = os.environ.get("FUZZYC_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
        "fuzzyc")
    path = Path(root)
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
        problem = _not_private(path)
    except OSError as exc:
        problem = f"cannot be made ({exc.strerror})"
    if problem:
        raise FuzzycError([Diagnostic(None, f"the C library cache {path} {problem}: fuzzyc "
                                            "loads the code it finds there; set "
                                            "FUZZYC_CACHE to a folder of your own (mode 0700)")])
    return path


def _not_private(path: Path) -> str:
    """Why another user could have put `path` there or could change it ('' if none can)."""
    st = path.stat()
    if st.st_uid != os.getuid():
        return f"belongs to user id {st.st_uid}, not to you ({os.getuid()})"
    if st.st_mode & 0o022:
        return f"is writable by others (mode {stat.S_IMODE(st.st_mode):04o})"
    return ""


def _trusted_library(path: Path) -> bool:
    """A regular file (not a link) of this user that nobody else can write; anything else in
    the cache is compiled anew over it, never loaded."""
    try:
        st = path.lstat()
    except FileNotFoundError:
        return False
    return stat.S_ISREG(st.st_mode) and not _not_private(path)


def library_path(sources: dict[str, str], main: str, flags: tuple[str, ...] = ()) -> Path:
    """Where the cache keeps the library of these sources and flags."""
    key = hashlib.sha256(repr((sorted(sources.items()), main, STRICT_FLAGS, flags))
                         .encode()).hexdigest()[:20]
    return cache_dir() / f"fz_{key}.so"


def compile_shared(sources: dict[str, str], main: str, flags: tuple[str, ...] = ()) -> Path:
    """Compile `main` (a key of sources) with its sibling files into a cached shared library."""
    target = library_path(sources, main, flags)
    if _trusted_library(target):
        return target
    with tempfile.TemporaryDirectory(dir=cache_dir()) as work:
        for fname, text in sources.items():
            Path(work, fname).write_text(text)
        tmp_lib = Path(work, "lib.so")
        cmd = ["gcc", *STRICT_FLAGS, *flags, "-shared", "-fPIC", "-o", str(tmp_lib),
               str(Path(work, main)), "-lm"]
        try:
            result = subprocess.run(cmd, capture_output=True, text=True)
        except FileNotFoundError:
            raise FuzzycError([Diagnostic(None, "running the generated C needs a C compiler: "
                                                "`gcc` is not on the PATH; install it (Debian: "
                                                "apt-get install gcc)")]) from None
        if result.returncode != 0:
            raise FuzzycError([Diagnostic(None, "the C compiler rejected the generated code:\n"
                                                + result.stderr)])
        os.chmod(tmp_lib, 0o700)      # private whatever the umask (see _trusted_library)
        os.replace(tmp_lib, target)   # atomic: a concurrent reader sees all or nothing
    return target


def shim_prefix(model: Model) -> str:
    """The prefix of the shim's entry points: `fz`, or `fzb` for a controller named `fz`
    (whose header defines fz_init, fz_step, fz_rulebase itself)."""
    return "fzb" if c_identifier(model.name) == "fz" else "fz"


def controller_sources(model: Model, numeric: str) -> dict[str, str]:
    """The files CController compiles: NAME.h and the batch shim, shim.c, that includes it."""
    name = c_identifier(model.name)
    text = SHIM + (SHIM_RULEBASE if len(emitted_blocks(model)) == 1 else "")
    shim = text.format(name=name, P=name.upper() + "_", real=REAL_OF[numeric],
                       entry=shim_prefix(model),
                       n_in=len(model.signals), n_out=len(model.outputs))
    return {f"{name}.h": c_backend.generate_header(model, numeric), "shim.c": shim}


class CController:
    """Same interface as `fuzzyc.engine.chain.Controller`, running the generated C."""

    def __init__(self, model: Model, batch: int = 1, numeric: str = "float"):
        self.model = model
        self.numeric = numeric
        self.input_names = [s.name for s in model.signals]
        self.output_names = [o.name for o in model.outputs]
        path = compile_shared(controller_sources(model, numeric), "shim.c")
        lib, entry = ctypes.CDLL(str(path)), shim_prefix(model)
        self._step, self._init = (getattr(lib, f"{entry}_{f}") for f in ("step", "init"))
        dptr = ctypes.POINTER(ctypes.c_double)
        self._step.argtypes = [ctypes.c_void_p, ctypes.c_int, dptr, dptr]
        self._rulebase = None         # a header of several rule bases has no NAME_rulebase
        if len(emitted_blocks(model)) == 1:
            self._rulebase = lib[f"{entry}_rulebase"]
            self._rulebase.argtypes = [ctypes.c_int, dptr, dptr]
        self._init.argtypes = [ctypes.c_void_p, ctypes.c_int]
        self._lib = lib
        self._state_size = getattr(lib, f"{entry}_state_size")()
        self.signals: dict[str, np.ndarray] = {}
        self.reset(batch)

    def reset(self, batch: int | None = None) -> None:
        if batch is not None:
            self.batch = int(batch)
        self._states = ctypes.create_string_buffer(max(1, self.batch) * self._state_size)
        self._init(self._states, self.batch)
        self.signals = {}

    @staticmethod
    def _ptr(a: np.ndarray):
        return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))

    def step(self, inputs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        missing = [n for n in self.input_names if n not in inputs]
        if missing:
            raise KeyError(f"no value for input(s): {', '.join(missing)}")
        n = self.batch
        x = np.ascontiguousarray(np.stack(
            [np.broadcast_to(np.asarray(inputs[k], dtype=float), (n,)) for k in self.input_names],
            axis=1))
        y = np.empty((n, len(self.output_names)))
        self._step(self._states, n, self._ptr(x), self._ptr(y))
        outputs = {k: y[:, o].copy() for o, k in enumerate(self.output_names)}
        # Only the chain's ends are visible from C (the intermediate signals are locals).
        self.signals = {**{k: x[:, i].copy() for i, k in enumerate(self.input_names)}, **outputs}
        return outputs

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """The bare rule base: x (N, I) -> y (N, O), like `fuzzyc.engine.inference.evaluate`."""
        rb = self.model.rulebase
        run = self.rulebase_entry()
        x = np.ascontiguousarray(np.atleast_2d(np.asarray(x, dtype=float)))
        if x.shape[1] != len(rb.inputs):
            raise ValueError(f"expected {len(rb.inputs)} input columns, got {x.shape[1]}")
        y = np.empty((x.shape[0], len(rb.outputs)))
        run(x.shape[0], self._ptr(x), self._ptr(y))
        return y

    def rulebase_entry(self):
        """The library's bare-rule-base entry (ctypes function), or a FuzzycError where the
        header has none."""
        if self._rulebase is None:
            raise FuzzycError([Diagnostic(None, f"the header of `{self.model.name}` splits its "
                                                "rule base by its outputs' own defuzzifiers "
                                                "and has no one NAME_rulebase; step the chain")])
        return self._rulebase


class CompiledEvaluator:
    """The model's bare rule base at one point, run by the generated header's NAME_rulebase
    through ctypes: `f(values)` takes a float per rule-base input, in order, and returns the
    outputs as a list.  The numbers are the header's, which follows the engine's semantics (in
    double precision the same operations: tests/test_compiled_evaluator.py); the cost is one
    foreign call, about a microsecond, where the engine pays numpy's fixed cost per call.
    Needs gcc at construction (the library is cached, see `cache_dir`)."""

    def __init__(self, model: Model, numeric: str = "double"):
        if numeric not in REAL_OF:
            raise ValueError(f"numeric is one of float, double, not `{numeric}` (the fixed-point"
                             " headers have no ctypes entry)")
        self._controller = CController(model, 1, numeric)   # owns the loaded library
        self._run = self._controller.rulebase_entry()
        rb = model.rulebase
        self.input_names = [v.name for v in rb.inputs]
        self.output_names = [v.name for v in rb.outputs]
        self._n = len(rb.inputs)
        self._x = (ctypes.c_double * len(rb.inputs))()
        self._y = (ctypes.c_double * len(rb.outputs))()
        self._run.argtypes = [ctypes.c_int, type(self._x), type(self._y)]

    def __call__(self, values: Sequence[float]) -> list[float]:
        if len(values) != self._n:
            raise ValueError(f"expected {self._n} input values ({', '.join(self.input_names)}),"
                             f" got {len(values)}")
        try:
            self._x[:] = values  # ctypes converts each to a C double
        except TypeError as exc:
            raise TypeError(f"the input values ({', '.join(self.input_names)}) must be real "
                            f"numbers: {exc}") from None
        self._run(1, self._x, self._y)
        return self._y[:]


def measured_entry_points(name: str, target: str) -> list[str]:
    """Out-of-line definitions of what a firmware calls in the header of `target` (float,
    double, q15, q31 or lut), for `footprint` to measure."""
    if target in ("q15", "q31"):   # the whole chain, like the float header's init and step
        io = "int16_t" if target == "q15" else "int32_t"
        p = f"{name}_{target}_"
        return [f"void measure_init({p}state *s) {{ {p}init(s); }}",
                f"void measure_step({p}state *s, const {io} *in, {io} *out) "
                f"{{ {p}step(s, in, out); }}"]
    if target == "lut":
        return [f"void measure_lut(const float *x, float *y) {{ {name}_lut(x, y); }}"]
    # What a firmware calls: init and step (the bare rule base is inlined inside step).
    return [f"void measure_init({name}_state *s) {{ {name}_init(s); }}",
            f"void measure_step({name}_state *s, const {name}_real *in, {name}_real *out) "
            f"{{ {name}_step(s, in, out); }}"]


MEASURE = """\
#include "{header}"
/* Out-of-line instances of the header's entry points, so size and stack can be measured. */
{body}
"""


def footprint(header_name: str, header: str, entry_points: list[str],
              flags: tuple[str, ...] = ("-O2",), failure: str = "",
              toolchain: str = "") -> tuple[int, int, int]:
    """(code + constant data bytes, static RAM bytes, worst-case stack bytes) of the header's
    entry points, compiled by `{toolchain}gcc` (e.g. toolchain "arm-none-eabi-").

    `entry_points` are full C definitions calling the header (and any globals, e.g. a state
    instance, whose bytes count as RAM).  Code and constants are `size`'s text (rodata
    included), RAM its data + bss; stack is the sum over every function gcc reports with
    -fstack-usage, an upper bound for any call chain among them.  A header gcc rejects is a
    FuzzycError with gcc's messages and `failure` (what the caller did not do).
    """
    with tempfile.TemporaryDirectory(dir=cache_dir()) as work:
        Path(work, header_name).write_text(header)
        Path(work, "measure.c").write_text(MEASURE.format(header=header_name,
                                                          body="\n".join(entry_points)))
        obj = Path(work, "measure.o")
        # No unwind tables (a firmware build has none; they would count as code here) and, on
        # x86-64, no red zone, which -fstack-usage would not count.
        red_zone = ["-mno-red-zone"] if not toolchain and platform.machine() in (
            "x86_64", "AMD64") else []
        cmd = [f"{toolchain}gcc", *STRICT_FLAGS, *flags, "-fno-asynchronous-unwind-tables", *red_zone,
               "-fstack-usage", "-c", "-o", str(obj),
               str(Path(work, "measure.c"))]
        result = subprocess.run(cmd, capture_output=True, text=True, cwd=work)
        if result.returncode != 0:
            raise FuzzycError([Diagnostic(None, "the C compiler rejected the generated code"
                                                + (f" ({failure})" if failure else "") + ":\n"
                                                + result.stderr)])
        size = subprocess.run([f"{toolchain}size", str(obj)], capture_output=True, text=True,
                              check=True)
        text_bytes, data, bss = map(int, size.stdout.splitlines()[1].split()[:3])
        stack = sum(int(line.split("\t")[1])
                    for line in Path(work, "measure.su").read_text().splitlines() if line)
    return text_bytes, data + bss, stack
