"""C99 text for the numbers and sympy expressions of a model, in one real type (float or double).

Only the node kinds that `fuzzyc.engine.expressions` evaluates are printed, with the same NaN behaviour:
min/max propagate NaN like numpy's minimum/maximum (C's fmin/fmax would drop it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import sympy

from ...errors import Diagnostic, FuzzycError


@dataclass(frozen=True)
class RealType:
    """The C real type and the spelling of its literals and libm functions."""
    name: str        # "float" | "double"
    suffix: str      # literal and libm suffix: "f" for float

    def lit(self, value: float) -> str:
        value = float(value)
        if math.isnan(value):
            raise ValueError("a NaN constant cannot be emitted")
        if math.isinf(value):
            return "INFINITY" if value > 0 else "(-INFINITY)"
        text = repr(value)
        if "e" not in text and "." not in text:
            text += ".0"
        text += self.suffix
        return f"({text})" if value < 0 else text

    def fn(self, name: str) -> str:
        return name + self.suffix


FLOAT = RealType("float", "f")
DOUBLE = RealType("double", "")
REAL_TYPES = {"float": FLOAT, "double": DOUBLE}


class ExprPrinter:
    """sympy expression -> C expression; `symbol` maps a symbol name to its C spelling.

    The helpers min/max/sign are called as `helper_prefix + name` (the header defines them).
    """

    def __init__(self, real: RealType, symbol: Callable[[str], str], helper_prefix: str):
        self.real = real
        self.symbol = symbol
        self.helper = helper_prefix

    def __call__(self, expr: sympy.Expr) -> str:
        r = self.real
        if isinstance(expr, sympy.Symbol):
            return self.symbol(expr.name)
        if expr.is_number:
            return r.lit(float(expr))
        args = [self(a) for a in expr.args]
        if isinstance(expr, sympy.Add):
            return "(" + " + ".join(args) + ")"
        if isinstance(expr, sympy.Mul):
            return "(" + " * ".join(args) + ")"
        if isinstance(expr, (sympy.Min, sympy.Max)):
            fn = self.helper + ("min" if isinstance(expr, sympy.Min) else "max")
            out = args[0]
            for a in args[1:]:
                out = f"{fn}({out}, {a})"
            return out
        if isinstance(expr, sympy.Abs):
            return f"{r.fn('fabs')}({args[0]})"
        if isinstance(expr, sympy.exp):
            return f"{r.fn('exp')}({args[0]})"
        if isinstance(expr, sympy.log):
            return f"{r.fn('log')}({args[0]})"
        if isinstance(expr, sympy.sign):
            return f"{self.helper}sign({args[0]})"
        if isinstance(expr, sympy.Pow):
            return self._power(expr, args[0])
        raise FuzzycError([Diagnostic(None, f"the C back end cannot translate `{expr}` "
                                            f"({type(expr).__name__})")])

    def _power(self, expr: sympy.Pow, base: str) -> str:
        exponent = expr.args[1]
        if exponent.is_number:
            e = float(exponent)
            if e == -1.0:
                return f"({self.real.lit(1.0)} / {base})"
            if e == 0.5:
                return f"{self.real.fn('sqrt')}({base})"
            if e in (2.0, 3.0):
                return "(" + " * ".join([base] * int(e)) + ")"
        return f"{self.real.fn('pow')}({base}, {self(exponent)})"
