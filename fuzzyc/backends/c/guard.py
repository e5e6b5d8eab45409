"""The last gate of every C header fuzzyc generates (float, double, q15, q31, lookup table):
`checked_header` reads the finished text the way a C compiler does and refuses it, before it
is returned or written, if user text could have become code.

User text (names, title, source path, units, notes) reaches a header in two forms only:
inside comments through `escape.c_comment` (no `*/`, `/*`, `??`, backslash or anything
outside printable ASCII) and as identifiers through `escape.c_identifier` ([A-Za-z0-9_]).  The
gate checks the result, not the call sites, so a call site that forgot `c_comment` (as the
q15/q31 "Derived worst case" sentence once did) is caught here:

1. characters: printable ASCII and newline only (no CR, NUL, tab, U+2028, ...);
2. no backslash and no `??`: no line splice, no trigraph, so what follows needs no escapes;
3. comments: the text splits into code and `/* ... */` comments (the lexer below is the
   compiler's because of 2 and because the code holds no `//`, `"` or `'`, which the
   generators never write: no line comments, no literals); every comment is closed, none
   holds a `/*`, and the code holds no `*/` (the mark a comment closed early);
4. user text: no comment delimiter the compiler honours overlaps a verbatim occurrence of a
   user text (inside it, or made of its first or last character and the header beside it).  A text written without escaping shows up verbatim, and one that closes or
   opens a comment puts the delimiter inside its own occurrence, so the header is refused
   (`c_comment` splits every `*/` and `/*`, so escaped text never holds one).  Texts
   without `*/` or `/*` cannot move a comment boundary, and what else 1 and 2 let through
   (a newline, a quote) is inert inside a block comment.

Sound for user text written verbatim; the identifiers are [A-Za-z0-9_] by construction
(tests/test_security_c_text.py also scans the back ends' f-strings for names that skip both
helpers).  A user text made of a delimiter and what the header writes around one (`*/`,
`1] */`) cannot be told from the header's own: it is refused with a message, never written.
"""
from __future__ import annotations

import bisect
import re

from ...errors import Diagnostic, FuzzycError
from ...semantics.model import Model

_NOT_PRINTABLE = re.compile(r"[^\x20-\x7e\n]")


def user_texts(model: Model) -> list[tuple[str, str]]:
    """(what, text) for every piece of user text a model carries."""
    texts = [("the controller's name", model.name), ("the title", model.title),
             ("the source path", model.source_path or "")]
    texts += [("a note", n) for n in model.notes]
    texts += [("a property", p.text) for p in model.properties]
    for kind, items in (("parameter", model.params.values()), ("signal", model.signals),
                        ("step", model.steps), ("output", model.outputs)):
        for item in items:
            texts += [(f"the {kind} name", item.name), (f"the unit of `{item.name}`",
                                                        item.unit or "")]
    for rb in model.blocks:
        texts.append(("the rule block name", rb.name))
        for var in (*rb.inputs, *rb.outputs):
            texts += [("the variable name", var.name),
                      (f"the unit of `{var.name}`", var.unit or "")]
            texts += [(f"a term name of `{var.name}`", t) for t in var.names]
    return texts


def _refuse(message: str) -> FuzzycError:
    return FuzzycError([Diagnostic(None, message)])


def _internal(header: str, at: int, rule: str) -> FuzzycError:
    line = header.count("\n", 0, at) + 1
    start = header.rfind("\n", 0, at) + 1
    end = header.find("\n", at)
    shown = header[start:end if end >= 0 else len(header)][:120]
    return _refuse(f"internal error in fuzzyc's C back end: the generated header {rule} at "
                   f"line {line} ({shown!r}); nothing was written. Please report this")


def comment_spans(header: str) -> list[tuple[int, int]]:
    """(start of `/*`, end of `*/`) of every comment, as the compiler finds them in a header
    that passes rules 1-2 and has no `//`, `"` or `'` in its code (checked by the caller)."""
    spans, i = [], 0
    while (start := header.find("/*", i)) >= 0:
        end = header.find("*/", start + 2)
        if end < 0:
            raise _internal(header, start, "leaves a comment open")
        spans.append((start, end + 2))
        i = end + 2
    return spans


def checked_header(header: str, model: Model) -> str:
    """`header` unchanged when it passes the rules of the module docstring, else FuzzycError."""
    bad = _NOT_PRINTABLE.search(header)
    if bad:
        raise _internal(header, bad.start(), f"holds {bad.group()!r}")
    for token in ("\\", "??"):
        if token in header:
            raise _internal(header, header.index(token), f"holds `{token}`")
    spans = comment_spans(header)
    code_from = 0
    for start, end in [*spans, (len(header), len(header))]:
        code = header[code_from:start]
        for token in ("*/", "//", '"', "'"):
            if token in code:
                raise _internal(header, code_from + code.index(token),
                                f"holds `{token}` outside a comment")
        body = header[start + 2:end - 2]
        if "/*" in body:
            raise _internal(header, start + 2 + body.index("/*"), "nests `/*` in a comment")
        code_from = end
    # every honoured delimiter's start: the `/*` and the `*/` of each comment
    delimiters = sorted([s for s, _ in spans] + [e - 2 for _, e in spans])
    for what, text in user_texts(model):
        if "*" not in text and "/" not in text:     # cannot be part of a delimiter
            continue
        at = header.find(text)
        while at >= 0:
            # a delimiter inside the occurrence, or one made of its first or last character
            # and the header's text beside it (`*` + "/ int x; /" + `*`)
            k = bisect.bisect_left(delimiters, at - 1)
            if k < len(delimiters) and delimiters[k] < at + len(text):
                raise _refuse(f"{what} {text!r} cannot be written into the C header: it meets "
                              "one of the header's comment delimiters (/* or */), so the "
                              "header could not be shown to hold it as inert text; rename it")
            at = header.find(text, at + 1)
    return header
