"""The tuned .fz: the source text with only the tuned numbers replaced, where they are written
(comments, layout and every other number kept), and a provenance comment block on top.

A number is written as the shortest text that reads back as the same float, so the file
parses to exactly the tuned values; a rule weight that was not written (`with w` left out)
is added at the end of its rule."""
from __future__ import annotations

import re

from ..formats.export import num
from ..semantics.tunable import TunedNumber

NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
BEGIN = "# ---- fuzzyc tune: provenance"
END = "# ---- end of provenance"


def rewrite(text: str, numbers: list[TunedNumber], values, provenance: list[str]) -> str:
    """`text` with each tuned number set to its value, and the provenance block on top (an
    earlier block, from an earlier tune, is replaced)."""
    lines = text.split("\n")          # a \r of a \r\n ending stays where it is
    edits = []          # (line index, column index, old length, new text)
    for n, value in zip(numbers, values):
        if n.token is not None:
            line, col = n.token.line - 1, n.token.col - 1
            match = NUMBER.match(lines[line], col)
            if match is None:
                raise ValueError(f"{n.token}: no number where `{n.target}` is written")
            edits.append((line, col, len(match.group(0)), num(value)))
        elif n.insert_at is not None:
            line, col = n.insert_at.line - 1, n.insert_at.col - 1
            edits.append((line, col, 0, f" with {num(value)}"))
    for start, end, text in _absolute_sections(numbers):
        edits.append((start.line - 1, start.col - 1, None, (end.line - 1, end.col - 1, text)))
    for line, col, length, new in sorted(edits, key=lambda e: e[:2], reverse=True):
        if length is None:              # a whole `tune` statement, over several lines
            last, end, text = new
            lines[line:last + 1] = (lines[line][:col] + text + lines[last][end:]).split("\n")
        else:
            lines[line] = lines[line][:col] + new + lines[line][col + length:]
    body = "\n".join(lines)
    return "\n".join(_block(provenance)) + "\n" + _without_block(body)


def _absolute_sections(numbers: list[TunedNumber]):
    """(start, end, text) of each `tune` statement with a `+/- d` bound: written again with
    every number's bound absolute, one line each, as the tuner used them (relative to the
    tuned values they would mean another box)."""
    from ..language.parser import fz_name
    sections: dict = {}
    for n in numbers:
        if n.section is not None:
            sections.setdefault(n.section, []).append(n)
    for (start, end), inside in sections.items():
        if not any(n.spread for n in inside):
            continue
        pad = " " * (start.col + 1)
        lines = [f"{pad}{'.'.join(fz_name(p) for p in n.target.split('.'))} in "
                 f"[{num(n.lo)}, {num(n.hi)}]" for n in inside]
        yield start, end, "tune {  # the bounds as tuned, absolute\n" + "\n".join(lines) + \
            "\n" + " " * (start.col - 1) + "}"


def _block(provenance: list[str]) -> list[str]:
    return [BEGIN, *(f"# {line}".rstrip() for line in provenance), END]


def _without_block(text: str) -> str:
    lines = text.split("\n")
    if lines and lines[0] == BEGIN and END in lines:
        return "\n".join(lines[lines.index(END) + 1:])
    return text
