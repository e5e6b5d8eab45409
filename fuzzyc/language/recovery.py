"""Several syntax errors in one run, through lark's own error recovery (`Lark.parse(on_error=)`).

After an error the handler skips the rest of the broken statement and resumes the parse at the
next statement: a token that can start one (read from the grammar, never a copy of its words),
or the `}` that closes the block the error is in.  Mid-line, a resumption point must let the
parse go on for two tokens (`rule if x is input then` does not restart at `input`,
`in [0} , 2000]` does not close the controller at `}`); it stays inside the innermost open
block.  Braces opened in the skipped text are skipped with it, so a block's own `}` never
shows up as a second error.
"""
from __future__ import annotations

import functools
import re
from collections.abc import Callable
from copy import copy

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken
from lark.lexer import BasicLexer, PatternStr
from lark.parsers.lalr_interactive_parser import InteractiveParser
from lark.parsers.lalr_parser_state import ParseConf, ParserState

# A resumption point is taken when the parse goes on past it for this many tokens: a statement
# word that begins its line always is (as statements do; the next statement's own mistake is
# then reported too), one in the middle of a line when two more tokens fit after it.
LOOKAHEAD_AT_LINE_START = 0
LOOKAHEAD_MID_LINE = 2
# A `}` that begins its line closes a block when one more token fits after it: a stray `}` must
# not end the controller before the statements that follow it.
LOOKAHEAD_CLOSING_BRACE = 1


class Recovery:
    """lark's on_error handler: report each error, skip to the next statement, resume."""

    def __init__(self, parser: Lark, report: Callable[[UnexpectedInput], None], limit: int,
                 too_many: Callable[[], None]):
        self.report, self.limit, self.too_many = report, limit, too_many
        self.errors = 0
        self.starts = statement_starts(parser)
        self.words = statement_words(parser)
        self.lexer = _skipping_lexer(parser)
        self.token_start = _token_start(parser)

    def __call__(self, exc: UnexpectedInput) -> bool:
        if self.errors >= self.limit:
            self.too_many()
            return False
        self.errors += 1
        self.report(exc)
        ip = exc.interactive_parser
        if ip is None or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
            return False
        if isinstance(exc, UnexpectedCharacters):
            _step_to_next_token(ip, self.token_start)
            return self._resume(ip, None)
        token = self._as_keyword(exc.token)
        if token.type == "LBRACE":      # a stray `{` opens no block the skip must pass over
            return _enter_controller_body(ip, token) or self._resume(ip, None)
        return self._resume(ip, token)

    def _resume(self, ip: InteractiveParser, token: Token | None) -> bool:
        """Skip tokens, from `token` (the offending one, already read) on, to one the parse
        resumes at; False at the end of the text (nothing more to check)."""
        depth = 0           # braces opened in the skipped text
        while True:
            if token is None:
                token = self._next_token(ip)
                if token is None:
                    return False
            if token.type == "LBRACE":
                if depth == 0 and _enter_controller_body(ip, token):
                    return True
                depth += 1
            elif token.type == "RBRACE" and depth > 0:
                depth -= 1
            elif depth == 0 and (token.type in self.starts or token.type == "RBRACE"):
                brace = _innermost_brace(ip.parser_state)
                floor = 1 if brace is None else brace + 2      # keep the open block's `{`
                if _feed_where_taken(ip, token, floor) or self._open_body_before(ip, token):
                    return True
                if token.type == "RBRACE" and brace is not None \
                        and self._drop_block(ip, brace):
                    return True
            token = None

    def _next_token(self, ip: InteractiveParser) -> Token | None:
        """The next token of the text, read in no parser state (so any terminal); characters
        no terminal matches are stepped over."""
        state = ip.lexer_thread.state
        while True:
            try:
                return self.lexer.next_token(state)
            except EOFError:
                return None
            except UnexpectedCharacters:
                _step_to_next_token(ip, self.token_start)

    def _open_body_before(self, ip: InteractiveParser, token: Token) -> bool:
        """A statement where the controller's header expects its `{` (`controller c` with
        `period 40 ms` on the next line): the body is taken as opened there."""
        if token.type not in self.starts:
            return False
        brace = Token.new_borrow_pos("LBRACE", "{", token)
        trial = _bare_copy(ip)
        if not (_enter_controller_body(trial, brace) and _feed_where_taken(trial, token, 1)):
            return False
        _enter_controller_body(ip, brace)
        return _feed_where_taken(ip, token, 1)

    def _drop_block(self, ip: InteractiveParser, brace: int) -> bool:
        """A `}` that closes a block which cannot end yet (a table without its cells): the
        parse goes on after the statement the block belongs to, as if it were not written."""
        state = ip.parser_state
        for depth in range(brace + 1, 0, -1):      # the states before the block's `{`
            if self.starts & set(state.parse_conf.states[state.state_stack[depth - 1]]):
                trial = _bare_copy(ip)
                _truncate(trial.parser_state, depth)
                if not _parses_on(trial, LOOKAHEAD_MID_LINE):
                    return False
                _truncate(state, depth)
                return True
        return False

    def _as_keyword(self, token: Token) -> Token:
        """A statement word read where a name was expected may still start the next statement
        (`param Yr =` with `input f ...` on the next line)."""
        if token.type == "KEYWORD_AS_NAME" and str(token) in self.words:
            return token.update(type=self.words[str(token)])
        return token


def _feed_where_taken(ip: InteractiveParser, token: Token, floor: int) -> bool:
    """Pop the stack (to no fewer than `floor` states) to where `token` is taken and feed it
    there, when the parse goes on after it; the parser is unchanged otherwise."""
    trial = _bare_copy(ip)
    if not _pop_until_taken(trial.parser_state, token, floor):
        return False
    trial.feed_token(token)
    if not _parses_on(trial, _lookahead(ip, token)):
        return False
    _pop_until_taken(ip.parser_state, token, floor)
    ip.feed_token(token)
    return True


def _enter_controller_body(ip: InteractiveParser, brace: Token) -> bool:
    """An error in `controller NAME "title" {`: the parse goes on from the body's first
    statement, as after a correct header (the header's `{` is the first one opened)."""
    state = ip.parser_state
    values = state.value_stack
    started = bool(values) and isinstance(values[0], Token) and values[0].type == "CONTROLLER"
    if not started or _innermost_brace(state) is not None:
        return False
    _truncate(state, 1)
    for kind, text in (("CONTROLLER", "controller"), ("NAME", "controller")):
        ip.feed_token(Token.new_borrow_pos(kind, text, brace))
    ip.feed_token(brace)
    return True


def _step_to_next_token(ip: InteractiveParser, token_start: re.Pattern) -> None:
    """Past the characters no terminal matches, in one step (a file of 10^6 `$`)."""
    state = ip.lexer_thread.state
    position = state.line_ctr.char_pos
    text = state.text.text
    found = token_start.search(text, position + 1)
    state.line_ctr.feed(text[position:found.start() if found else len(text)])


def _innermost_brace(state: ParserState) -> int | None:
    """The index on the value stack of the innermost `{` (the block the parse is in)."""
    for i in range(len(state.value_stack) - 1, -1, -1):
        value = state.value_stack[i]
        if isinstance(value, Token) and value.type == "LBRACE":
            return i
    return None


def _pop_until_taken(state: ParserState, token: Token, floor: int) -> bool:
    """Pop the stack, keeping at least `floor` states, to the innermost state that takes
    `token`; the stack is unchanged when none does.  The parse table says which states may
    (a constant-time look); a trial feed confirms (LALR may reduce, then refuse)."""
    table = state.parse_conf.states
    for depth in range(len(state.state_stack), max(floor, 1) - 1, -1):
        if token.type not in table[state.state_stack[depth - 1]]:
            continue
        trial = ParserState(_without_callbacks(state.parse_conf), state.lexer,
                            state.state_stack[:depth], state.value_stack[:depth - 1])
        try:
            trial.feed_token(token)
        except UnexpectedToken:
            continue
        _truncate(state, depth)
        return True
    return False


def _truncate(state: ParserState, depth: int) -> None:
    """Keep the bottom `depth` states (and their values) of the parser's stack."""
    del state.state_stack[depth:]
    del state.value_stack[depth - 1:]


def _bare_copy(ip: InteractiveParser) -> InteractiveParser:
    """A copy of the parser and its lexer position to try a resumption on, building no tree."""
    trial = ip.copy(deepcopy_values=False)
    trial.parser_state.parse_conf = _without_callbacks(trial.parser_state.parse_conf)
    return trial


def _without_callbacks(conf: ParseConf) -> ParseConf:
    bare = copy(conf)
    bare.callbacks = {}
    return bare


def _lookahead(ip: InteractiveParser, token: Token) -> int:
    text = ip.lexer_thread.state.text.text
    line_start = text.rfind("\n", 0, token.start_pos) + 1
    if text[line_start:token.start_pos].strip():
        return LOOKAHEAD_MID_LINE
    return LOOKAHEAD_CLOSING_BRACE if token.type == "RBRACE" else LOOKAHEAD_AT_LINE_START


def _parses_on(trial: InteractiveParser, tokens: int) -> bool:
    """The parse goes on for `tokens` tokens (or to the end of the text) from here."""
    if tokens <= 0:
        return True
    fed = 0
    try:
        for token in trial.lexer_thread.lex(trial.parser_state):
            trial.feed_token(token)
            fed += 1
            if fed >= tokens:       # before the lexer reads one more
                return True
    except UnexpectedInput:
        return False
    return True


@functools.cache
def statement_starts(parser: Lark) -> frozenset[str]:
    """The terminals that can start a statement: what the grammar's `statements` entry takes
    first (the end of the text aside)."""
    return frozenset(parser.parse_interactive("", start="statements").accepts()) - {"$END"}


@functools.cache
def statement_words(parser: Lark) -> dict[str, str]:
    """Statement word -> its terminal's name (`input` -> INPUT)."""
    return {t.pattern.value: t.name for t in parser.terminals
            if isinstance(t.pattern, PatternStr) and t.name in statement_starts(parser)}


@functools.cache
def _token_start(parser: Lark) -> re.Pattern:
    """Where any terminal (an ignored one too) matches: where skipped text has a token again."""
    return re.compile("|".join(f"(?:{t.pattern.to_regexp()})" for t in parser.terminals),
                      parser.options.g_regex_flags)


@functools.cache
def _skipping_lexer(parser: Lark) -> BasicLexer:
    """A lexer that knows every terminal: skipped text is read in no parser state."""
    return BasicLexer(parser.lexer_conf)
