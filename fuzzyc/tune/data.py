"""Data for a tune: a CSV with a header row naming the rule base's inputs and outputs (other
columns are ignored), and the sha256 of its bytes for the provenance."""
from __future__ import annotations

import csv
import hashlib
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..csvtext import csv_line
from ..semantics.model import Model


@dataclass
class Table:
    name: str                 # the file name, as the provenance says it
    sha256: str
    x: np.ndarray             # (N, I) in the rule base's input order
    y: np.ndarray             # (N, O) in its output order


def read_csv(path: str | Path, model: Model) -> Table:
    path = Path(path)
    raw = path.read_bytes()
    rows = list(csv.reader(io.StringIO(raw.decode("utf-8-sig"))))
    if len(rows) < 2:
        raise ValueError(f"{path}: a header row and at least one row of numbers are needed")
    header = [h.strip() for h in rows[0]]
    rb = model.rulebase
    wanted = [v.name for v in rb.inputs] + [v.name for v in rb.outputs]
    missing = [n for n in wanted if n not in header]
    if missing:
        raise ValueError(f"{path}: no column for {', '.join(missing)} (the header has "
                         f"{', '.join(header)})")
    columns = [header.index(n) for n in wanted]
    values = np.empty((len(rows) - 1, len(wanted)))
    for r, row in enumerate(rows[1:], start=2):
        try:
            values[r - 2] = [float(row[c]) for c in columns]
        except (ValueError, IndexError):
            raise ValueError(f"{path}:{r}: a row of numbers is needed for "
                             f"{', '.join(wanted)}") from None
    n_in = len(rb.inputs)
    return Table(path.name, hashlib.sha256(raw).hexdigest(), values[:, :n_in], values[:, n_in:])


def write_csv(path: str | Path, names: list[str], columns: np.ndarray) -> None:
    """Columns under a header, each number as the shortest text that reads back the same."""
    lines = [csv_line(names)] + [csv_line([repr(float(v)) for v in row]) for row in columns]
    Path(path).write_text("".join(lines))
