"""User text on its way into generated files: one function per target, each either makes the
text inert there or refuses it with a FuzzycError that names it.

No input is trusted: titles, notes, descriptions, source paths and the names of models,
variables and terms can come from any imported file.  See docs/security.md.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

from .errors import Diagnostic, FuzzycError

SAFE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# what a .fz name may hold between backticks (`Food-Quality`, `rule`): any character but a
# backtick, a dot (dotted names select in `tune` and `vary`) and line breaks or control
# characters; the grammar's NAME takes this very pattern (language/parser.py `_grammar`)
FZ_QUOTED_NAME = re.compile(r"[^`.\x00-\x1f\x7f\x85\u2028\u2029]+")


def c_comment(text: str) -> str:
    """`text` as it may stand inside a C block comment: it can neither end the comment nor
    start a new one, nor splice lines.

    Everything outside printable ASCII (newlines, control characters, non-ASCII letters)
    becomes <U+XXXX>; a backslash becomes `/` (a backslash before a newline, also the `??/`
    trigraph, splices lines); then `*/` and `/*` are split by a space and `??` by a space
    (no trigraph), repeated until none is left (`*/*/` leaves a new pair after one pass).
    """
    shown = "".join(c if " " <= c <= "~" else f"<U+{ord(c):04X}>" for c in text)
    shown = shown.replace("\\", "/")
    while True:
        split = (shown.replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?"))
        if split == shown:
            return shown
        shown = split


def c_identifier(name: str) -> str:
    """A C identifier made of [A-Za-z0-9_] only: every other character becomes `_`, a leading
    digit (or an empty name) gets `m_` in front.  Not one-to-one: `check_c_names` refuses a
    model whose names meet."""
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return ident if ident[:1].isalpha() or ident[:1] == "_" else "m_" + ident


def check_c_names(names) -> None:
    """FuzzycError when two different names give the same C identifier, upper-cased as the
    #define names are (`a-b` and `a_b`, `e1` and `E1`): the header would not compile."""
    seen: dict[str, str] = {}
    clashes = []
    for name in dict.fromkeys(names):
        key = c_identifier(name).upper()
        if key in seen:
            clashes.append(f"`{seen[key]}` and `{name}` give the same C name "
                           f"{c_identifier(name)} (C names are letters, digits and _, and the "
                           "#defines are upper case): rename one")
        seen.setdefault(key, name)
    if clashes:
        raise FuzzycError([Diagnostic(None, c) for c in clashes])


def one_line(text: str) -> str:
    """Text for a one-line field of a text format (a description, a comment line): line breaks
    and other control characters become spaces, so the text cannot start a line of its own."""
    return "".join(" " if c < " " or c == "\x7f" or c in "\u2028\u2029\x85" else c
                   for c in text)


def plot_text(text: str) -> str:
    """Text for a matplotlib label or title, shown as written: a `$` would start mathtext,
    which renders (or fails to parse, `$\\frac{$`) as TeX."""
    return text.replace("$", r"\$")


def name_problems(names, fmt: str, allowed: re.Pattern = SAFE_NAME,
                  rule: str = "letters, digits and _, not starting with a digit") -> list[str]:
    """A sentence per name the target format cannot say as written (`allowed` must match all
    of it), for the exporters' refusal lists; the name is shown with repr so the odd
    characters are visible."""
    return [f"the name {name!r} cannot be written in {fmt} (a name there is {rule}); "
            "rename it" for name in dict.fromkeys(names) if not allowed.fullmatch(name)]


class OutputFolder:
    """Files named after user text in one output folder: each name is made of [A-Za-z0-9_.-]
    (others become `_`, no leading dot), so it can neither leave the folder (`a/../../x`) nor
    hide; names that meet get _2, _3, ... instead of overwriting each other."""

    def __init__(self, folder: str | os.PathLike):
        self.folder = Path(folder)
        self.used: set[str] = set()

    def file(self, stem: str, suffix: str) -> Path:
        safe = re.sub(r"[^A-Za-z0-9_.-]", "_", stem).lstrip(".") or "unnamed"
        name, n = safe + suffix, 2
        while name in self.used:
            name, n = f"{safe}_{n}{suffix}", n + 1
        self.used.add(name)
        path = self.folder / name
        if path.parent != self.folder:   # cannot happen with the alphabet above: say so if it does
            raise FuzzycError([Diagnostic(None, f"{name!r} is not a file name inside "
                                                f"{self.folder}")])
        return path
