"""The signal chain of a rule file: period, params, inputs, `let` steps and outputs, and
their expressions turned into sympy node by node (never from text), with units checked.
Stateful calls (delta, prev, lowpass) become hidden steps, so every expression in the
Model is a pure function of the current sample."""

from __future__ import annotations

import sympy

from .. import units
from ...errors import suggest
from ...semantics.model import Op, Output, OutputKind, Param, Signal, Step
from ..syntax import Expr, Stmt

PURE_FUNCTIONS = {"clamp": 3, "abs": 1, "min": None, "max": None, "sqrt": 1, "exp": 1, "log": 1}

STATEFUL_FUNCTIONS = {"delta": 1, "prev": 1, "lowpass": 3}

# The names the builder generates (the hidden steps of delta, prev, lowpass) start with this;
# a declared name may not (docs/language.md), so the two never meet.
RESERVED_PREFIX = "__"

BINARY_OPS = ("add", "sub", "mul", "div", "pow")


def fold_left(node: Expr, leaf, binary):
    """Evaluate an expression tree without recursing down left operands: a sum of 1000 terms is
    a left-deep chain 1000 deep. `leaf(n)` gives the value of a node that is no binary operator
    (and of every right operand), `binary(n, left_value, right_value)` that of a binary node."""
    spine = []
    while node.op in BINARY_OPS:
        spine.append(node)
        node = node.args[0]
    value = leaf(node)
    for parent in reversed(spine):
        value = binary(parent, value, leaf(parent.args[1]))
    return value


# What fuzzyc.engine.expressions (the engine) and the C back end compute, besides symbols and real numbers.
COMPUTED = (sympy.Add, sympy.Mul, sympy.Pow, sympy.Min, sympy.Max, sympy.Abs, sympy.exp,
            sympy.log, sympy.sign)


def uncomputable(expr) -> str | None:
    """Why the engine and the C back end cannot compute `expr` (a node sympy made of it that
    neither has, or a number that is not real, as log(-1) = I*pi), else None."""
    for node in sympy.preorder_traversal(expr):
        if node.is_number:
            if not node.is_extended_real:
                return (f"this expression makes `{node}` (sympy's value of it), which is not a "
                        "real number")
        elif not isinstance(node, (sympy.Symbol, *COMPUTED)):
            return (f"sympy rewrites this expression with `{node}`, and the engine and the C "
                    f"back end have no `{type(node).__name__}` (they compute + - * / ^, abs, "
                    "min, max, clamp, sqrt, exp, log): write it another way")
    return None


class ChainBuilder:
    """The statements and expressions of the signal chain (a part of `Builder`)."""

    def _stmt_period(self, s: Stmt) -> None:
        unit = units.make(s.data["unit"])
        scale = units.SECONDS.get(unit[0][0]) if len(unit) == 1 and unit[0][1] == 1 else None
        if scale is None:
            self.error(s.data["value"].loc, "period needs a time unit: s, ms or us")
            return
        self.period = s.data["value"].value * scale

    def _stmt_param(self, s: Stmt) -> None:
        name = s.data["name"]
        if self._declare(name, "param"):
            unit = units.make(s.data["unit"]) if s.data["unit"] else None
            self.params[name.text] = Param(name.text, s.data["value"].value,
                                           units.format_unit(unit) if unit else None, name.loc)
            self.units[name.text] = unit

    def _stmt_input(self, s: Stmt) -> None:
        name = s.data["name"]
        rng = self._range(s.data["range"], f"input `{name.text}`")
        if rng is None:
            self.broken.add(name.text)
        if self._declare(name, "input") and rng:
            unit = units.make(s.data["unit"]) if s.data["unit"] else None
            self.signals[name.text] = Signal(name.text, rng[0], rng[1],
                                             units.format_unit(unit) if unit else None, name.loc)
            self.units[name.text] = unit

    def _stmt_let(self, s: Stmt) -> None:
        name = s.data["name"]
        if not self._declare(name, "signal"):
            return
        declared = units.make(s.data["unit"]) if s.data["unit"] else None
        expr, unit = self._expression(s.data["expr"], allow_stateful=True, owner=name.text)
        rng = self._range(s.data["range"], f"`{name.text}`") if s.data["range"] else None
        if expr is None or (s.data["range"] and rng is None):
            self.broken.add(name.text)
            return
        if declared is not None and unit is not None and declared != unit:
            self.error(s.data["expr"].loc,
                       f"`{name.text}` is declared in {units.format_unit(declared)} but its "
                       f"expression is in {units.format_unit(unit)}")
        self.units[name.text] = declared if declared is not None else unit
        step = Step(name.text, Op.ASSIGN, expr,
                    unit=units.format_unit(self.units[name.text]) if self.units[name.text] else None,
                    lo=rng[0] if rng else None, hi=rng[1] if rng else None, loc=name.loc)
        self._add_step(step)

    def _add_step(self, step: Step) -> None:
        self.steps.append(step)
        self.step_by_name[step.name] = step

    def _stmt_output(self, s: Stmt) -> None:
        d = s.data
        name = d["name"]
        if not self._declare(name, "output"):
            return
        rng = self._range(d["range"], f"output `{name.text}`")
        expr_node = d["expr"]
        kind, inner = OutputKind.DIRECT, expr_node
        if expr_node.op == "call" and expr_node.name == "integrate":
            kind, inner = OutputKind.INCREMENT, expr_node.args
        elif (expr_node.op == "div" and expr_node.args[0].op == "constant"
              and expr_node.args[0].args[0] == 1.0 and expr_node.args[1].op == "call"
              and expr_node.args[1].name == "integrate"):
            kind, inner = OutputKind.RECIPROCAL_INCREMENT, expr_node.args[1].args
        if isinstance(inner, list):
            if len(inner) != 1:
                self.error(expr_node.loc, "integrate takes one argument: the increment per sample")
                return
            inner = inner[0]
        expr, _unit = self._expression(inner, allow_stateful=False)
        if expr is None or rng is None:
            return
        if kind == OutputKind.RECIPROCAL_INCREMENT and rng[0] <= 0:
            self.error(d["range"][0].loc, "a reciprocal output needs a range above 0")
            return
        init = d["init"].value if d["init"] is not None else rng[0]
        if not rng[0] <= init <= rng[1]:
            self.error(d["init"].loc, f"start value {init:g} is outside [{rng[0]:g}, {rng[1]:g}]; "
                                      "write one within the range")
            return
        unit = units.make(d["unit"]) if d["unit"] else None
        self.units[name.text] = unit
        self.outputs.append(Output(name.text, kind, expr, rng[0], rng[1], init,
                                   units.format_unit(unit) if unit else None, name.loc))

    def _known_symbol(self, name: str) -> bool:
        return (name in self.params or name in self.signals or name in self.step_by_name
                or (name in self.vars and not self.vars[name].is_input))

    def _expression(self, node: Expr, allow_stateful: bool, owner: str = ""):
        """(sympy expression, unit) for an expression node; (None, None) after an error.

        The symbols are built real (signals and params are real numbers), so that sympy's
        automatic rewrites stay real: abs(exp(a)) is exp(a), not exp(re(a)) as for a complex
        `a`. The result has plain symbols, as the rest of fuzzyc names them (a real and a
        plain symbol of the same name are different symbols to sympy)."""
        expr, unit = self._sympy(node, allow_stateful, owner)
        if expr is None:
            return None, None
        expr = expr.xreplace({x: sympy.Symbol(x.name) for x in expr.free_symbols})
        problem = uncomputable(expr)
        if problem is not None:
            self.error(node.loc, problem)
            return None, None
        return expr, unit

    def _sympy(self, node: Expr, allow_stateful: bool, owner: str = ""):
        """(sympy expression with real symbols, unit) for an expression node; (None, None)
        after an error. Callers outside the recursion use `_expression`."""
        op = node.op
        if op == "constant":
            value, is_int = node.args
            return (sympy.Integer(int(value)) if is_int else sympy.Float(value)), None
        if op == "symbol":
            name = node.args[0]
            if name in self.broken:
                return None, None
            if not self._known_symbol(name):
                steps = [n for n, st in self.step_by_name.items() if not st.hidden]
                outs = [n for n, v in self.vars.items() if not v.is_input]
                known = sorted([*self.params, *self.signals, *steps, *outs])
                self.error(node.loc, f"unknown name `{name}`: {suggest(name, known)}")
                return None, None
            return sympy.Symbol(name, real=True), self.units.get(name)
        if op == "call":
            return self._call(node, allow_stateful, owner)
        if op == "neg":
            a, ua = self._sympy(node.args[0], allow_stateful, owner)
            return (None, None) if a is None else (-a, ua)
        return fold_left(node, lambda n: self._sympy(n, allow_stateful, owner),
                         self._sympy_binary)

    def _sympy_binary(self, node: Expr, left, right):
        """(sympy, unit) of a binary `node` from its operands' (either (None, None) after an
        error)."""
        op = node.op
        (a, ua), (b, ub) = left, right
        if a is None or b is None:
            return None, None
        if op in ("add", "sub"):
            return (a + b if op == "add" else a - b), self._same_unit(ua, ub, node.args[1], op)
        if op == "mul":
            return a * b, units.multiply(ua, ub)
        if op == "div":
            return a / b, units.multiply(ua, ub, -1)
        if op == "pow":
            exponent = int(b) if b.is_Integer else None
            if ua is not None and exponent is None:
                self.error(node.loc, "a quantity with a unit can only be raised to a whole number")
                return None, None
            return a ** b, units.power(ua, exponent) if exponent is not None else None
        raise AssertionError(op)

    def _same_unit(self, ua, ub, operand: Expr, what: str):
        """The unit of a sum (or of min/max/clamp) whose operands so far have unit `ua` and
        whose next operand, `operand`, has `ub`; a mismatch is reported at that operand (the
        one that disagrees with what came before it), not at the start of the expression."""
        if ua is not None and ub is not None and ua != ub:
            verb = {"add": "add", "sub": "subtract", "compare": "compare"}.get(what, "combine")
            self.error(operand.loc, f"unit mismatch: cannot {verb} {units.format_unit(ua)} and "
                                 f"{units.format_unit(ub)}")
        return ua if ua is not None else ub

    def _call(self, node: Expr, allow_stateful: bool, owner: str):
        fn, args = node.name, node.args
        arity = PURE_FUNCTIONS.get(fn, STATEFUL_FUNCTIONS.get(fn, -1))
        if arity == -1:
            hint = ("; integrate() is only allowed as a whole output expression"
                    if fn == "integrate" else "")
            known = [*PURE_FUNCTIONS, *STATEFUL_FUNCTIONS]
            self.error(node.loc, f"unknown function `{fn}`: {suggest(fn, known)}{hint}")
            return None, None
        if arity is not None and len(args) != arity:
            self.error(node.loc, f"`{fn}` takes {arity} argument{'s' if arity > 1 else ''}, "
                                 f"got {len(args)}")
            return None, None
        if fn in STATEFUL_FUNCTIONS:
            if not allow_stateful:
                self.error(node.loc, f"`{fn}` keeps state: use it in a `let`, then name that signal")
                return None, None
            return self._stateful(node, owner)
        parts = [self._sympy(a, allow_stateful, owner) for a in args]
        if any(p[0] is None for p in parts):
            return None, None
        values = [p[0] for p in parts]
        unit = parts[0][1]
        if fn in ("clamp", "min", "max"):
            for arg, p in zip(args[1:], parts[1:]):
                unit = self._same_unit(unit, p[1], arg, "combine")
        if fn == "clamp":
            return sympy.Min(sympy.Max(values[0], values[1]), values[2]), unit
        if fn in ("min", "max"):
            return (sympy.Min if fn == "min" else sympy.Max)(*values), unit
        if fn == "abs":
            return sympy.Abs(values[0]), unit
        function = {"sqrt": sympy.sqrt, "exp": sympy.exp, "log": sympy.log}[fn]
        if fn != "sqrt" and unit:
            self.error(node.loc, f"`{fn}` needs a dimensionless argument, got {units.format_unit(unit)}")
        return function(values[0]), None

    def _stateful(self, node: Expr, owner: str):
        arg, unit = self._expression(node.args[0], True, owner)
        if arg is None:
            return None, None
        coeffs = (0.0, 0.0)
        op = {"delta": Op.DELTA, "prev": Op.PREV, "lowpass": Op.LOWPASS}[node.name]
        if op == Op.LOWPASS:
            a = self._constant(node.args[1], "the lowpass coefficient a")
            b = self._constant(node.args[2], "the lowpass coefficient b")
            if a is None or b is None:
                return None, None
            if not (0 <= a < 1 and b > 0):
                self.error(node.args[1].loc, f"lowpass(x, a, b) needs 0 <= a < 1 and b > 0 "
                                             f"(y = a*y_prev + b*x), got a={a:g}, b={b:g}")
                return None, None
            coeffs = (a, b)
        self._hidden_count += 1
        # RESERVED_PREFIX: no declared name starts so (core._declare), so none is overwritten
        name = f"{RESERVED_PREFIX}{node.name}{self._hidden_count}_{owner}"
        self._add_step(Step(name, op, arg, coeffs, units.format_unit(unit) if unit else None,
                            hidden=True, loc=node.loc))
        self.units[name] = unit
        return sympy.Symbol(name, real=True), unit
