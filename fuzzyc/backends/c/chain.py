"""The signal chain of the float/double header: the chain walk (`fuzzyc.semantics.chain_ops`) in a
domain whose values are C expressions and whose effects are C statements.

The state struct holds per stateful step its memory and a `seen` flag (a finite value was
stored), per output its state; `NAME_step` runs the steps, the rule base, then the outputs,
with the float semantics' rules for non-finite values spelled as `isfinite` tests.
"""
from __future__ import annotations

from typing import Callable, NamedTuple

from ...escape import c_identifier
from ...semantics.chain_ops import OUTPUT_OPS, STEP_OPS, run_chain
from ...semantics.model import Model
from .expressions import ExprPrinter, RealType


class _Held(NamedTuple):
    """`then` where `test` is finite, else `otherwise` (an output's state: printed as an `if`
    that leaves it alone)."""
    test: str
    then: str
    otherwise: str


class CChain:
    """The chain walk's C domain for one model in one real type; helpers are named with
    prefix `p` (`p`clamp), rule-base sizes with `P`, names spelled by `symbol`."""

    def __init__(self, model: Model, real: RealType, p: str, P: str,
                 symbol: Callable[[str], str], blocks: list[tuple]):
        self.model, self.real, self.p, self.P, self.symbol = model, real, p, P, symbol
        # per emitted rule base (fuzzyc.backends.rule_blocks): it, the prefixes of its
        # rulebase function and of its sizes
        self.blocks = blocks
        self.lit, self.t = real.lit, real.name
        self.printer = ExprPrinter(real, symbol, p)
        self.code: list[str] = []

    # -- the state ----------------------------------------------------------------------------

    def state_fields(self) -> list[str]:
        t, fields = self.t, []
        for s in self.model.steps:
            if STEP_OPS[s.op].stateful:
                ident = c_identifier(s.name)
                fields += [f"    {t} memory_{ident};   /* last finite value */",
                           f"    unsigned char seen_{ident};   /* a finite value was stored */"]
        for o in self.model.outputs:
            state = "1/u(k-1)" if OUTPUT_OPS[o.kind].reciprocal else "u(k-1)"
            fields.append(f"    {t} out_{c_identifier(o.name)};   /* {state} */")
        return fields or ["    unsigned char unused;"]

    def init_lines(self) -> list[str]:
        lines = []
        for s in self.model.steps:
            if STEP_OPS[s.op].stateful:
                ident = c_identifier(s.name)
                lines += [f"    s->memory_{ident} = {self.lit(0)};", f"    s->seen_{ident} = 0;"]
        if not lines and not self.model.outputs:
            lines.append("    s->unused = 0;")      # the struct has only this field
        for o in self.model.outputs:
            lines.append(f"    s->out_{c_identifier(o.name)} = "
                         f"{self.lit(OUTPUT_OPS[o.kind].initial_state(o))};")
        return lines

    def statements(self) -> list[str]:
        """The body of NAME_step after the signals are read: steps, rule base, outputs."""
        self.code = []
        run_chain(self.model, self)
        return self.code

    # -- arithmetic -----------------------------------------------------------------------

    @staticmethod
    def sub(a: str, b: str) -> str:
        return f"{a} - {b}"

    def mix(self, a: float, x: str, b: float, y: str) -> str:
        return f"{self.lit(a)} * {x} + {self.lit(b)} * {y}"

    def zero_unless_nan(self, x: str) -> str:
        return f"({x} != {x} ? {x} : {self.lit(0)})"

    def clamp(self, x: str, lo: float, hi: float) -> str:
        return f"{self.p}clamp({x}, {self.lit(lo)}, {self.lit(hi)})"

    @staticmethod
    def if_finite(test: str, then: str, otherwise: str) -> _Held:
        return _Held(test, then, otherwise)

    def finite_or_zero(self, x: str) -> str:
        return f"(isfinite({x}) ? {x} : {self.lit(0)})"

    def saturating_add(self, state: str, x: str, lo: float, hi: float) -> str:
        return self.clamp(f"{state} + {x}", lo, hi)

    def reciprocal(self, o, state: str) -> str:
        return f"{self.lit(1)} / {state}"

    # -- steps: `T v; { const T arg = ...; v = seen ? ... : ...; store }` -----------------------

    @staticmethod
    def _slots(s) -> tuple[str, str]:
        ident = c_identifier(s.name)
        return f"s->memory_{ident}", f"s->seen_{ident}"

    def argument(self, s, stateful: bool) -> str:
        text = self.printer(s.expr)
        if not stateful:
            return text
        self.code += [f"{self.t} {self.symbol(s.name)};", "{", f"    const {self.t} arg = {text};"]
        return "arg"

    def memory(self, s, rule, arg: str) -> str:
        return self._slots(s)[0]

    @staticmethod
    def may_be_seen(s) -> bool:
        return True

    @staticmethod
    def may_be_fresh(s) -> bool:
        return True

    def select(self, s, seen: str, fresh: str) -> str:
        v = self.symbol(s.name)
        self.code.append(f"    {v} = {self._slots(s)[1]} ? {seen} : {fresh};")
        return v

    def store(self, s, keep: str) -> None:
        mem, seen = self._slots(s)
        self.code.append(f"    if (isfinite({keep})) {{ {mem} = {keep}; {seen} = 1; }}")

    def define(self, s, value: str) -> None:
        if STEP_OPS[s.op].stateful:     # declared and set in its block: close it
            self.code.append("}")
        else:
            self.code.append(f"const {self.t} {self.symbol(s.name)} = {value};")

    # -- the rule base and the outputs ----------------------------------------------------------

    def rule_blocks(self) -> None:
        """Each block in order: its inputs (signals, steps or earlier blocks' outputs) into
        x, its rulebase, its outputs named; x and y numbered where there are several."""
        t, symbol = self.t, self.symbol
        many = len(self.blocks) > 1
        for k, (rb, p, P) in enumerate(self.blocks):
            x, y = (f"x{k}", f"y{k}") if many else ("x", "y")
            self.code += [f"{t} {x}[{P}N_RB_INPUTS], {y}[{P}N_RB_OUTPUTS];"]
            if k == 0:
                self.code += [f"{t} {symbol(o.name)};" for o in self.model.outputs]
            self.code += [f"{x}[{i}] = {symbol(v.name)};" for i, v in enumerate(rb.inputs)]
            self.code += [f"{p}rulebase({x}, {y});"]
            self.code += [f"const {t} {symbol(v.name)} = {y}[{o}];"
                          for o, v in enumerate(rb.outputs)]

    @staticmethod
    def limits(o) -> tuple[float, float]:
        return OUTPUT_OPS[o.kind].state_limits(o)

    def output_value(self, k: int, o) -> str:
        self.code += ["{", f"    const {self.t} value = {self.printer(o.expr)};"]
        return "value"

    @staticmethod
    def output_state(o) -> str:
        return f"s->out_{c_identifier(o.name)}"

    def set_state(self, o, state) -> None:
        ref = self.output_state(o)
        if isinstance(state, _Held):      # held against this state (OutputOp.update)
            self.code.append(f"    if (isfinite({state.test})) {ref} = {state.then};")
        else:
            self.code.append(f"    {ref} = {state};")

    read_state = output_state

    def emit_output(self, k: int, o, result: str) -> None:
        self.code += [f"    out[{k}] = {result};", f"    {self.symbol(o.name)} = out[{k}];", "}"]
