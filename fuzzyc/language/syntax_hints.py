"""What to write instead, for the syntax errors a newcomer makes first (issue 30).

Each function looks at one lark error and, when it recognises the mistake, returns where to
report it and a message that says the fix: a statement left unfinished on its line (`var u`
with no range: reported at `u`, not at the next statement), a keyword in upper case (FCL's
`IF ... IS ... THEN`), another format's name for a term shape (MATLAB's `trimf`).
"""
from __future__ import annotations

import difflib
import functools
import re

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedToken
from lark.lexer import PatternStr

from ..errors import source_lines
from ..semantics.shapes import SHAPES, shape_words
from .recovery import statement_starts, statement_words

Hint = tuple[int, int, str]         # line, column, message


# -- a term shape under another format's name ------------------------------------------------

def shape_suggestion(name: str) -> str | None:
    """`did you mean `tri`?` for another format's name of a shape (the registry's), or for a
    near miss of one of ours; None when nothing is close."""
    key = name.lower()
    words = [w.word for s in SHAPES.values() for w in s.words
             if key in {n.lower() for n in w.names}]
    order = ""
    if not words:
        for shape in SHAPES.values():
            if len(shape.words) == 1 and key in {n.lower() for n in
                                                 (shape.fll, shape.fcl, shape.fis) if n}:
                words = [shape.words[0].word]
                if shape.fis_params is not None and key == shape.fis.lower():
                    order = " (its numbers in fuzzyc's order, not MATLAB's: see docs/language.md)"
    if not words:
        words = difflib.get_close_matches(key.removesuffix("mf"), shape_words(), n=1, cutoff=0.6)
    if not words:
        return None
    return f"did you mean {' or '.join(f'`{w}`' for w in words)}?{order}"


# -- a keyword in upper case -----------------------------------------------------------------

def keyword_case(parser: Lark, exc: UnexpectedToken, keywords: frozenset[str],
                 text: str) -> Hint | None:
    """`IF` where `if` is taken: the offending token, or the name just read that made the parse
    go wrong (`rule IF a`: `IF` is read as the rule's name, `a` is the error)."""
    ip = exc.interactive_parser
    if ip is None:
        return None
    token = exc.token
    state = ip.parser_state
    table = state.parse_conf.states
    if _taken_in_lower_case(parser, token, keywords, table[state.position]):
        return _case_message(token, text, keywords)
    previous = state.value_stack[-1] if state.value_stack else None
    if isinstance(previous, Token) and len(state.state_stack) >= 2 and _taken_in_lower_case(
            parser, previous, keywords, table[state.state_stack[-2]]):
        return _case_message(previous, text, keywords)
    return None


def _taken_in_lower_case(parser: Lark, token: Token, keywords: frozenset[str],
                         row: dict) -> bool:
    word = str(token).lower()
    return (token.type == "NAME" and str(token) != word and word in keywords
            and bool(_terminals_of(parser, word) & set(row)))


def _case_message(token: Token, text: str, keywords: frozenset[str]) -> Hint:
    line = source_lines(text)[token.line - 1]
    later = [w for w in re.findall(r"[A-Za-z_]\w*", line[token.end_column - 1:])
             if w.lower() in keywords and w != w.lower()]
    also = ""
    if later:
        also = f" (and {', '.join(f'`{w.lower()}`' for w in dict.fromkeys(later))} " \
               "later on this line)"
    return (token.line, token.column,
            f"`{token}` is not a keyword: keywords are lower case: write "
            f"`{str(token).lower()}`{also}")


def _terminals_of(parser: Lark, word: str) -> frozenset[str]:
    return _keyword_terminals(parser).get(word, frozenset())


@functools.cache
def _keyword_terminals(parser: Lark) -> dict[str, frozenset[str]]:
    """keyword -> the terminals that read it (`and` is AND and INFERENCE_KEY)."""
    found: dict[str, set[str]] = {}
    for terminal in parser.terminals:
        if terminal.name in ("NAME", "DOTTED_NAME"):
            continue
        if isinstance(terminal.pattern, PatternStr):
            found.setdefault(terminal.pattern.value, set()).add(terminal.name)
            continue
        regexp = re.compile(terminal.pattern.to_regexp())
        for word in re.findall(r"[a-z_]+", terminal.pattern.value):
            if regexp.fullmatch(word):
                found.setdefault(word, set()).add(terminal.name)
    return {word: frozenset(names) for word, names in found.items()}


# -- a statement left unfinished at the end of its line --------------------------------------

def unfinished_statement(parser: Lark, exc: UnexpectedToken, text: str,
                         expected: str) -> Hint | None:
    """A statement that stops before its end, the error found only at the next line's
    statement, `}` or the end of the file: reported right after the statement's last token,
    on its own line (`var u` with no range says line 3, not where `terms` begins line 4)."""
    ip = exc.interactive_parser
    token = exc.token
    if ip is None:
        return None
    starts = statement_starts(parser)
    if token.type == "KEYWORD_AS_NAME":         # `terms` where a name could stand
        token = token.update(type=statement_words(parser).get(str(token), token.type))
    if token.type not in starts and token.type not in ("RBRACE", "$END"):
        return None
    state = ip.parser_state
    row = set(state.parse_conf.states[state.position])
    if row & (starts | {"RBRACE"}):
        return None         # the statement before is complete: the mistake is the token's
    last = _last_token(state.value_stack)
    if last is None or (token.type != "$END" and last.end_line >= token.line):
        return None
    keyword = _statement_keyword(state.value_stack, starts)
    written = _written(last, text, keyword)
    message = f"`{written}` is unfinished: expected {expected} after `{last}`"
    if keyword is not None and keyword.type in ("VAR", "INPUT") and "IN" in row:
        message += f"; write `{written} in [low, high]`"       # the range they must have
    if token.type == "$END":
        message += "; the file ends there"
    return last.end_line, last.end_column, message


# The longest part of an unfinished statement a message quotes (its end, where the error is).
MAX_QUOTED = 40


def _statement_keyword(values: list, starts: frozenset[str]) -> Token | None:
    """The word that began the statement in progress (`var`), or the controller's header."""
    for value in reversed(values):
        if isinstance(value, Token) and (value.type in starts or value.type == "CONTROLLER"):
            return value
        if isinstance(value, Token) and value.type == "LBRACE":
            return None
    return None


def _written(last: Token, text: str, keyword: Token | None) -> str:
    """The unfinished statement as written on its last line, from its keyword when that is
    on the line (`var u`, not the `controller c {` before it), shortened to its end."""
    line = source_lines(text)[last.end_line - 1]
    begin = len(line) - len(line.lstrip())
    if keyword is not None and keyword.line == last.end_line:
        begin = keyword.column - 1
    written = line[begin:last.end_column - 1].strip()
    return written if len(written) <= MAX_QUOTED else "..." + written[-MAX_QUOTED:]


def unclosed_brace(exc: UnexpectedToken) -> str | None:
    """At the end of the file, the `{` still open: which line opened it, and what to write."""
    ip = exc.interactive_parser
    if ip is None:
        return None
    for value in reversed(ip.parser_state.value_stack):
        if isinstance(value, Token) and value.type == "LBRACE":
            return (f"the file ends too early: the `{{` of line {value.line} is not closed; "
                    "write `}`")
    return None


def _last_token(values: list) -> Token | None:
    """The last token read: the top of the value stack, or the last token of a subtree."""
    for value in reversed(values):
        if isinstance(value, Token):
            return value
        if isinstance(value, Tree):
            tokens = list(value.scan_values(lambda v: isinstance(v, Token)))
            if tokens:
                return max(tokens, key=lambda t: (t.end_line, t.end_column))
    return None
