"""The .fz front end: text -> lark parse tree -> syntax objects -> Model.

Syntax errors are reported per statement: when the whole file does not parse, each statement
is parsed on its own, so one run reports every broken statement, not just the first.
"""
from __future__ import annotations

import functools
import re
from importlib import resources
from pathlib import Path

from lark import Lark, Token, Tree
from lark.lark import PostLex
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from .builder import Builder
from ..errors import Reporter, shown_char, source_lines
from .limits import MAX_NESTING, check_model, number_problem, read_rule_file
from ..semantics.model import Model
from .syntax import ToSyntax

STATEMENT_KEYWORDS = ("period", "param", "input", "let", "var", "terms", "inference", "rule",
                      "table", "output", "note", "verify", "block")

# MAX_NESTING (fuzzyc.language.limits): the tree depth the transformer and the builder recurse through
# (a statement and its expression's operators each take a level).

# How the parser's terminal names read in a message.
READABLE = {
    "NAME": "a name", "SIGNED_NUMBER": "a number", "NUMBER": "a number", "INT": "a rule number",
    "SIGNED_INT": "a whole number", "STRING": "a quoted title", "LBRACE": "`{`", "RBRACE": "`}`",
    "LPAR": "`(`", "RPAR": "`)`", "LSQB": "`[`", "RSQB": "`]`", "COMMA": "`,`", "COLON": "`:`",
    "SEMICOLON": "`;`", "EQUAL": "`=`", "ARROW": "`->`", "SHAPE": "a term shape (tri, trap, "
    "lshoulder, rshoulder, gauss, bell, sigmoid, singleton, sshape, zshape, pishape, spike, "
    "cosine, concave, linear)", "HEDGE": "a hedge", "NOT": "`not`",
    "INFERENCE_KEY": "an inference setting (and, or, implication, aggregation, defuzzify)",
    "AXIS": "`rows` or `cols`", "DIRECTION": "`increasing` or `decreasing`",
    "COMPARE": "a comparison (<, <=, >, >=)", "DOTTED_NAME": "a parameter name",
    "PERCENT": "`%`", "UNIT_OP": "`/` or `*`", "$END": "the end of the file",
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
    return resources.files("fuzzyc").joinpath("language/grammar/fuzzyc.lark").read_text()


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
    """`name` as .fz text: in backticks when it is a keyword."""
    return f"`{name}`" if name in keywords() else name


def load(path: str | Path) -> Model:
    """Parse and check a .fz file; raises FuzzycError with every diagnostic found."""
    path = Path(path)
    return parse(read_rule_file(path), str(path))


def parse(text: str, path: str = "<string>") -> Model:
    reporter = Reporter(path, text)
    try:
        tree = _lark().parse(text, start="start")
    except UnexpectedInput:
        _report_syntax_errors(text, reporter)
        reporter.raise_if_any()
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


def _report_syntax_errors(text: str, reporter: Reporter) -> None:
    """Parse statement by statement so that independent mistakes are all reported."""
    lines = source_lines(text)
    chunks = _statement_chunks(lines)
    if not chunks:
        _report(_first_error(text, "start"), reporter)
        return
    for first, last in chunks:
        padded = "\n" * first + "\n".join(lines[first:last])
        error = _first_error(padded, "statements")
        if error is not None:
            _report(error, reporter)
    if not reporter.diagnostics:
        _report(_first_error(text, "start"), reporter)


def _statement_chunks(lines: list[str]) -> list[tuple[int, int]]:
    """Line spans [first, last) of the statements inside `controller ... { }`."""
    starts, depth, end = [], 0, len(lines)
    keyword = re.compile(r"\s*(" + "|".join(STATEMENT_KEYWORDS) + r")\b")
    for i, line in enumerate(lines):
        code = line.split("#", 1)[0]
        if depth == 1 and keyword.match(code):
            starts.append(i)
        depth += code.count("{") - code.count("}")
        if depth <= 0 and starts and i > starts[-1]:
            end = i
            break
    return [(s, e) for s, e in zip(starts, starts[1:] + [end])]


def _first_error(text: str, start: str) -> UnexpectedInput | None:
    try:
        _lark().parse(text, start=start)
    except UnexpectedInput as exc:
        return exc
    return None


def _report(exc: UnexpectedInput | None, reporter: Reporter) -> None:
    if exc is None:
        return
    if isinstance(exc, UnexpectedCharacters):
        reporter.error(reporter.loc(exc.line, exc.column),
                       f"unexpected character {shown_char(exc.char)}")
        return
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        lines = source_lines(reporter.text)
        last = max(len(lines) - (lines[-1] == ""), 1)
        reporter.error(reporter.loc(last, 1), "the file ends too early: a statement or the "
                                              "closing `}` of the controller is missing")
        return
    token: Token = exc.token
    if token.type == "KEYWORD_AS_NAME":
        reporter.error(reporter.loc(token.line, token.column),
                       f"`{token}` is a keyword, not a name; a name spelled like a keyword is "
                       f"written in backticks (`{token}` with the backticks typed)")
        return
    expected = sorted({READABLE.get(t, f"`{t.lower()}`") for t in exc.expected
                       if not t.startswith("__")})
    reporter.error(reporter.loc(token.line, token.column),
                   f"unexpected `{token}`; expected {_one_of(expected)}")


def _one_of(options: list[str]) -> str:
    if len(options) > 6:
        options = options[:6] + ["..."]
    return options[0] if len(options) == 1 else "one of " + ", ".join(options)
