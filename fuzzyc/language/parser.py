"""The .fz front end: text -> lark parse tree -> syntax objects -> Model.

Syntax errors are reported per statement: lark's error recovery (`.recovery`) skips the rest of
a broken statement and parses on from the next, so one run reports every broken statement (up
to MAX_SYNTAX_ERRORS), not just the first.  Where `.syntax_hints` recognises the mistake (a
statement unfinished on its line, an upper-case keyword, another format's shape name) the
message says what to write, at the place to write it.
"""
from __future__ import annotations

import functools
import re
from importlib import resources
from pathlib import Path

from lark import Lark, Token, Tree
from lark.lark import PostLex
from lark.lexer import PatternStr
from lark.parsers.lalr_parser_state import ParserState
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from .builder import Builder
from ..errors import Reporter, shown_char, source_lines
from ..escape import FZ_QUOTED_NAME, SAFE_NAME
from .limits import MAX_NESTING, check_model, number_problem, read_rule_file
from .recovery import Recovery
from .syntax_hints import keyword_case, shape_suggestion, unclosed_brace, unfinished_statement
from ..semantics.model import Model
from ..semantics.shapes import shape_words as registry_words
from .syntax import ToSyntax

# Syntax errors reported in one run; past it the last one says that more follow.  A limit of
# the front end like those of fuzzyc.language.limits (it belongs there and in docs/limits.md).
MAX_SYNTAX_ERRORS = 20

# MAX_NESTING (fuzzyc.language.limits): the tree depth the transformer and the builder recurse
# through (a statement and its expression's operators each take a level).

# How the parser's terminal names read in a message.
READABLE = {
    "NAME": "a name", "SIGNED_NUMBER": "a number", "NUMBER": "a number", "INT": "a rule number",
    "SIGNED_INT": "a whole number", "STRING": "a quoted title", "LBRACE": "`{`", "RBRACE": "`}`",
    "LPAR": "`(`", "RPAR": "`)`", "LSQB": "`[`", "RSQB": "`]`", "COMMA": "`,`", "COLON": "`:`",
    "SEMICOLON": "`;`", "EQUAL": "`=`", "ARROW": "`->`", "HEDGE": "a hedge", "NOT": "`not`",
    "INFERENCE_KEY": "an inference setting (and, or, implication, aggregation, defuzzify)",
    "AXIS": "`rows` or `cols`", "DIRECTION": "`increasing` or `decreasing`",
    "COMPARE": "a comparison (<, <=, >, >=)", "DOTTED_NAME": "a parameter name",
    "PERCENT": "`%`", "UNIT_OP": "`/` or `*`", "$END": "the end of the file",
    "DOT": "`.`", "PLUSMINUS": "`+/-`",
}


class _Names(PostLex):
    """NAME is in every state of lark's contextual lexer: a keyword string then matches only
    when NAME matches exactly it (lark turns that NAME into the keyword), so `ruleset`, `isA`,
    `iffy` are names, never a keyword with letters glued on.  A NAME still spelled like a
    keyword stands where the keyword does not: it becomes KEYWORD_AS_NAME, which no rule
    accepts (`_report` says what to write); a name in backticks loses them."""
    always_accept = ("NAME",)

    def process(self, stream):
        for tok in stream:
            if tok.type in ("NAME", "DOTTED_NAME"):
                if tok in keywords():      # `controller.Vset`: a dotted name is never a keyword
                    tok = tok.update(type="KEYWORD_AS_NAME")
                elif "`" in tok:
                    tok = tok.update(value=tok.replace("`", ""))
            yield tok


def _grammar() -> str:
    text = resources.files("fuzzyc").joinpath("language/grammar/fuzzyc.lark").read_text()
    return text.replace("/`QUOTED_NAME`/", f"/`{FZ_QUOTED_NAME.pattern}`/")


@functools.lru_cache(maxsize=1)
def _lark() -> Lark:
    return Lark(_grammar(), parser="lalr", start=["start", "statements"],
                propagate_positions=True, postlex=_Names())


@functools.lru_cache(maxsize=1)
def keywords() -> frozenset[str]:
    """Every word of the grammar (its quoted literals): a name spelled like one is written in
    backticks, `rule`."""
    code = re.sub(r"//[^\n]*", "", _grammar())
    return frozenset(re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)"', code))


def fz_name(name: str) -> str:
    """`name` as .fz text: in backticks when it is a keyword or no plain identifier
    (`Food-Quality`); a name no backticks can hold (escape.FZ_QUOTED_NAME) is refused by the
    writer first (formats.export.unsayable_names)."""
    return f"`{name}`" if name in keywords() or not SAFE_NAME.fullmatch(name) else name


def load(path: str | Path) -> Model:
    """Parse and check a .fz file; raises FuzzycError with every diagnostic found."""
    path = Path(path)
    return parse(read_rule_file(path), str(path))


def parse(text: str, path: str = "<string>") -> Model:
    reporter = Reporter(path, text)
    tree = _parse_tree(text, reporter)
    reporter.raise_if_any()
    if tree is None:
        raise AssertionError("a syntax error was found but not reported")  # pragma: no cover
    too_deep = _first_too_deep(tree)
    if too_deep is not None:
        reporter.error(reporter.loc(too_deep.meta.line, too_deep.meta.column),
                       f"an expression nested more than {MAX_NESTING} operators deep; split it "
                       "with `let` signals")
        reporter.raise_if_any()
    _check_numbers(tree, reporter)
    reporter.raise_if_any()
    syntax = ToSyntax(path).transform(tree)
    model = Builder(reporter).build(syntax, text, path)
    check_model(model)
    return model


def _check_numbers(tree, reporter: Reporter) -> None:
    """Every number literal within the stated limits, reported where it is written."""
    for tok in tree.scan_values(lambda t: isinstance(t, Token)
                                and t.type in ("NUMBER", "SIGNED_NUMBER")):
        problem = number_problem(float(tok))
        if problem is not None:
            reporter.error(reporter.loc(tok.line, tok.column), problem)


def _first_too_deep(tree: Tree) -> Tree | None:
    """The first node nested deeper than MAX_NESTING: what follows recurses through the tree, and
    long sums and products are flat lists, so only brackets nest this deep."""
    stack = [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_NESTING:
            return node
        stack.extend((child, depth + 1) for child in node.children if isinstance(child, Tree))
    return None


def _parse_tree(text: str, reporter: Reporter) -> Tree | None:
    """The parse tree, or None; every syntax error found goes to `reporter` (the tree of a
    file with errors is one lark patched up to go on, never used)."""
    def too_many() -> None:
        reporter.diagnostics[-1].message += (
            f"; more syntax errors follow (fuzzyc reports the first {MAX_SYNTAX_ERRORS}, "
            "fuzzyc.language.parser.MAX_SYNTAX_ERRORS)")

    recovery = Recovery(_lark(), lambda exc: _report(exc, reporter), MAX_SYNTAX_ERRORS, too_many)
    try:
        return _lark().parse(text, start="start", on_error=recovery)
    except UnexpectedInput:
        return None         # reported by `recovery`, which stops at the end or the limit


def _report(exc: UnexpectedInput | None, reporter: Reporter) -> None:
    if exc is None:
        return
    if isinstance(exc, UnexpectedCharacters):
        reporter.error(reporter.loc(exc.line, exc.column),
                       f"unexpected character {shown_char(exc.char)}")
        return
    hint = _hint(exc, reporter.text) if isinstance(exc, UnexpectedToken) else None
    if hint is not None:
        line, col, message = hint
        reporter.error(reporter.loc(line, col), message)
        return
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken)
                                          and exc.token.type == "$END"):
        lines = source_lines(reporter.text)
        last = max(len(lines) - (lines[-1] == ""), 1)
        message = isinstance(exc, UnexpectedToken) and unclosed_brace(exc)
        reporter.error(reporter.loc(last, 1), message or "the file ends too early: a "
                       "statement or the closing `}` of the controller is missing")
        return
    token: Token = exc.token
    if token.type == "KEYWORD_AS_NAME" and _expected(exc) & {"NAME", "DOTTED_NAME"}:
        reporter.error(reporter.loc(token.line, token.column),
                       f"`{token}` is a keyword, not a name; a name spelled like a keyword is "
                       f"written in backticks (`{token}` with the backticks typed)")
        return
    reporter.error(reporter.loc(token.line, token.column),
                   f"unexpected `{token}`; expected {_expected_text(exc)}")


def _hint(exc: UnexpectedToken, text: str) -> tuple[int, int, str] | None:
    """The error said with its fix, where `syntax_hints` recognises the mistake."""
    found = unfinished_statement(_lark(), exc, text, _expected_text(exc)) \
        or keyword_case(_lark(), exc, keywords(), text)
    if found is not None:
        return found
    token = exc.token
    if token.type == "NAME" and "SHAPE" in _expected(exc):
        suggestion = shape_suggestion(str(token))
        if suggestion is not None:
            return (token.line, token.column,
                    f"unknown term shape `{token}`: {suggestion}")
    return None


def _expected_text(exc: UnexpectedToken) -> str:
    expected = _expected(exc)
    if "SHAPE" in expected:     # `formula("...")` is said with the shapes
        expected.discard("FORMULA")
    return _one_of(sorted({_readable(t) for t in expected if not t.startswith("__")}))


def _expected(exc: UnexpectedToken) -> set[str]:
    """What the parser takes where the error is: lark's `accepts()` tries each terminal (the
    parse table's row also lists look-aheads of LALR-merged states, `bounded` after `e is N`).
    A token the lexer did not expect comes with what the lexer knew instead: NAME always
    (`_Names.always_accept`), a keyword only as the NAME it is spelled like (`at` expects
    `least`, not a name)."""
    if exc.interactive_parser is not None:
        return set(exc.interactive_parser.accepts())
    state = exc.state
    if isinstance(state, ParserState):
        return {t for t in state.parse_conf.states[state.position] if t.isupper()}
    return set(exc.expected)


def _readable(terminal: str) -> str:
    """How a terminal of the grammar reads in a message: its words, or the text it stands for
    (`-` for MINUS, `let` for LET)."""
    if terminal == "SHAPE":     # the registry's words (tests hold the grammar's equal to them)
        return f"a term shape ({', '.join(sorted(registry_words()))}) or `formula(\"...\")`"
    if terminal in READABLE:
        return READABLE[terminal]
    literal = _literals().get(terminal)
    return f"`{literal}`" if literal is not None else f"`{terminal.lower()}`"


@functools.lru_cache(maxsize=1)
def _literals() -> dict[str, str]:
    """Terminal name -> the one text it matches, for the terminals that are a fixed text."""
    return {t.name: t.pattern.value for t in _lark().terminals if isinstance(t.pattern, PatternStr)}


@functools.lru_cache(maxsize=1)
def shape_words() -> tuple[str, ...]:
    """The term shapes the grammar takes, from its SHAPE terminal (`(?:tri|trap|...)\\b` once
    lark has compiled it): the one list the message about a shape names."""
    pattern = _lark().get_terminal("SHAPE").pattern.value.replace("\\b", "")
    return tuple(sorted(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", pattern)))


def _one_of(options: list[str]) -> str:
    if len(options) > 6:
        options = options[:6] + ["..."]
    return options[0] if len(options) == 1 else "one of " + ", ".join(options)
