"""Diagnostics: every mistake in an input file is reported as file:line:col, the source line, a
caret, and a sentence that names the fix where it can. Front ends collect several and raise once.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from pathlib import Path

from .semantics.model import SourceLoc


def source_lines(text: str) -> list[str]:
    r"""The lines as lark numbers them: split at newlines only (str.splitlines also splits at
    vertical tab, form feed, U+2028 and others, which would put the caret on the wrong line);
    the \r of a \r\n ending is dropped."""
    return [line.removesuffix("\r") for line in text.split("\n")]


@dataclass
class Diagnostic:
    loc: SourceLoc | None
    message: str
    source_line: str | None = None
    severity: str = "error"          # or "warning": the file is read, the reader is told

    def format(self) -> str:
        if self.loc is None:
            return f"{self.severity}: {self.message}"
        text = f"{self.loc}: {self.severity}: {self.message}"
        if self.source_line is not None:
            # One column per character: a tab, a form feed or a U+2028 shows as a space.
            line = "".join(c if c.isprintable() else " " for c in self.source_line.rstrip("\r\n"))
            caret = " " * max(self.loc.col - 1, 0) + "^"
            text += f"\n    {line}\n    {caret}"
        return text


class FuzzycError(Exception):
    """One or more diagnostics about an input file. The CLI prints them and exits with 2."""

    def __init__(self, diagnostics: list[Diagnostic]):
        self.diagnostics = diagnostics
        super().__init__("\n".join(d.format() for d in diagnostics))


def read_source(path: str | Path) -> str:
    """A rule file's text (UTF-8, a byte-order mark allowed); FuzzycError when it cannot be read,
    with file:line:col of the first byte that is not UTF-8."""
    try:
        data = Path(path).read_bytes()
    except (OSError, ValueError) as exc:      # ValueError: a NUL in the name
        raise FuzzycError([Diagnostic(None, f"cannot read {path}: {exc}")]) from None
    return decode_source(data, path)


def decode_source(data: bytes, path: str | Path) -> str:
    """`data` as UTF-8 (a byte-order mark allowed), or a FuzzycError at the first bad byte."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line_start = data.rfind(b"\n", 0, exc.start) + 1
        line = data.count(b"\n", 0, exc.start) + 1
        col = len(data[line_start:exc.start].decode("utf-8-sig", errors="replace")) + 1
        shown = data[line_start:].split(b"\n", 1)[0].decode("utf-8-sig", errors="replace")
        raise FuzzycError([Diagnostic(SourceLoc(str(path), line, col),
                                      f"byte 0x{data[exc.start]:02x} is not UTF-8: save the file "
                                      "as UTF-8", shown)]) from None


@dataclass
class Reporter:
    """Collects diagnostics for one source text, so a front end can go on after a mistake."""
    file: str
    text: str = ""
    diagnostics: list[Diagnostic] = field(default_factory=list)
    warnings: list[Diagnostic] = field(default_factory=list)

    def loc(self, line: int, col: int) -> SourceLoc:
        return SourceLoc(self.file, line, col)

    def error(self, loc: SourceLoc | None, message: str) -> None:
        self.diagnostics.append(Diagnostic(loc, message, self._line(loc)))

    def warn(self, loc: SourceLoc | None, message: str) -> None:
        """A finding that does not stop the file being read (`fuzzyc check` prints it)."""
        self.warnings.append(Diagnostic(loc, message, self._line(loc), "warning"))

    def _line(self, loc: SourceLoc | None) -> str | None:
        if loc is not None and self.text:
            lines = source_lines(self.text)
            if 1 <= loc.line <= len(lines):
                return lines[loc.line - 1]
        return None

    def raise_if_any(self) -> None:
        if self.diagnostics:
            self.diagnostics.sort(key=lambda d: (d.loc.line, d.loc.col) if d.loc else (0, 0))
            raise FuzzycError(self.diagnostics)


def shown_char(char: str) -> str:
    """A character for a message: `x`, or U+000B for one that does not print."""
    return f"`{char}`" if char.isprintable() else f"U+{ord(char):04X}"


def suggest(name: str, known: list[str] | tuple[str, ...]) -> str:
    """' — did you mean `X`?' when a close match exists, else the list of known names."""
    close = difflib.get_close_matches(str(name), list(known), n=1, cutoff=0.5)  # a YAML key: 1.5
    if close:
        return f"did you mean `{close[0]}`?"
    if known:
        return "known: " + " ".join(known)
    return "none are declared; declare it first"
