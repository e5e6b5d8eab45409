"""Hypothesis strategies that turn a well-formed seed file into a hostile one.

Each input is a seed file with one to four mutations applied in turn: line edits (delete,
duplicate, swap), token edits (a token replaced by a hostile value or by another token of the
same file), character insertions, truncation, splicing two seeds, and byte-level damage
(BOM, invalid UTF-8, Latin-1 re-encoding). Hypothesis picks every choice, so a run is
reproducible from its seed and the inputs lean towards the edge cases hypothesis favours.
"""
from __future__ import annotations

import re

from hypothesis import strategies as st

# Values no well-formed file has at that place: numbers at the float limits, words the formats
# treat specially, the line breaks Python's splitlines() knows and text editors do not, control
# characters, unbalanced brackets and YAML syntax.
HOSTILE = (
    "1e400", "-1e400", "1e308", "-1e308", "1e-320", "nan", "NaN", "-nan", "inf", "-inf",
    "Infinity", "0", "-0", "0.0", "-1", "9" * 400, "0x1F", "1_000", "1e", ".", "-", "+",
    "", " ", "\t", "\v", "\f", "\r", "\r\n", "\x85", "\u2028", "\u2029", "\x00", "\ufeff",
    "\x1b[31m", "é", "名前", "𝔵", "a" * 300,
    "(", ")", "[", "]", "{", "}", ",", ";", ":", "::", "=", "'", '"', "#", "%", "//", "(*",
    "*)", "/*", "*/", "\\",
    "null", "~", "true", "yes", "[]", "{}", "[1, 2]", "{a: 1}", "- x", "&a", "*a", "!!binary",
    "!!python/object:os.system", "---", "...", "|", ">",
)
TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|\S")


def _lines(text: str) -> list[str]:
    return text.splitlines(keepends=True) or [""]


@st.composite
def _line_edit(draw, text: str) -> str:
    lines = _lines(text)
    i = draw(st.integers(0, len(lines) - 1))
    kind = draw(st.sampled_from(("delete", "duplicate", "swap")))
    if kind == "delete":
        del lines[i]
    elif kind == "duplicate":
        lines.insert(i, lines[i])
    else:
        j = draw(st.integers(0, len(lines) - 1))
        lines[i], lines[j] = lines[j], lines[i]
    return "".join(lines)


@st.composite
def _token_edit(draw, text: str) -> str:
    tokens = list(TOKEN.finditer(text))
    if not tokens:
        return text + draw(st.sampled_from(HOSTILE))
    token = tokens[draw(st.integers(0, len(tokens) - 1))]
    other = st.sampled_from([t.group() for t in tokens])
    value = draw(st.one_of(st.sampled_from(HOSTILE), other, st.text(max_size=8)))
    return text[:token.start()] + value + text[token.end():]


@st.composite
def _insert(draw, text: str) -> str:
    at = draw(st.integers(0, len(text)))
    return text[:at] + draw(st.sampled_from(HOSTILE)) + text[at:]


@st.composite
def _truncate(draw, text: str) -> str:
    return text[:draw(st.integers(0, len(text)))]


@st.composite
def _splice(draw, text: str, seeds: tuple[str, ...]) -> str:
    other = draw(st.sampled_from(seeds))
    return text[:draw(st.integers(0, len(text)))] + other[draw(st.integers(0, len(other))):]


def text_mutation(text: str, seeds: tuple[str, ...]) -> st.SearchStrategy[str]:
    return st.one_of(_line_edit(text), _token_edit(text), _token_edit(text), _insert(text),
                     _truncate(text), _splice(text, seeds))


@st.composite
def _encode(draw, text: str) -> bytes:
    """The text as UTF-8, now and then damaged at the byte level."""
    data = text.encode("utf-8", "surrogatepass")
    kind = draw(st.sampled_from(("utf-8",) * 6 + ("bom", "latin-1", "bad byte")))
    if kind == "bom":
        return b"\xef\xbb\xbf" + data
    if kind == "latin-1":
        return text.encode("latin-1", "replace")
    if kind == "bad byte":
        at = draw(st.integers(0, len(data)))
        return data[:at] + draw(st.sampled_from((b"\xff", b"\xc3", b"\xed\xa0\x80"))) + data[at:]
    return data


@st.composite
def mutated(draw, text: str, seeds: tuple[str, ...]) -> bytes:
    """`text` with one to four mutations (a splice takes a tail from `seeds`), as bytes."""
    for _ in range(draw(st.integers(1, 4))):
        text = draw(text_mutation(text, seeds))
    return draw(_encode(text))
