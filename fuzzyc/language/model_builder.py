"""Build a model in Python code: `fuzzyc.ModelBuilder` (issue 30).

Design: there is one path to a checked Model, the .fz front end (`fuzzyc.language.parser`,
whose builder in `fuzzyc.language.builder` resolves names and checks everything).  A
ModelBuilder does not make IR objects itself: it records each declaration (with the file and
line of the Python call that made it), renders them as .fz text and parses that text.  So a
built model is exactly the model of its text (`ModelBuilder.text()`), it passes the same
checks, and no validity rule has a second copy here.  What this module checks itself is only
what keeps the text faithful to the calls: every name is a .fz name (letters, digits and _,
not starting with a digit; one spelled like a keyword is written in backticks, as the .fz
writer does), every number finite, a title or note one line without `"` or `\\` (the
language's strings have no escapes), a unit only units' characters, and no `#` in a free
text: those are refused at the call, with ValueError (TypeError for a value of the wrong
type).  A free text (a rule's, a property's, a tune line's) is parsed by the grammar, never
evaluated; when the whole text has parsed, `build` also refuses one that is not exactly one
statement of its kind (two rules in one text), at its call.

Every mistake the front end finds is reported as the FuzzycError it raises, each diagnostic
moved to the Python call that declared the offending item: `script.py:12: error: rule 3:
unknown term ...`, followed by the .fz statement that call made with a caret under the place.
Such a diagnostic's `loc` is a `CallSite` (file and line of the call; `col` is the caret's
column in the shown statement); a mention of another line of the text ("already declared at
line 4") names that declaration's call instead.
"""
from __future__ import annotations

import math
import numbers
import os
import re
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import FrameType
from typing import Any

from ..errors import Diagnostic, FuzzycError
from ..semantics.model import Model, SourceLoc

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_UNIT_ATOM = r"(?:[A-Za-z_][A-Za-z0-9_]*|%|[0-9]+)(?:\^[+-]?[0-9]+)?"
_UNIT = re.compile(rf"{_UNIT_ATOM}(?:[/*]{_UNIT_ATOM})*\Z")
_INFERENCE_KEYS = {"and": "and", "and_": "and", "or": "or", "or_": "or",
                   "implication": "implication", "aggregation": "aggregation",
                   "defuzzify": "defuzzify"}
_HERE = os.path.normcase(os.path.abspath(__file__))

# the order the declarations are written in, whatever order they were made in: a variable
# is declared before its terms, the terms before the rules that read them
_NOTE, _VARIABLE, _TERMS, _INFERENCE, _RULES, _BLOCK, _VERIFY, _TUNE = range(8)
# the sections whose lines stand inside `WORD { ... }`, and what a free text of each must be
_SECTIONS = {_VERIFY: "verify", _TUNE: "tune"}
_KINDS = {"rule": (None, "rule"), "property": ("verify", "property"),
          "tune": ("tune", "tune line")}


@dataclass(frozen=True)
class CallSite(SourceLoc):
    """The Python call that declared an item: `file:line` (col: the caret's column in the
    .fz statement the diagnostic shows)."""

    def __str__(self) -> str:
        return f"{self.file}:{self.line}"


@dataclass
class _Item:
    """One declaration: what it is called in a message, the call that made it, its .fz lines,
    (for a free text) the statement kind the text must be, and the rule block it is in."""
    what: str
    site: tuple[str, int]
    lines: list[str]
    rank: int
    kind: str | None = None       # a key of _KINDS: free text parsed as one statement
    order: int = 0
    block: _Item | None = None


def _call_site() -> tuple[str, int]:
    """File and line of the nearest caller outside this module."""
    frame: FrameType | None = sys._getframe(1)
    while frame is not None and os.path.normcase(os.path.abspath(
            frame.f_code.co_filename)) == _HERE:
        frame = frame.f_back
    if frame is None:            # pragma: no cover - always called from somewhere
        return "<unknown>", 0
    return frame.f_code.co_filename, frame.f_lineno


def _name(value: Any, what: str) -> str:
    """A name as .fz text (a keyword in backticks), or ValueError."""
    from .parser import fz_name
    if not isinstance(value, str):
        raise TypeError(f"{what} is a name (a str), not {type(value).__name__} {value!r}")
    if not _NAME.match(value):
        raise ValueError(f"{what} {value!r} is not a .fz name: use letters, digits and _, not "
                         "starting with a digit")
    return fz_name(value)


def _number(value: Any, what: str) -> str:
    """A finite real as the .fz writer writes it (the shortest text that reads back the same)."""
    from ..formats.export import num
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what} must be a number, not {type(value).__name__} {value!r}")
    if not math.isfinite(float(value)):
        raise ValueError(f"{what} must be a finite number, not {value!r}")
    return num(float(value))


def _string(value: Any, what: str) -> str:
    """A one-line text as a .fz string literal; refused where it would not read back as given
    (the language's strings have no escapes)."""
    if not isinstance(value, str):
        raise TypeError(f"{what} is a str, not {type(value).__name__}")
    bad = [c for c in value if c in '"\\' or not c.isprintable()]
    if bad:
        raise ValueError(f"{what} {value!r} cannot be written as .fz text: it must be one line "
                         f"without `\"` or `\\` (found {bad[0]!r})")
    return f'"{value}"'


def _unit(value: Any, what: str) -> str:
    from .parser import fz_name
    if value is None:
        return ""
    if not isinstance(value, str) or not _UNIT.match(value.replace(" ", "")):
        raise ValueError(f"the unit of {what} must be named atoms (or %) with integer powers, "
                         f"joined by / and *, e.g. \"mm/min\" or \"m/s^2\"; not {value!r}")
    spelled = re.sub(r"[A-Za-z_][A-Za-z0-9_]*", lambda m: fz_name(m.group()),
                     value.replace(" ", ""))
    return f" : {spelled}"


def _one_line(text: Any, what: str) -> str:
    """A rule's or property's text on one line (its own line of the .fz text)."""
    if not isinstance(text, str):
        raise TypeError(f"{what} is a str, not {type(text).__name__}")
    if "#" in text:
        raise ValueError(f"{what} {text!r} holds `#`, which starts a comment in .fz; "
                         "remove it")
    return " ".join(text.split())


def _clause(var: str, value: Any, what: str) -> str:
    """`VAR is [not] [HEDGE] TERM` from a condition's value "TERM", "not TERM", "very TERM",
    "not very TERM"."""
    from .builder.rules import HEDGES
    hedges = sorted(h for h in HEDGES if h)
    if not isinstance(value, str):
        raise TypeError(f"{what}: the condition on `{var}` is a term name (a str), not "
                        f"{type(value).__name__} {value!r}")
    words = value.split()
    if not words:
        raise ValueError(f"{what}: the condition on `{var}` names no term")
    *mods, term = words
    if mods and mods[0] == "not":
        mods = mods[1:]
        head = ["not"]
    else:
        head = []
    if len(mods) > 1 or (mods and mods[0] not in hedges):
        raise ValueError(f"{what}: the condition on `{var}` must be `[not] [hedge] term` (hedges: "
                         f"{', '.join(hedges)}), not {value!r}")
    return " ".join([_name(var, f"{what}: the variable"), "is", *head, *mods,
                     _name(term, f"{what}: the term of `{var}`")])


def _term(name: str, spec: Any, var: str) -> str:
    what = f"term `{name}` of `{var}`"
    if isinstance(spec, str) or not isinstance(spec, Sequence) or not spec \
            or not isinstance(spec[0], str):
        raise TypeError(f"{what} must be (shape, number, ...), e.g. (\"tri\", 0, 5, 10); "
                        f"not {spec!r}")
    shape, *args = spec
    if not _NAME.match(shape):
        raise ValueError(f"{what}: the shape {shape!r} is not a word (tri, trap, gauss, ...)")
    values = ", ".join(_number(a, f"{what}: each number") for a in args)
    return f"{_name(name, f'the name of a term of `{var}`')} = {shape}({values})"


class BuilderVariable:
    """A variable of a ModelBuilder (what `input` and `output` return): declare its terms
    with `terms`, `uniform` or `singletons`; each returns the variable, so calls chain."""

    def __init__(self, builder: ModelBuilder, name: str, output: bool):
        self._builder = builder
        self.name = name
        self.is_output = output

    def __repr__(self) -> str:
        return f"<{'output' if self.is_output else 'input'} {self.name} of {self._builder!r}>"

    def terms(self, terms: Mapping[str, Sequence[Any]] | None = None, /,
              **more: Sequence[Any]) -> BuilderVariable:
        """Terms by name, each (shape, number, ...) as .fz writes it: `terms(low=("tri", 0,
        5, 10), high=("rshoulder", 5, 10))`; a mapping first for names Python cannot take as
        keywords (`terms({"if": ("tri", 0, 1, 2)})`)."""
        given = {**dict(terms or {}), **more}
        defs = ", ".join(_term(n, spec, self.name) for n, spec in given.items())
        self._builder._add(f"terms of `{self.name}`", _TERMS,
                           [f"terms {_name(self.name, 'the variable')} : {defs}".rstrip()])
        return self

    def uniform(self, *names: str,
                over: tuple[float, float] | None = None) -> BuilderVariable:
        """A uniform partition of the range (or of `over`): isosceles triangles with evenly
        spread peaks, shoulders at the ends."""
        words = " ".join(_name(n, f"the name of a term of `{self.name}`") for n in names)
        if over is not None and (isinstance(over, str) or not isinstance(over, Sequence)
                                 or len(over) != 2):
            raise TypeError(f"`over` of `{self.name}` is (low, high), not {over!r}")
        span = "" if over is None else (
            f" over [{_number(over[0], 'over')}, {_number(over[1], 'over')}]")
        self._builder._add(f"terms of `{self.name}`", _TERMS,
                           [f"terms {_name(self.name, 'the variable')} : uniform "
                            f"{words}{span}"])
        return self

    def singletons(self, values: Mapping[str, float] | None = None, /,
                   **more: float) -> BuilderVariable:
        """Singleton terms by name: `singletons(low=0, high=1)`."""
        given = {**dict(values or {}), **more}
        defs = " ".join(f"{_name(n, f'the name of a term of `{self.name}`')}="
                        f"{_number(v, f'term `{n}` of `{self.name}`')}"
                        for n, v in given.items())
        self._builder._add(f"terms of `{self.name}`", _TERMS,
                           [f"terms {_name(self.name, 'the variable')} : singletons {defs}"])
        return self

    def inference(self, **settings: str) -> BuilderVariable:
        """This output's own `aggregation` and `defuzzify` (the rule base's otherwise)."""
        if not self.is_output:
            raise ValueError(f"`{self.name}` is an input: an inference setting of its own "
                             "belongs to an output")
        self._builder._add(f"inference of `{self.name}`", _INFERENCE,
                           [f"inference {_name(self.name, 'the output')}: "
                            + _settings(settings)])
        return self


def _settings(settings: Mapping[str, Any]) -> str:
    if not settings:
        raise ValueError("inference takes at least one setting: and_, or_, implication, "
                         "aggregation, defuzzify")
    out = []
    for key, value in settings.items():
        if key not in _INFERENCE_KEYS:
            raise ValueError(f"unknown inference setting `{key}`: known: and_, "
                             "or_, implication, aggregation, defuzzify")
        out.append(f"{_INFERENCE_KEYS[key]} = {_name(value, f'the {key} setting')}")
    return ", ".join(out)


class _Rules:
    """Rules, tables and inference settings, of the model's top level (ModelBuilder) or of
    one of its rule blocks (RuleBlock)."""
    _builder: ModelBuilder
    _block: _Item | None

    def rule(self, text: str | None = None, *, when: Mapping[str, str] | None = None,
             then: Mapping[str, str | float] | None = None, weight: float | None = None,
             name: str | None = None) -> None:
        """A rule: its .fz text (`"if food is bad then tip is low"`, parsed by the grammar),
        or `when` (variable -> "[not] [hedge] term", joined by `and`) and `then` (output ->
        term, or a number: a singleton of its own); `weight` in [0, 1]; `name` labels it."""
        what = f"rule {self._builder._next('rule')}"
        label = "" if name is None else f"{_name(name, f'{what}: the name')}: "
        if text is not None:
            if when is not None or then is not None:
                raise ValueError(f"{what}: give its text or when/then, not both")
            body = _one_line(text, f"{what}: the text")
            if body.startswith("rule "):
                body = body[5:]
            kind: str | None = "rule"
        else:
            if not when or not then:
                raise ValueError(f"{what}: give its text, or both `when` (variable -> term) "
                                 "and `then` (output -> term)")
            conclusions = []
            for var, term in dict(then).items():
                value = (_number(term, f"{what}: the conclusion on `{var}`")
                         if isinstance(term, numbers.Real) and not isinstance(term, bool)
                         else _name(term, f"{what}: the term of `{var}`"))
                conclusions.append(f"{_name(var, f'{what}: the output')} is {value}")
            body = (f"if {' and '.join(_clause(v, t, what) for v, t in dict(when).items())} "
                    f"then {', '.join(conclusions)}")
            kind = None
        if weight is not None:
            body += f" with {_number(weight, f'{what}: the weight')}"
        self._builder._add(what, _RULES, [f"rule {label}{body}"], kind, self._block)
        self._builder._counted("rule")

    def table(self, output: str, rows: tuple[str, Sequence[str]],
              cols: tuple[str, Sequence[str]], cells: Sequence[Sequence[Any]], *,
              when: Mapping[str, str] | None = None, learnable: bool = False) -> None:
        """A rule table as the papers print it (the language's `table` statement): `rows` and
        `cols` are (variable, [term, ...]); `cells[i][j]` the term of `output` where the row
        variable is rows' i-th term and the column variable cols' j-th (a number: a singleton
        of its own; None: no rule); `when` guards every cell ("variable -> term")."""
        what = f"table {self._builder._next('table')} (`{output}`)"
        guard = "" if not when else " when " + " and ".join(
            _clause(v, t, what) for v, t in dict(when).items())
        axes = []
        for word, (var, terms) in (("rows", rows), ("cols", cols)):
            if isinstance(terms, str):
                raise TypeError(f"{what}: the {word}' terms are a list of names, not a str")
            axes.append(f"{word} {_name(var, f'{what}: the {word} variable')}: "
                        + " ".join(_name(t, f"{what}: a term of `{var}`") for t in terms))
        lines = [f"table {_name(output, f'{what}: the output')}{guard} ({'; '.join(axes)})"
                 f"{' learnable' if learnable else ''} {{"]
        for row in cells:
            if isinstance(row, str):
                raise TypeError(f"{what}: each row of cells is a list of cells, not a str")
            lines.append("  " + " ".join(
                "-" if c is None else
                _number(c, f"{what}: a cell") if isinstance(c, numbers.Real)
                and not isinstance(c, bool) else _name(c, f"{what}: a cell") for c in row))
        lines.append("}")
        self._builder._add(what, _RULES, lines, block=self._block)
        self._builder._counted("table")

    def inference(self, **settings: str) -> None:
        """The rule base's (or block's) inference: `and_`, `or_`, `implication`,
        `aggregation`, `defuzzify` (the .fz words: `inference(and_="product",
        defuzzify="centroid")`)."""
        what = "inference" if self._block is None else f"inference of {self._block.what}"
        self._builder._add(what, _INFERENCE, ["inference " + _settings(settings)],
                           block=self._block)


class RuleBlock(_Rules):
    """A rule block of a ModelBuilder (what `block` returns): its own `rule`, `table` and
    `inference`, evaluated after the blocks declared before it, whose outputs it may read."""

    def __init__(self, builder: ModelBuilder, item: _Item, name: str):
        self._builder = builder
        self._block = item
        self.name = name

    def __repr__(self) -> str:
        return f"<block {self.name} of {self._builder!r}>"


class ModelBuilder(_Rules):
    """A model declared by Python calls, checked as the same model written in .fz would be.

    `input(name, lo, hi)` and `output(name, lo, hi)` declare the rule base's variables and
    return them (`BuilderVariable`: `terms`, `uniform`, `singletons`, an output's own
    `inference`);
    `rule` adds a rule (its .fz text, or `when`/`then` mappings), `table` a rule table,
    `inference` the rule base's settings, `block` a rule block (`RuleBlock`: its own `rule`,
    `table`, `inference`), `verify` properties, `tune` the lines of the tune section, `note`
    a remark. `build()`
    returns the checked Model or raises FuzzycError, each diagnostic at the Python line that
    declared the offending item; `text()` is the .fz text the model is read from.

    It renders .fz text and parses it rather than building the model's objects itself, so
    that the language's front end stays the one place a model is checked (see the module's
    docstring)."""

    def __init__(self, name: str, title: str = ""):
        site = _call_site()
        self.name = name
        head = f"controller {_name(name, 'the model name')}"
        if title:
            head += " " + _string(title, "the title")
        self._head = _Item(f"the model `{name}`", site, [head + " {"], -1)
        self._builder = self
        self._block = None
        self._items: list[_Item] = []
        self._variables: dict[str, BuilderVariable] = {}
        self._counts: dict[str, int] = {}

    def __repr__(self) -> str:
        counts = [(len(self._variables), "variable"), (self._counts.get("rule", 0), "rule"),
                  (self._counts.get("table", 0), "table")]
        return f"<ModelBuilder {self.name}: " + ", ".join(
            f"{n} {word}{'' if n == 1 else 's'}" for n, word in counts) + ">"

    def _add(self, what: str, rank: int, lines: list[str], kind: str | None = None,
             block: _Item | None = None) -> _Item:
        item = _Item(what, _call_site(), lines, rank, kind, len(self._items), block)
        self._items.append(item)
        return item

    def _next(self, kind: str) -> int:
        """The number the next `kind` declared gets (counted once it is added: a refused
        call takes no number)."""
        return self._counts.get(kind, 0) + 1

    def _counted(self, kind: str) -> None:
        self._counts[kind] = self._next(kind)

    # -- declarations -------------------------------------------------------------------------

    def input(self, name: str, lo: float, hi: float, *,
              unit: str | None = None) -> BuilderVariable:
        """A rule-base input over [lo, hi] (`input NAME : UNIT in [lo, hi]`)."""
        line = (f"input {_name(name, 'the input name')}{_unit(unit, f'`{name}`')} "
                f"in [{_number(lo, f'the low end of `{name}`')}, "
                f"{_number(hi, f'the high end of `{name}`')}]")
        self._add(f"input `{name}`", _VARIABLE, [line])
        return self._variables.setdefault(name, BuilderVariable(self, name, False))

    def output(self, name: str, lo: float, hi: float, *, unit: str | None = None,
               default: float | None = None) -> BuilderVariable:
        """A rule-base output over [lo, hi] (`var NAME : UNIT in [lo, hi] default d`);
        `default` is its value where no rule fires."""
        line = (f"var {_name(name, 'the output name')}{_unit(unit, f'`{name}`')} "
                f"in [{_number(lo, f'the low end of `{name}`')}, "
                f"{_number(hi, f'the high end of `{name}`')}]")
        if default is not None:
            line += f" default {_number(default, f'the default of `{name}`')}"
        self._add(f"output `{name}`", _VARIABLE, [line])
        return self._variables.setdefault(name, BuilderVariable(self, name, True))

    def block(self, name: str) -> RuleBlock:
        """A rule block (`block NAME { ... }`): declare its rules, tables and inference on
        what this returns. A model with blocks has all its rules in blocks."""
        line = f"block {_name(name, 'the block name')} {{"
        return RuleBlock(self, self._add(f"block `{name}`", _BLOCK, [line]), name)

    def tune(self, *targets: str) -> None:
        """Lines of the `tune` section, each its .fz text (`"food.bad.c in [1, 3]"`,
        `"tip.* in +/- 1"`; docs/tuning.md): what `fuzzyc.tune` may move."""
        first = self._next("tune")
        texts = [_one_line(text, f"tune line {first + i}: the text")
                 for i, text in enumerate(targets)]
        for text in texts:
            self._add(f"tune line {self._next('tune')}", _TUNE, [text], "tune")
            self._counted("tune")

    def verify(self, *properties: str) -> None:
        """Properties for `fuzzyc.verify`, each its .fz text (`"complete"`,
        `"covers food at least 0.5"`, `"monotone tip increasing in food"`)."""
        first = self._next("property")
        texts = [_one_line(text, f"property {first + i}: the text")
                 for i, text in enumerate(properties)]
        for text in texts:
            self._add(f"property {self._next('property')}", _VERIFY, [text], "property")
            self._counted("property")

    def note(self, text: str) -> None:
        """A remark kept in the model (`model.notes`) and shown in reports."""
        line = f"note {_string(text, 'a note')}"
        self._add(f"note {self._next('note')}", _NOTE, [line])
        self._counted("note")

    # -- the model ----------------------------------------------------------------------------

    def _layout(self) -> tuple[list[str], list[_Item | None]]:
        """The .fz lines and, per line, the declaration it belongs to."""
        lines = list(self._head.lines)
        owner: list[_Item | None] = [self._head]

        def emit(item: _Item | None, text: str) -> None:
            lines.append(text)
            owner.append(item)

        def ordered(block: _Item | None) -> list[_Item]:
            return sorted((i for i in self._items if i.block is block),
                          key=lambda i: (i.rank, i.order))

        top = ordered(None)
        for item in top:
            section = _SECTIONS.get(item.rank)
            mates = [i for i in top if i.rank == item.rank]
            if section and item is mates[0]:
                emit(item, f"  {section} {{")
            indent = "    " if section else "  "
            for line in item.lines:
                emit(item, indent + line)
            if item.rank == _BLOCK:
                for inner in ordered(item):
                    for line in inner.lines:
                        emit(inner, "    " + line)
                emit(item, "  }")
            if section and item is mates[-1]:
                emit(item, "  }")
        emit(None, "}")
        return lines, owner

    def text(self) -> str:
        """The .fz text of the declarations so far: what `build` parses."""
        return "\n".join(self._layout()[0]) + "\n"

    def build(self) -> Model:
        """The checked Model; FuzzycError with every mistake found, each at the Python call
        that declared it."""
        from .parser import parse
        site = _call_site()
        lines, owner = self._layout()
        text = "\n".join(lines) + "\n"
        path = f"{self.name}.fz"
        try:
            model = parse(text, path)
        except FuzzycError as error:
            raise FuzzycError([self._relocate(d, path, lines, owner, site)
                               for d in error.diagnostics]) from None
        not_one = [d for d in map(_one_statement, self._items) if d is not None]
        if not_one:
            raise FuzzycError(not_one)
        return model

    def _relocate(self, d: Diagnostic, path: str, lines: list[str],
                  owner: list[_Item | None], build_site: tuple[str, int]) -> Diagnostic:
        """The front end's diagnostic at the Python call that made its line."""
        if d.loc is None or d.loc.file != path:
            return d
        row = d.loc.line - 1
        item = owner[row] if 0 <= row < len(owner) else None
        file, line = item.site if item is not None else build_site
        what = item.what if item is not None else "the model"

        def elsewhere(match: re.Match) -> str:
            n = int(match.group(3)) - 1
            other = owner[n] if 0 <= n < len(owner) else None
            if other is None:
                return match.group()
            if other is item and match.group(1):     # "rule 3: ... in rule at line 9"
                return ""
            return f"{match.group(1) or ''}{match.group(2)} {other.site[0]}:{other.site[1]}"

        message = re.sub(r"( in rule)?( at| of) line (\d+)\b", elsewhere, d.message)
        shown = lines[row] if 0 <= row < len(lines) else ""
        indent = len(shown) - len(shown.lstrip())
        return Diagnostic(CallSite(file, line, max(d.loc.col - indent, 1)),
                          f"{what}: {message}", shown.strip())


def _one_statement(item: _Item) -> Diagnostic | None:
    """A rule's or property's text that parsed in the whole file but is not exactly one
    statement of its kind there (two rules in one text, say)."""
    from lark import Tree
    from lark.exceptions import UnexpectedInput
    from .parser import _lark
    if item.kind is None:
        return None
    line = item.lines[0]
    section, noun = _KINDS[item.kind]
    wrapped = line if section is None else f"{section} {{ {line} }}"
    try:
        stmts = [t for t in _lark().parse(wrapped, start="statements").children
                 if isinstance(t, Tree)]
    except UnexpectedInput:
        count = None
    else:
        count = len([t for t in stmts[0].children if isinstance(t, Tree)]) \
            if section is not None and len(stmts) == 1 else len(stmts)
        if count == 1 and stmts[0].data == (section or "rule"):
            return None
    return Diagnostic(CallSite(item.site[0], item.site[1], 1),
                      f"{item.what}: the text is not one {noun}"
                      + ("" if count is None else f" but {count}")
                      + f"; give each {noun} its own call", line)


__all__ = ["BuilderVariable", "CallSite", "ModelBuilder", "RuleBlock"]
