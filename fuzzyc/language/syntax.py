"""The lark Transformer: parse tree -> plain syntax objects that keep their source locations.

Nothing here knows what a name means; `fuzzyc.language.builder` resolves names, checks the file and
makes the Model. Expressions stay trees (`Expr`) until the builder turns them into sympy.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from lark import Token, Transformer, v_args

from ..semantics.model import SourceLoc


@dataclass
class Name:
    text: str
    loc: SourceLoc


@dataclass
class Num:
    value: float
    loc: SourceLoc
    is_int: bool = False


@dataclass
class Expr:
    """op: constant | symbol | add | sub | mul | div | pow | neg | call; call has `name`."""
    op: str
    args: list[Any]
    loc: SourceLoc
    name: str = ""


def _fold_left(items: list) -> Expr:
    """[a, op, b, op, c, ...] -> op(op(a, b), c): each binary Expr at its left operand's place."""
    left = items[0]
    for op, right in zip(items[1::2], items[2::2]):
        left = Expr(op, [left, right], items[0].loc)
    return left


@dataclass
class Clause:
    var: Name
    term: Name
    negated: bool = False
    hedge: str | None = None


@dataclass
class Condition:
    connective: str          # "and" | "or" | "not" | "hedge" | "concluded" | "carried" (one
    #                          part) | "weight"
    parts: list[Any]         # Clause | Condition
    hedge: str | None = None  # "hedge": its word (`very (a is x or b is y)`)
    weight: Any = None        # "weight": its Num (`seldom (0.5 * (a is x))`)


@dataclass
class Conclusion:
    var: Name
    term: Name | Num


@dataclass
class TermDef:
    name: Name
    shape: str
    args: list[Num]
    formula: str | None = None        # shape "formula": its text, found at formula_loc
    formula_loc: SourceLoc | None = None


@dataclass
class Stmt:
    kind: str
    loc: SourceLoc
    data: dict[str, Any] = field(default_factory=dict)
    end: SourceLoc | None = None


def _num(tok: Token, file: str) -> Num:
    text = str(tok)
    is_int = text.lstrip("+-").isdigit()
    return Num(float(text), SourceLoc(file, tok.line, tok.column), is_int)


class ToSyntax(Transformer):
    """Builds `Stmt` objects; every value carries the location of the token it came from."""

    def __init__(self, file: str):
        super().__init__()
        self.file = file

    def _loc(self, tok_or_meta) -> SourceLoc:
        return SourceLoc(self.file, tok_or_meta.line, tok_or_meta.column)

    def _name(self, tok: Token) -> Name:
        return Name(str(tok), self._loc(tok))

    # ---- leaves
    def NAME(self, tok):
        return self._name(tok)

    def DOTTED_NAME(self, tok):
        return self._name(tok)

    def number(self, items):
        return _num(items[0], self.file)

    signed_number = number

    def constant(self, items):
        n = _num(items[0], self.file)
        return Expr("constant", [n.value, n.is_int], n.loc)

    def symbol(self, items):
        return Expr("symbol", [items[0].text], items[0].loc)

    def name_list(self, items):
        return list(items)

    def range(self, items):
        return (items[0], items[1])

    over = range

    def unit_power(self, items):
        atom = items[0].text if isinstance(items[0], Name) else str(items[0])
        exponent = int(str(items[1])) if len(items) > 1 else 1
        return (atom, exponent)

    def unit(self, items):
        powers, sign = [], 1
        for item in items:
            if isinstance(item, Token) and item.type == "UNIT_OP":
                sign = -1 if str(item) == "/" else 1
            else:
                powers.append((item[0], sign * item[1]))
        return powers

    def unit_decl(self, items):
        return items[0]

    # ---- expressions
    def sum(self, items):
        return _fold_left(items)

    product = sum

    def add_op(self, items):
        return {"+": "add", "-": "sub"}[str(items[0])]

    def mul_op(self, items):
        return {"*": "mul", "/": "div"}[str(items[0])]

    def pow(self, items):
        return Expr("pow", list(items), items[0].loc)

    @v_args(meta=True)
    def neg(self, meta, items):
        return Expr("neg", list(items), SourceLoc(self.file, meta.line, meta.column))

    def call(self, items):
        return Expr("call", list(items[1:]), items[0].loc, name=items[0].text)

    @v_args(meta=True)
    def comparison(self, meta, items):
        return Expr("compare", [items[0], items[2]], SourceLoc(self.file, meta.line, meta.column),
                    name=str(items[1]))

    def and_pred(self, items):
        return Expr("and", list(items), items[0].loc)

    def or_pred(self, items):
        return Expr("or", list(items), items[0].loc)

    # ---- conditions
    def is_clause(self, items):
        var, rest = items[0], items[1:]
        negated = any(isinstance(t, Token) and t.type == "NOT" for t in rest)
        hedge = next((str(t) for t in rest if isinstance(t, Token) and t.type == "HEDGE"), None)
        return Clause(var, rest[-1], negated, hedge)

    def and_cond(self, items):
        return Condition("and", list(items))

    def or_cond(self, items):
        return Condition("or", list(items))

    def not_cond(self, items):
        return Condition("not", [items[-1]])

    def hedge_cond(self, items):
        return Condition("hedge", [items[-1]], str(items[0]))

    def concluded_cond(self, items):
        return Condition(str(items[0]), [items[-1]], str(items[1]) if len(items) == 3 else None)

    def weighted_cond(self, items):
        return Condition("weight", [items[-1]], weight=items[0])

    def conclusion(self, items):
        return Conclusion(items[0], items[1])

    def weight(self, items):
        return items[0]

    def guard(self, items):
        return list(items)

    where = guard

    # ---- terms
    def term_def(self, items):
        return TermDef(items[0], str(items[1]), list(items[2:]))

    def formula_def(self, items):
        text = items[1]
        return TermDef(items[0], "formula", [], str(text)[1:-1],
                       SourceLoc(self.file, text.line, text.column + 1))

    def term_list(self, items):
        return ("list", list(items))

    def uniform(self, items):
        over = items[-1] if isinstance(items[-1], tuple) else None
        names = [i for i in items if isinstance(i, Name)]
        return ("uniform", names, over)

    def singleton(self, items):
        return TermDef(items[0], "singleton", [items[1]])

    def singletons(self, items):
        return ("list", list(items))

    def default(self, items):
        return items[0]

    def start_value(self, items):
        return items[0]

    def setting(self, items):
        return (str(items[0]), items[1])

    def axis(self, items):
        return (str(items[0]), items[1], list(items[2:]))

    @v_args(meta=True)
    def empty_cell(self, meta, items):
        return Name("-", SourceLoc(self.file, meta.line, meta.column))

    @v_args(meta=True)
    def any_cell(self, meta, items):
        return Name("*", SourceLoc(self.file, meta.line, meta.column))

    def list_row(self, items):
        cells = list(items[1:])
        weight = cells.pop() if cells and isinstance(cells[-1], Num) else None
        arrow = next(i for i, c in enumerate(cells) if isinstance(c, Token) and c.type == "ARROW")
        return {"label": _num(items[0], self.file), "premises": cells[:arrow],
                "conclusions": cells[arrow + 1:], "weight": weight}

    # ---- statements
    @v_args(meta=True)
    def _stmt(self, kind, meta, data):
        return Stmt(kind, SourceLoc(self.file, meta.line, meta.column), data,
                    SourceLoc(self.file, meta.end_line, meta.end_column))

    @v_args(meta=True)
    def period(self, meta, items):
        return self._stmt("period", meta, {"value": items[0], "unit": items[1]})

    @v_args(meta=True)
    def param(self, meta, items):
        return self._stmt("param", meta, {"name": items[0], "value": items[1],
                                          "unit": items[2] if len(items) > 2 else None})

    @v_args(meta=True)
    def input(self, meta, items):
        unit = items[1] if isinstance(items[1], list) else None
        return self._stmt("input", meta, {"name": items[0], "unit": unit, "range": items[-1]})

    @v_args(meta=True)
    def let(self, meta, items):
        data = {"name": items[0], "unit": None, "range": None, "expr": items[-1]}
        for item in items[1:-1]:
            data["range" if isinstance(item, tuple) else "unit"] = item
        return self._stmt("let", meta, data)

    @v_args(meta=True)
    def var(self, meta, items):
        data = {"name": items[0], "unit": None, "range": None, "default": None, "hold": False}
        for item in items[1:]:
            if isinstance(item, Token) and item.type == "HOLD":
                data["hold"] = True
                continue
            key = "range" if isinstance(item, tuple) else "unit" if isinstance(item, list) else "default"
            data[key] = item
        return self._stmt("var", meta, data)

    @v_args(meta=True)
    def terms(self, meta, items):
        defined = isinstance(items[-1], tuple) and items[-1][0] in ("list", "uniform")
        data = {"names": items[0], "range": None, "default": None,
                "terms": items[-1] if defined else ("list", [])}
        for item in items[1:len(items) - defined]:
            data["range" if isinstance(item, tuple) else "default"] = item
        return self._stmt("terms", meta, data)

    @v_args(meta=True)
    def inference(self, meta, items):
        items = list(items)
        output = items.pop(0) if isinstance(items[0], Name) else None
        return self._stmt("inference", meta, {"output": output, "settings": items})

    @v_args(meta=True)
    def block(self, meta, items):
        return self._stmt("block", meta, {"name": items[0], "statements": list(items[1:])})

    @v_args(meta=True)
    def rule(self, meta, items):
        items = list(items)
        name = items.pop(0) if isinstance(items[0], Name) else None
        weight = items.pop() if isinstance(items[-1], Num) else None
        condition, conclusions = items[0], items[1:]
        return self._stmt("rule", meta, {"name": name, "condition": condition,
                                         "conclusions": conclusions, "weight": weight})

    @v_args(meta=True)
    def table2d(self, meta, items):
        items = list(items)
        output = items.pop(0)
        guard = items.pop(0) if isinstance(items[0], list) else []
        axes = [items.pop(0), items.pop(0)]
        learnable = bool(items) and isinstance(items[0], Token) and items[0].type == "LEARNABLE"
        if learnable:
            items.pop(0)
        return self._stmt("table2d", meta, {"output": output, "guard": guard, "axes": axes,
                                            "learnable": learnable, "cells": items})

    @v_args(meta=True)
    def list_table(self, meta, items):
        return self._stmt("list_table", meta, {"premises": items[0], "outputs": items[2],
                                               "rows": list(items[3:])})

    @v_args(meta=True)
    def output(self, meta, items):
        items = list(items)
        data = {"name": items.pop(0), "unit": None, "init": None}
        if isinstance(items[0], list):
            data["unit"] = items.pop(0)
        data["range"] = items.pop(0)
        data["expr"] = items.pop(0)
        if items:
            data["init"] = items.pop(0)
        return self._stmt("output", meta, data)

    @v_args(meta=True)
    def note(self, meta, items):
        return self._stmt("note", meta, {"text": str(items[0])[1:-1]})

    @v_args(meta=True)
    def fuzzylite(self, meta, items):
        return self._stmt("fuzzylite", meta, {"key": items[0], "args": list(items[1:])})

    # ---- verification
    @v_args(meta=True)
    def verify(self, meta, items):
        return self._stmt("verify", meta, {"properties": list(items)})

    @v_args(meta=True)
    def covers(self, meta, items):
        return self._stmt("covers", meta, {"inputs": items[0], "level": items[1]})

    @v_args(meta=True)
    def consistent(self, meta, items):
        return self._stmt("consistent", meta, {})

    @v_args(meta=True)
    def complete(self, meta, items):
        return self._stmt("complete", meta, {"output": items[0] if items else None})

    @v_args(meta=True)
    def continuous(self, meta, items):
        return self._stmt("continuous", meta, {"output": items[0] if items else None})

    @v_args(meta=True)
    def monotone(self, meta, items):
        return self._stmt("monotone", meta, {"output": items[0], "direction": str(items[1]),
                                             "input": items[2],
                                             "where": items[3] if len(items) > 3 else []})

    @v_args(meta=True)
    def bounded(self, meta, items):
        return self._stmt("bounded", meta, {"signal": items[0], "range": items[1]})

    @v_args(meta=True)
    def closed_loop(self, meta, items):
        items = list(items)
        scenario, duration = items.pop(0), items.pop(0)
        unit = items.pop(0) if items and isinstance(items[0], list) else None
        return self._stmt("closed_loop", meta, {"scenario": scenario, "duration": duration,
                                                "unit": unit, "items": items})

    @v_args(meta=True)
    def loop_set(self, meta, items):
        return self._stmt("set", meta, {"key": items[0], "value": items[1]})

    @v_args(meta=True)
    def loop_vary(self, meta, items):
        return self._stmt("vary", meta, {"key": items[0], "range": items[1],
                                         "before": items[2] if len(items) > 2 else None})

    def step_window(self, items):
        return (items[0], items[1] if len(items) > 1 else None)

    @v_args(meta=True)
    def loop_fault(self, meta, items):
        unit = items[3] if len(items) > 3 else None
        return self._stmt("fault", meta, {"signal": items[0], "kind": str(items[1]),
                                          "seconds": items[2], "unit": unit})

    @v_args(meta=True)
    def always(self, meta, items):
        return self._stmt("always", meta, {"predicate": items[0]})

    @v_args(meta=True)
    def eventually(self, meta, items):
        unit = items[1] if len(items) > 2 else None
        return self._stmt("eventually", meta, {"within": items[0], "unit": unit,
                                               "predicate": items[-1]})

    @v_args(meta=True)
    def settles(self, meta, items):
        unit = items[4] if len(items) > 4 else None
        return self._stmt("settles", meta, {"signal": items[0], "target": items[1],
                                            "tolerance": items[2], "by": items[3], "unit": unit})

    @v_args(meta=True)
    def overshoot(self, meta, items):
        return self._stmt("overshoot", meta, {"signal": items[0], "limit": items[1]})

    # ---- tuning (fuzzyc.language.builder.tunables reads these)
    @v_args(meta=True)
    def tune(self, meta, items):
        return self._stmt("tune", meta, {"items": list(items)})

    def tune_item(self, items):
        *paths, bound = items
        return {"paths": paths, "bound": bound}

    def tune_path(self, items):
        return list(items)

    @v_args(meta=True)
    def tune_any(self, meta, items):
        return Name("*", SourceLoc(self.file, meta.line, meta.column))

    def spread(self, items):
        return ("spread", items[-1])

    def controller(self, items):
        items = list(items)
        name = items.pop(0)
        title = str(items.pop(0))[1:-1] if items and isinstance(items[0], Token) else ""
        return {"name": name, "title": title, "statements": items}

    def start(self, items):
        return items[0]
