"""The C headers' cell table (term tuple -> its rules), one builder for the float/double header
(`c`) and the q15/q31 header (`c_fixed`).

A call finds the (at most two) active terms of each input and visits every tuple of them; a
tuple's cell code is its term ids in mixed radix (input 0 slowest).  The radix of an input is
its number of terms, plus one where a rule leaves it open (`*`, a code of its own, only in the
fixed-point header).  There is no code for "no term": a slot without a term (a single term
active, or a NaN input) reads term 0 at membership 0, so its tuples' rules get activation 0
and add nothing.  A grid of 3-term inputs has 3**I cells (the engine's code for "no term"
would make it 4**I).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...engine.strength_grid import place_values
from ...language.limits import MAX_C_TABLE_CELLS


def int_table(rows) -> str:
    return "{" + ", ".join("{" + ", ".join(str(int(v)) for v in row) + "}" for row in rows) + "}"


def index_type(largest: int) -> str:
    """The smallest unsigned C type holding 0..largest (small tables for small targets)."""
    return "unsigned char" if largest <= 255 else "unsigned short" if largest <= 65535 \
        else "unsigned long"


class CellTable(NamedTuple):
    radix: np.ndarray              # per input, its number of codes
    codes: np.ndarray | None       # the occupied cells' codes ascending, or None: direct
    rows: np.ndarray               # (cells or occupied cells + 1, depth): rules, padded with R

    @property
    def place(self) -> np.ndarray:
        return place_values(self.radix)

    @property
    def cell_type(self) -> str:
        """The C type of a cell code."""
        return index_type(int(np.prod(self.radix)) - 1)

    @property
    def depth(self) -> int:
        """Rules per cell (the most in one cell)."""
        return self.rows.shape[1]

    @property
    def one_rule_per_cell(self) -> bool:
        """A direct table whose cells hold at most one rule: the headers can table that rule's
        consequents and weight per cell (CELL_CONSEQUENTS), one load fewer per tuple."""
        return self.codes is None and self.depth == 1


def active_codes(part) -> np.ndarray:
    """Per segment of a LocalPartition, the codes of its two slots' terms (B + 1, 2): a slot
    without a term as term 0, whose piece there is 0."""
    ids = part.table[:, 6:8].astype(int)
    return np.where(ids < part.n_terms, ids, 0)


def cell_table(ids: np.ndarray, radix: np.ndarray) -> CellTable | None:
    """The cell table of the rules whose term codes are ids (rules, inputs), each in
    [0, radix).  codes is None while the cells are at most MAX_C_TABLE_CELLS, indexed by the
    cell code itself; past that they are the occupied cells' codes ascending, found by binary
    search, with their rows and a last row without rules for every other code.  None where
    even the occupied cells pass the limit (or a code passes 32 bits, C99's least unsigned
    long)."""
    radix = np.asarray(radix, dtype=np.int64)
    n_rules = len(ids)
    if np.prod(radix.astype(float)) > 2.0 ** 32:
        return None
    cells = ids @ place_values(radix)
    codes, rank = np.unique(cells, return_inverse=True)
    rank = rank.ravel()
    direct = np.prod(radix.astype(float)) <= MAX_C_TABLE_CELLS
    if not direct and len(codes) + 1 > MAX_C_TABLE_CELLS:
        return None
    row_of = cells if direct else rank
    n_rows = int(np.prod(radix)) if direct else len(codes) + 1
    counts = np.bincount(row_of, minlength=n_rows)
    rows = np.full((n_rows, max(1, int(counts.max(initial=0)))), n_rules)
    order = np.argsort(row_of, kind="stable")
    slot = np.arange(n_rules) - np.searchsorted(row_of[order], row_of[order])
    rows[row_of[order], slot] = order
    return CellTable(radix, None if direct else codes, rows)


def cell_table_c(table: CellTable, P: str, p: str, n_rules: int) -> list[str]:
    """The C of the table: CELLS, and past the direct limit CODES and `cell_row`."""
    rows, codes = table.rows, table.codes
    lines = ["/* Per cell (tuple of term ids): its rules, padded with N_RULES. */"
             if codes is None else
             "/* Per occupied cell (tuple of term ids), in the order of CODES: its rules, "
             "padded with N_RULES; the last row, none, for every other cell. */",
             f"static const {index_type(n_rules)} {P}CELLS[{rows.shape[0]}]"
             f"[{rows.shape[1]}] = {int_table(rows)};"]
    if codes is None:
        return lines
    n, cell_type = len(codes), table.cell_type
    return lines + [
        "/* The occupied cells' codes, ascending. */",
        f"static const {cell_type} {P}CODES[{n}] = "
        "{" + ", ".join(str(int(c)) for c in codes) + "};",
        "/* The row of CELLS of a cell code: its rank in CODES (binary search), or "
        f"{n}, the row without rules. */",
        f"static inline int {p}cell_row({cell_type} code) {{",
        "    /* without branches on the data (a conditional move per step): the "
        "tuples' codes are unpredictable. lo + n <= N holds, so the probe never "
        "passes N - 1; the clamp says so to a prover (Frama-C EVA). */",
        f"    int lo = 0, n = {n}, at;",
        "    while (n > 1) {",
        "        int half = n / 2;",
        f"        int probe = lo + half < {n - 1} ? lo + half : {n - 1};",
        f"        lo = {P}CODES[probe] < code ? probe : lo;",
        "        n -= half;",
        "    }",
        f"    at = lo + ({P}CODES[lo] < code);",
        f"    return at < {n} && {P}CODES[at] == code ? at : {n};",
        "}"]


def cell_row_c(table: CellTable, p: str, code: str) -> str:
    """The C expression of the CELLS row of the cell code `code` (a C expression)."""
    return code if table.codes is None else f"{p}cell_row(({table.cell_type})({code}))"
