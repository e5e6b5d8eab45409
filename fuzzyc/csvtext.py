"""CSV lines as every reader takes them back: a name with a comma, a quote, a line feed or a
bare carriage return (a FIS file may name a variable so) is quoted.

The csv module quotes only the characters of its line terminator besides the delimiter and
the quote; with "\\n" as terminator it would leave a bare "\\r" unquoted and a reader would
split the row there. So rows are written with "\\r\\n" and end in "\\n" as the rest of our
output does.
"""
from __future__ import annotations

import csv
import io


def csv_line(fields) -> str:
    """One row of `fields` (texts) as a CSV line ending in a newline."""
    out = io.StringIO()
    csv.writer(out, lineterminator="\r\n").writerow(fields)
    return out.getvalue()[:-2] + "\n"
