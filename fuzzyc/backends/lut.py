"""The lookup-table back end: the rule base sampled on a grid, read back by multilinear
interpolation, usable from Python (`LookupTable`) and emitted as C (`generate_lut_header`).

Semantics (documented in the header too): each input is clamped to its variable's [lo, hi]
(so +-inf read the table's edge); a NaN in any input gives the outputs' declared defaults.
Inside the range the table differs from the engine by the interpolation error, which
`measure_error` finds on a dense check (random points plus every cell centre of the grid).

A model of several rule blocks is tabulated as one function (`Core`): its inputs are the
blocks' inputs that no earlier block computes, its outputs every block's, each block reading
the values of the earlier blocks' outputs as the engine's chain does. A table holds no state,
so an output that holds its last value (lock-previous) is refused.
"""
from __future__ import annotations

import numpy as np

from ..engine.inference import evaluate as engine_evaluate
from ..errors import Diagnostic, FuzzycError
from ..escape import c_comment, c_identifier
from ..semantics.model import Model, RuleBase, Variable
from .c.expressions import FLOAT
from .c.guard import checked_header

MAX_CELLS = 1 << 24
CHECK_RANDOM = 200_000
MAX_CENTRES = 200_000


class Core:
    """A model's rule blocks in order as one function of the inputs no block computes."""

    def __init__(self, blocks: list[RuleBase]):
        self.blocks = blocks
        computed = {v.name for rb in blocks for v in rb.outputs}
        seen: dict[str, Variable] = {}
        for rb in blocks:
            for v in rb.inputs:
                if v.name not in computed:
                    seen.setdefault(v.name, v)
        self.inputs = list(seen.values())
        self.outputs = [v for rb in blocks for v in rb.outputs]

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """x (N, I) -> (N, O): each block reads its inputs' and earlier blocks' values."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        env = {v.name: x[:, i] for i, v in enumerate(self.inputs)}
        for rb in self.blocks:
            y = engine_evaluate(rb, np.column_stack([env[v.name] for v in rb.inputs]))
            env.update({v.name: y[:, o] for o, v in enumerate(rb.outputs)})
        return np.column_stack([env[v.name] for v in self.outputs])


class LookupTable:
    def __init__(self, model: Model | RuleBase, resolution: int):
        core = Core(model.blocks if isinstance(model, Model) else [model])
        n_in = len(core.inputs)
        held = [v.name for v in core.outputs if v.lock_previous]
        if held:
            raise FuzzycError([Diagnostic(None, f"a lookup table holds no state: output "
                                                f"`{held[0]}` keeps its last value where no "
                                                f"rule fires (lock-previous); use --target c, "
                                                f"which keeps it")])
        if resolution < 2:
            raise FuzzycError([Diagnostic(None, "the lookup table needs a resolution >= 2")])
        if resolution ** n_in * len(core.outputs) > MAX_CELLS:
            raise FuzzycError([Diagnostic(None, f"{resolution}**{n_in} grid points are too many "
                                                f"for a lookup table; lower --resolution")])
        self.core, self.resolution = core, resolution
        self.inputs, self.outputs = core.inputs, core.outputs
        self.lo = np.array([v.lo for v in core.inputs], dtype=float)
        self.hi = np.array([v.hi for v in core.inputs], dtype=float)
        self.defaults = np.array([v.default for v in core.outputs], dtype=float)
        axes = [np.linspace(lo, hi, resolution) for lo, hi in zip(self.lo, self.hi)]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, n_in)
        self.values = core.evaluate(grid)                    # (resolution**I, O), row-major
        self.place = resolution ** np.arange(n_in - 1, -1, -1)

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """x (N, I) -> y (N, O) by multilinear interpolation."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        n_cells = self.resolution - 1
        nan = np.isnan(x).any(axis=1)
        xc = np.clip(np.where(np.isnan(x), self.lo, x), self.lo, self.hi)
        pos = (xc - self.lo) / (self.hi - self.lo) * n_cells
        base = np.minimum(np.floor(pos).astype(np.intp), n_cells - 1)
        frac = pos - base
        y = np.zeros((len(x), self.values.shape[1]))
        n_in = x.shape[1]
        for corner in range(1 << n_in):      # the 2**I corners of the cell, not the batch
            bits = (corner >> np.arange(n_in - 1, -1, -1)) & 1
            weight = np.prod(np.where(bits, frac, 1.0 - frac), axis=1)
            y += weight[:, None] * self.values[(base + bits) @ self.place]
        y[nan] = self.defaults
        return y

    def check_points(self, seed: int = 0) -> np.ndarray:
        """Random points over the box plus (up to MAX_CENTRES of) the grid's cell centres."""
        rng = np.random.default_rng(seed)
        n_in = len(self.lo)
        random = self.lo + (self.hi - self.lo) * rng.random((CHECK_RANDOM, n_in))
        n_cells = self.resolution - 1
        total = n_cells ** n_in
        pick = np.arange(total) if total <= MAX_CENTRES else rng.choice(total, MAX_CENTRES,
                                                                         replace=False)
        index = np.stack(np.unravel_index(pick, (n_cells,) * n_in), axis=1)
        centres = self.lo + (index + 0.5) / n_cells * (self.hi - self.lo)
        return np.concatenate([random, centres])

    def measure_error(self, seed: int = 0) -> np.ndarray:
        """The largest |table - engine| per output over `check_points`."""
        x = self.check_points(seed)
        return np.abs(self.evaluate(x) - self.core.evaluate(x)).max(axis=0)


def generate_lut_header(model: Model, table: LookupTable, error: np.ndarray) -> str:
    """C99 header with the table and NAME_lut(x, y); float arithmetic."""
    lit = FLOAT.lit
    name = c_identifier(model.name)
    p, P = name + "_", name.upper() + "_LUT_"
    n_in, n_out, res = len(table.inputs), len(table.outputs), table.resolution
    guard = f"FUZZYC_{name.upper()}_LUT_H"
    errors = ", ".join(f"{c_comment(v.name)} {e:.3g} ({e / (v.hi - v.lo):.2e} of its range)"
                       for v, e in zip(table.outputs, error))
    inference = "; ".join(
        (f"block {c_comment(rb.name or str(k + 1))}: " if len(table.core.blocks) > 1 else "")
        + f"{rb.inference.describe()}" for k, rb in enumerate(table.core.blocks))
    rows = ",\n    ".join("{" + ", ".join(lit(v) for v in row) + "}" for row in table.values)
    place = [int(v) for v in table.place]
    lines = [
        "/*",
        f" * {name}_lut.h - generated by fuzzyc from "
        f"{c_comment(model.source_path or '(built in memory)')}",
        f" * source hash (sha256, first 16 hex): {model.source_hash}",
        f" * inference: {inference}",
        f" * lookup table: {res} points per input over "
        + ", ".join(f"{c_comment(v.name)} [{v.lo:g}, {v.hi:g}]" for v in table.inputs)
        + ", multilinear interpolation",
        f" * measured max error against the engine ({CHECK_RANDOM} random points and up to "
        f"{MAX_CENTRES} cell centres): {errors}",
        " * Inputs are clamped to their ranges (+-inf read the edge); a NaN input gives the",
        " * declared defaults. static inline, no heap, no recursion, constant loop bounds.",
        " */",
        f"#ifndef {guard}", f"#define {guard}", "",
        f"#define {P}N_INPUTS {n_in}", f"#define {P}N_OUTPUTS {n_out}",
        f"#define {P}RESOLUTION {res}", "",
        f"static const float {P}TABLE[{len(table.values)}][{n_out}] = {{\n    {rows}\n}};",
        f"static const float {P}LO[{n_in}] = {{" + ", ".join(lit(v) for v in table.lo) + "};",
        f"static const float {P}SCALE[{n_in}] = {{"
        + ", ".join(lit((res - 1) / (h - lo)) for lo, h in zip(table.lo, table.hi)) + "};",
        f"static const float {P}DEFAULT[{n_out}] = {{"
        + ", ".join(lit(v) for v in table.defaults) + "};",
        f"static const int {P}PLACE[{n_in}] = {{" + ", ".join(map(str, place)) + "};",
        "",
        f"static inline void {p}lut(const float x[{n_in}], float y[{n_out}]) {{",
        f"    int base[{n_in}], i, o, corner;",
        f"    float frac[{n_in}];",
        f"    for (i = 0; i < {n_in}; ++i) {{",
        "        float pos;",
        "        if (x[i] != x[i]) {",
        f"            for (o = 0; o < {n_out}; ++o) y[o] = {P}DEFAULT[o];",
        "            return;",
        "        }",
        f"        pos = (x[i] - {P}LO[i]) * {P}SCALE[i];",
        f"        pos = pos < 0 ? 0 : (pos > {lit(res - 1)} ? {lit(res - 1)} : pos);",
        f"        base[i] = (int)pos < {res - 2} ? (int)pos : {res - 2};",
        "        frac[i] = pos - (float)base[i];",
        "    }",
        f"    for (o = 0; o < {n_out}; ++o) y[o] = 0;",
        f"    for (corner = 0; corner < {1 << n_in}; ++corner) {{",
        "        float w = 1;",
        "        int cell = 0;",
        f"        for (i = 0; i < {n_in}; ++i) {{",
        f"            int bit = (corner >> ({n_in - 1} - i)) & 1;",
        "            w *= bit ? frac[i] : 1 - frac[i];",
        f"            cell += (base[i] + bit) * {P}PLACE[i];",
        "        }",
        f"        for (o = 0; o < {n_out}; ++o) y[o] += w * {P}TABLE[cell][o];",
        "    }",
        "}", "", f"#endif /* {guard} */", ""]
    return checked_header("\n".join(lines), model)
