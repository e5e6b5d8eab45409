"""fuzzylite's `Function` terms: a formula of x and of other variables' values.

The text is parsed with lark (numbers, names, + - * / % ^, unary minus, parentheses, calls of
fuzzylite's function set) and kept as a plain tree of tuples (`Formula.tree`), evaluated by
walking it with numpy over a batch; the text never reaches eval/exec/sympify.  Nodes:
  ("num", value) | ("name", name) | ("neg", a) | (op, a, b) for op in + - * / % ^ |
  ("call", function, a[, b]).
Arithmetic is IEEE: 0/0 is NaN, 1/0 inf, an overflowing power inf (numpy, warnings off); what a
non-finite value means is the caller's (the engine's policy, fuzzyc.engine.held_outputs).
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from lark import Lark, Transformer
from lark.exceptions import UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

MAX_TEXT = 2000       # characters: a formula is one line of a rule file
MAX_DEPTH = 64        # nesting of parentheses, and of the parsed tree: deeper is refused

GRAMMAR = r"""
?start: sum
?sum: product | sum "+" product -> add | sum "-" product -> sub
?product: unary | product "*" unary -> mul | product "/" unary -> div
        | product "%" unary -> mod
?unary: power | "-" unary -> neg | "+" unary
?power: atom | atom ("^" | "**") unary -> pow
?atom: NUMBER -> num | NAME -> name | NAME "(" [sum ("," sum)*] ")" -> call | "(" sum ")"
NUMBER: /([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?/
NAME: /[A-Za-z_][A-Za-z0-9_]*/
%ignore /[ \t]+/
"""


def _compare(op):
    return lambda a, b: op(a, b).astype(float)


# fuzzylite's functions (pyfuzzylite 8 FunctionFactory; fuzzylite 6 has the same names)
FUNCTIONS = {
    **{name: (1, f) for name, f in {
        "abs": np.fabs, "fabs": np.fabs, "acos": np.arccos, "asin": np.arcsin,
        "atan": np.arctan, "ceil": np.ceil, "cos": np.cos, "cosh": np.cosh, "exp": np.exp,
        "floor": np.floor, "log": np.log, "log10": np.log10, "round": np.round, "sin": np.sin,
        "sinh": np.sinh, "sqrt": np.sqrt, "tan": np.tan, "tanh": np.tanh, "log1p": np.log1p,
        "expm1": np.expm1, "acosh": np.arccosh, "asinh": np.arcsinh,
        "atanh": np.arctanh}.items()},
    **{name: (2, f) for name, f in {
        "pow": np.float_power, "atan2": np.arctan2, "fmod": np.fmod, "min": np.minimum,
        "max": np.maximum, "gt": _compare(np.greater), "ge": _compare(np.greater_equal),
        "lt": _compare(np.less), "le": _compare(np.less_equal), "eq": _compare(np.equal),
        "neq": _compare(np.not_equal)}.items()},
}
CONSTANTS = {"pi": np.pi}
OPERATORS = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.true_divide,
             "%": np.remainder, "^": np.float_power}
PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "%": 2, "neg": 3, "^": 4}


class FormulaError(ValueError):
    """What is wrong with a formula, and where: `offset` (0-based) into its text."""

    def __init__(self, message: str, offset: int):
        super().__init__(message)
        self.offset = offset


class _Tree(Transformer):
    def num(self, items):
        return ("num", float(items[0]))

    def name(self, items):
        name = str(items[0])
        return ("num", CONSTANTS[name]) if name in CONSTANTS else ("name", name)

    def neg(self, items):
        return ("neg", items[0])

    def call(self, items):
        token, args = items[0], [a for a in items[1:] if a is not None]
        arity, _ = FUNCTIONS.get(str(token), (None, None))
        if arity is None:
            raise FormulaError(f"unknown function `{token}`: fuzzylite's are "
                               + ", ".join(sorted(FUNCTIONS)), token.start_pos)
        if len(args) != arity:
            raise FormulaError(f"`{token}` takes {arity} argument{'s' * (arity > 1)}, got "
                               f"{len(args)}", token.start_pos)
        return ("call", str(token), *args)


for _op, _rule in (("+", "add"), ("-", "sub"), ("*", "mul"), ("/", "div"), ("%", "mod"),
                   ("^", "pow")):
    setattr(_Tree, _rule, lambda self, items, op=_op: (op, items[0], items[1]))


@lru_cache(maxsize=1)
def _parser() -> Lark:
    return Lark(GRAMMAR, parser="lalr")


@dataclass(frozen=True)
class Formula:
    """A parsed formula: its text as written and its tree (see the module docstring)."""
    text: str
    tree: tuple

    def names(self) -> set[str]:
        """The variable names it reads (x among them when it does)."""
        found, stack = set(), [self.tree]
        while stack:
            node = stack.pop()
            if node[0] == "name":
                found.add(node[1])
            else:
                stack.extend(n for n in node[1:] if isinstance(n, tuple))
        return found

    def evaluate(self, env: dict[str, np.ndarray | float]) -> np.ndarray:
        """The formula at every sample of env (name -> (N,) or scalar), IEEE arithmetic."""
        with np.errstate(all="ignore"):
            return np.asarray(_value(self.tree, env), dtype=float)

    def infix(self) -> str:
        """The formula written back (fuzzylite's syntax; parenthesised where needed)."""
        return _infix(self.tree)


def _value(node: tuple, env):
    kind = node[0]
    if kind == "num":
        return node[1]
    if kind == "name":
        return env[node[1]]
    if kind == "neg":
        return np.negative(_value(node[1], env))
    if kind == "call":
        return FUNCTIONS[node[1]][1](*(_value(a, env) for a in node[2:]))
    return OPERATORS[kind](_value(node[1], env), _value(node[2], env))


def _infix(node: tuple, parent: int = 0, right: bool = False) -> str:
    kind = node[0]
    if kind == "num":
        return "pi" if node[1] == np.pi else repr(node[1])
    if kind == "name":
        return node[1]
    if kind == "call":
        return f"{node[1]}(" + ", ".join(_infix(a) for a in node[2:]) + ")"
    own = PRECEDENCE[kind]
    if kind == "neg":
        text = "-" + _infix(node[1], own)
    else:   # left-associative but ^, which binds to the right
        text = (_infix(node[1], own, kind == "^") + f" {kind} "
                + _infix(node[2], own, kind != "^"))
    return f"({text})" if own < parent or (own == parent and right) else text


def parse_formula(text: str) -> Formula:
    """The formula of `text`; FormulaError (with the offset) for a syntax error or an unknown
    function.  The names it reads are checked by the importer (formats.functions.check_reads),
    once the model's variables are known."""
    if len(text) > MAX_TEXT:
        raise FormulaError(f"a formula of {len(text)} characters (at most {MAX_TEXT})", 0)
    depth = 0
    for offset, char in enumerate(text):
        depth += (char == "(") - (char == ")")
        if depth > MAX_DEPTH:
            raise FormulaError(f"parentheses nested deeper than {MAX_DEPTH}", offset)
    try:
        parsed = _parser().parse(text)
        if _depth(parsed) > MAX_DEPTH:
            raise FormulaError(f"the formula nests deeper than {MAX_DEPTH} operations", 0)
        tree = _Tree().transform(parsed)
    except UnexpectedInput as exc:
        at_end = isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken)
                                                     and exc.token.type == "$END")
        offset = len(text.rstrip()) if at_end else exc.pos_in_stream or 0
        what = "the formula ends too early" if at_end else f"unexpected `{text[offset]}`"
        raise FormulaError(f"{what}: a formula takes numbers, names, + - * / % ^, "
                           "parentheses and fuzzylite's functions", offset) from None
    except VisitError as exc:
        if isinstance(exc.orig_exc, FormulaError):
            raise exc.orig_exc from None
        raise
    return Formula(text.strip(), tree)


def _depth(tree) -> int:
    """The depth of a lark tree, counted without recursion (a hostile formula is deep)."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        deepest = max(deepest, depth)
        stack.extend((child, depth + 1) for child in getattr(node, "children", ()))
    return deepest


def name_offset(text: str, name: str) -> int:
    """Where `name` first stands as a whole word in `text` (0 if nowhere)."""
    found = re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", text)
    return found.start() if found else 0
