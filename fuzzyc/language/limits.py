"""The stated limits of a rule file, checked before anything is built from it.

Every limit is a module constant (docs/limits.md gives the reason and the measured cost of each;
the tests use the constants at the limit and one past it).  A file beyond a limit is an error
with its place, never an exhausted machine or a header that does not compile.

Numbers: every number a file writes is finite, and either 0 or of a magnitude in
[MIN_MAGNITUDE, MAX_MAGNITUDE].  In that band the float C header's arithmetic (squares, the
centroid's cubes over an output's range) neither overflows nor leaves the normal floats, and
the engine's double arithmetic is exact enough to be the reference.  A range must also be wide
enough against its own magnitude for float to tell its points apart (MIN_RELATIVE_WIDTH).
"""
from __future__ import annotations

import math
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import sympy

from ..errors import Diagnostic, FuzzycError, Reporter, decode_source
from ..semantics.model import Model, SourceLoc

MAX_SOURCE_BYTES = 1_000_000     # a rule file (any format); parsing costs ~10 us and ~5 kB a byte-line
MAX_TERMS = 253                  # per variable: the C back ends keep term ids (and `*`) in a byte
MAX_RULES = 10_000               # per rule base
MAX_RULEBASE_INPUTS = 32         # linguistic inputs of a rule base
MAX_RULEBASE_OUTPUTS = 32        # rule-base output variables
MAX_MAGNITUDE = 1e12             # |every number| (0 aside)
MIN_MAGNITUDE = 1e-12            # |every non-zero number|
MIN_RELATIVE_WIDTH = 1e-5        # hi - lo >= this * max(|lo|, |hi|)
# Nesting of an expression (.fz) or a rule condition (FLL, FCL): the front ends and the
# builder recurse through it, and Python's stack stops near 1000 frames.
MAX_NESTING = 200
MAX_HEDGES = 16                  # hedges on one clause or conclusion (FLL, FCL): each nests
# Not limits of a file.  `simulate --batch` (and api.simulate's batch): the loops' arrays take
# about 1 kB a loop (wedm_rough: 1e6 loops, 0.98 GB); checked before any is allocated.
MAX_BATCH = 1_000_000
# `--workers N` (and Cluster(workers=N)): a local Dask cluster is one process a worker on this
# machine; `--workers 99999999999` tried to start that many and ran out of memory. 64 is past
# any workstation's cores; a larger campaign runs on a cluster of its own (`--scheduler`).
MAX_WORKERS = 64
MAX_FILE_NAME_BYTES = 255        # a generated file's name (NAME.h), as ext4, XFS, APFS, NTFS
# Not limits of the file but of the C headers.  The cell table (term tuple -> rules): indexed
# by the cell code up to this many cells, past it this many occupied cells found by binary
# search; past that the float/double header loops over every rule, q15/q31 refuse.
MAX_C_TABLE_CELLS = 1 << 16
# The q15/q31 header visits every combination of the inputs' active terms (2 per input, 3
# where a rule has `*`) and has no loop over every rule: it refuses past this many per call
# (16 inputs; 10 inputs with `*` on each take 59,049).
MAX_C_SLOT_COMBINATIONS = 1 << 16


def read_rule_file(path: str | Path) -> str:
    """The text of a rule file, refused past MAX_SOURCE_BYTES without reading the rest."""
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_SOURCE_BYTES + 1)
    except (OSError, ValueError) as exc:      # ValueError: a NUL in the name
        raise FuzzycError([Diagnostic(None, f"cannot read {path}: {exc}")]) from None
    if len(data) > MAX_SOURCE_BYTES:
        # placed at the first byte past the limit, like every other message about a file
        line = data.count(b"\n", 0, MAX_SOURCE_BYTES) + 1
        col = MAX_SOURCE_BYTES - data.rfind(b"\n", 0, MAX_SOURCE_BYTES)
        raise FuzzycError([Diagnostic(SourceLoc(str(path), line, col),
                                      f"{path} is larger than {MAX_SOURCE_BYTES} "
                                      "bytes, the largest rule file fuzzyc reads "
                                      "(fuzzyc.language.limits.MAX_SOURCE_BYTES)")])
    return decode_source(data, path)


def number_problem(value: float) -> str | None:
    """Why a number written in a rule file is out of bounds, or None."""
    if math.isnan(value) or math.isinf(value):
        return (f"the number {value:g} is not finite (fuzzyc reads numbers up to "
                f"{MAX_MAGNITUDE:g} in magnitude)")
    if abs(value) > MAX_MAGNITUDE:
        return (f"the number {value:g} is larger than {MAX_MAGNITUDE:g} in magnitude, the "
                f"largest fuzzyc accepts (fuzzyc.language.limits.MAX_MAGNITUDE); use a larger unit")
    if value != 0 and abs(value) < MIN_MAGNITUDE:
        return (f"the number {value:g} is smaller than {MIN_MAGNITUDE:g} in magnitude, the "
                f"smallest non-zero number fuzzyc accepts (fuzzyc.language.limits.MIN_MAGNITUDE); "
                f"use a smaller unit")
    return None


def range_problem(lo: float, hi: float) -> str | None:
    """Why [lo, hi] cannot be a variable's range (its numbers are checked on their own)."""
    scale = max(abs(lo), abs(hi))
    if hi - lo < MIN_RELATIVE_WIDTH * scale:
        return (f"the range [{lo:g}, {hi:g}] is narrower than {MIN_RELATIVE_WIDTH:g} of its "
                f"magnitude (fuzzyc.language.limits.MIN_RELATIVE_WIDTH): float arithmetic cannot tell "
                f"its points apart; shift it: use a `let` that subtracts an offset")
    return None


def check_model(model: Model) -> None:
    """FuzzycError naming every limit the model passes (counts, numbers, ranges)."""
    reporter = Reporter(model.source_path or "<model>", model.source_text or "")
    seen = set()
    for loc, message in _problems(model):
        key = (loc, message.split(": ", 1)[-1])    # an input's range is its variable's range
        if key not in seen:
            seen.add(key)
            reporter.error(loc, message)
    reporter.raise_if_any()


def _problems(model: Model) -> Iterable[tuple[SourceLoc | None, str]]:
    for rb in model.blocks:
        for what, count, limit, name, locs in (
                ("rules", rb.n_rules, MAX_RULES, "MAX_RULES", rb.rule_locs),
                ("rule-base inputs", len(rb.inputs), MAX_RULEBASE_INPUTS, "MAX_RULEBASE_INPUTS",
                 [v.loc for v in rb.inputs]),
                ("rule-base outputs", len(rb.outputs), MAX_RULEBASE_OUTPUTS,
                 "MAX_RULEBASE_OUTPUTS", [v.loc for v in rb.outputs])):
            if count > limit:
                yield (_at(locs, limit), f"{count} {what}: at most {limit} (fuzzyc.language.limits.{name})")
        for var in rb.inputs + rb.outputs:
            if var.n_terms > MAX_TERMS:
                yield (_at(var.term_locs, MAX_TERMS) or var.loc,
                       f"`{var.name}` has {var.n_terms} terms: at most {MAX_TERMS} per variable "
                       f"(fuzzyc.language.limits.MAX_TERMS)")
            yield from _number_problems(var.loc, f"`{var.name}`", [var.lo, var.hi, var.default])
            yield from _range_problems(var.loc, f"`{var.name}`", var.lo, var.hi)
            params = np.asarray(var.params, dtype=float)
            for t, row in enumerate(params):
                extra = (var.coefficients or {}).get(t, ())
                where = _at(var.term_locs, t) or var.loc
                # +-inf are a shoulder's open ends, not numbers the file wrote
                yield from _number_problems(where, f"term `{var.names[t]}`",
                                            [v for v in (*row, *extra) if not math.isinf(v)])
    for signal in model.signals:
        yield from _number_problems(signal.loc, f"input `{signal.name}`", [signal.lo, signal.hi])
        yield from _range_problems(signal.loc, f"input `{signal.name}`", signal.lo, signal.hi)
    for out in model.outputs:
        yield from _number_problems(out.loc, f"output `{out.name}`", [out.lo, out.hi, out.init])
        yield from _range_problems(out.loc, f"output `{out.name}`", out.lo, out.hi)
    for param in model.params.values():
        yield from _number_problems(param.loc, f"param `{param.name}`", [param.value])
    for step in model.steps:
        constants = [float(n) for n in step.expr.atoms(sympy.Number)]
        yield from _number_problems(step.loc, f"`{step.name}`",
                                    [*constants, *(v for v in (step.lo, step.hi) if v is not None)])


def _at(locs: list[SourceLoc | None], index: int) -> SourceLoc | None:
    return locs[index] if index < len(locs) else None


def _number_problems(loc, what: str, values) -> Iterable[tuple[SourceLoc | None, str]]:
    for value in values:
        problem = number_problem(float(value))
        if problem is not None:
            yield loc, f"{what}: {problem}"
            return      # one message per place


def _range_problems(loc, what: str, lo: float, hi: float):
    if math.isfinite(lo) and math.isfinite(hi):
        problem = range_problem(lo, hi)
        if problem is not None:
            yield loc, f"{what}: {problem}"
