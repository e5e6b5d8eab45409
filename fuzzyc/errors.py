"""Diagnostics: every mistake in an input file is reported as file:line:col, the source line, a
caret, and a sentence that names the fix where it can. Front ends collect several and raise once.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass, field

from .model import SourceLoc


@dataclass
class Diagnostic:
    loc: SourceLoc | None
    message: str
    source_line: str | None = None

    def format(self) -> str:
        if self.loc is None:
            return f"error: {self.message}"
        text = f"{self.loc}: error: {self.message}"
        if self.source_line is not None:
            line = self.source_line.rstrip("\n").expandtabs(1)
            caret = " " * max(self.loc.col - 1, 0) + "^"
            text += f"\n    {line}\n    {caret}"
        return text


class FuzzycError(Exception):
    """One or more diagnostics about an input file. The CLI prints them and exits with 2."""

    def __init__(self, diagnostics: list[Diagnostic]):
        self.diagnostics = diagnostics
        super().__init__("\n".join(d.format() for d in diagnostics))


@dataclass
class Reporter:
    """Collects diagnostics for one source text, so a front end can go on after a mistake."""
    file: str
    text: str = ""
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def loc(self, line: int, col: int) -> SourceLoc:
        return SourceLoc(self.file, line, col)

    def error(self, loc: SourceLoc | None, message: str) -> None:
        line = None
        if loc is not None and self.text:
            lines = self.text.splitlines()
            if 1 <= loc.line <= len(lines):
                line = lines[loc.line - 1]
        self.diagnostics.append(Diagnostic(loc, message, line))

    def raise_if_any(self) -> None:
        if self.diagnostics:
            self.diagnostics.sort(key=lambda d: (d.loc.line, d.loc.col) if d.loc else (0, 0))
            raise FuzzycError(self.diagnostics)


def suggest(name: str, known: list[str] | tuple[str, ...]) -> str:
    """' — did you mean `X`?' when a close match exists, else the list of known names."""
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.5)
    if close:
        return f"did you mean `{close[0]}`?"
    if known:
        return "known: " + " ".join(known)
    return "none are declared"
