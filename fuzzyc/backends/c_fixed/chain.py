"""The whole signal chain in fixed point (q15/q31): integer arithmetic from raw inputs to outputs.

Every signal has a range: inputs and outputs declare one, a `let ... in [lo, hi]` is saturated
to its declared one, and any other value takes the interval bound of its expression (inputs
saturated to their declared ranges first, so the bounds hold).  From its range each value gets
a binary point: it is the integer round(v * 2**frac) with frac the largest that keeps it within
31 bits plus a sign, so the chain itself loses about 1e-9 of a range per operation; memories
are kept at that precision too (an increment of 1.8e-4 * du per sample would vanish at 15
bits), integrator states at STATE_GUARD bits more in int64 (a constant increment rounds the
same way every sample).  Products and alignments run in int64 and round to nearest.
The I/O arrays are int16_t (q15) or int32_t (q31) with their own binary points (the header
#defines NAME_Q15_IN_x_FRAC / NAME_Q15_OUT_x_FRAC), and the rule base in between is the one of
`c_fixed`, called at its guard precision (`NAME_rulebase_wide`), so the chain does not round
to the I/O LSB there.  Emitted operations: + - and * (constants and params folded), min/max
(clamp), delta, prev, lowpass (0 <= a < 1, b >= 0), direct, integrate and 1/integrate outputs.
Anything else is a diagnostic naming the step.

Every value also carries `err`, a bound on |C value - the exact value of the same expression on
the same inputs| derived by interval reasoning over the rounding of every operation: a
constant is off by its own rounding, a right shift by half its new LSB, a sum by the sum of
its terms' errors, a product c x by |c| err_x + |c' - c| (max|x| + err_x) (c' the rounded
constant), x y by |x| err_y + |y| err_x + err_x err_y, min/max/clamp by the largest error of
their arguments (they are 1-Lipschitz); delta by twice its argument's (the memory holds an
earlier argument), a low-pass by the fixed point E = f(E) of its recursion (f affine with slope
a + |a' - a| < 1), the rule base by `c_fixed.derived_error_bound` with its inputs' errors,
an integrator by its initial rounding plus N times its increment's error after N steps (the
saturation is 1-Lipschitz), 1/v by err_v / (v_min (v_min - err_v)) plus the division's
rounding.  `FixedChain.output_errors` collects the outputs' bounds (see
c_fixed.chain_error_bound); the exact chain is the engine's Controller, up to float64 rounding.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import sympy

from ...errors import Diagnostic, FuzzycError
from ...semantics.chain_ops import OUTPUT_OPS, STEP_OPS, run_output, run_step
from ...semantics.model import Model
from ...escape import c_identifier

CHAIN_BITS = 31
# assumption: integrator states carry 16 fraction bits more than their range allows in 31 bits
# (int64 state).  A constant increment that is not a multiple of the state's LSB is rounded the
# same way every sample: WEDM's 8e-5 * (-0.5) = -85899.35 LSB of 1/t_off at 31 bits lost 0.35
# LSB per sample, 600 LSB over a long stretch, which 1/v^2 = 48^2 made 1.4e-5 of t_off's
# range.  16 bits make that 2^-16 as much; values read from the state are rounded back to
# 31 bits, so the products downstream stay in int64.
STATE_GUARD = 16


@dataclass(frozen=True)
class Fx:
    """A fixed-point value: the C int64 expression `code` stands for code * 2**-frac, and the
    value lies in [lo, hi]."""
    code: str
    frac: int
    lo: float
    hi: float
    err: float = 0.0      # |C value - exact value|, at most (see the module docstring)

    @property
    def magnitude(self) -> float:
        """The largest |C value|."""
        return max(abs(self.lo), abs(self.hi)) + self.err


def frac_for(lo: float, hi: float, bits: int = CHAIN_BITS) -> int:
    """The most fraction bits with which every value of [lo, hi] rounds into `bits` bits."""
    m = max(abs(lo), abs(hi))
    if m == 0.0:
        return bits - 1
    frac = bits - 1 - math.floor(math.log2(m))
    return frac - 1 if round(m * 2.0 ** frac) >= 2 ** bits else frac


def const_error(value: float, frac: int) -> float:
    """How far the constant's integer at frac bits is from it."""
    return abs(round(value * 2.0 ** frac) / 2.0 ** frac - value)


def drop_error(frm: int, to: int) -> float:
    """The rounding of a value at frm bits to `to` bits (none when bits are added)."""
    return 0.5 * 2.0 ** -to if to < frm else 0.0


def _fail(message: str) -> FuzzycError:
    return FuzzycError([Diagnostic(None, message)])


class FixedChain:
    """Builds the C statements of one chain; the helpers are named with prefix `p`."""

    def __init__(self, model: Model, p: str):
        self.model, self.p = model, p
        self.params = {name: float(prm.value) for name, prm in model.params.items()}
        self.symbols: dict[str, Fx] = {}
        self.where = ""          # the step being translated, for diagnostics
        self.memories: list[str] = []    # identifiers of the stateful steps
        self.io = "int64_t"
        self.steps = 1                   # the run length the integrators' errors are bound for
        self.rulebase_error = None       # input errors (LSBs) -> rule-base output errors
        self.output_errors: dict[str, float] = {}
        self.state_errors: dict[str, float] = {}     # per output: its state's, after update
        self.code: list[str] = []        # the statements of the step or output being walked
        self.io_frac, self.io_max = 0, 0     # the output being walked: its I/O scale

    # -- arithmetic on Fx and float constants -------------------------------------------------

    @staticmethod
    def const(value: float, frac: int) -> str:
        return str(int(round(value * 2.0 ** frac)))

    def rescale(self, code: str, frm: int, to: int) -> str:
        """`code` at frm fraction bits, at `to` bits (rounded to nearest when bits drop)."""
        if to == frm:
            return code
        if to > frm:   # a multiplication: << of a negative value is undefined in C
            return f"(int64_t)({code}) * {1 << (to - frm)}"
        return f"{self.p}shr({code}, {frm - to})"

    def align(self, v: Fx | float, frac: int) -> str:
        return self.const(v, frac) if isinstance(v, float) else self.rescale(v.code, v.frac, frac)

    @staticmethod
    def align_error(v: Fx | float, frac: int) -> float:
        return const_error(v, frac) if isinstance(v, float) else v.err + drop_error(v.frac, frac)

    def fitted(self, code: str, frac: int, lo: float, hi: float, err: float) -> Fx:
        """The value `code` (at frac bits, in [lo, hi], off by err) at the precision its range
        allows."""
        target = frac_for(lo, hi)
        return Fx(self.rescale(code, frac, target), target, lo, hi,
                  err + drop_error(frac, target))

    def add(self, terms: list) -> Fx | float:
        c = sum(t for t in terms if isinstance(t, float))
        signals = [t for t in terms if isinstance(t, Fx)]
        if not signals:
            return c
        lo = sum(t.lo for t in signals) + c
        hi = sum(t.hi for t in signals) + c
        frac = frac_for(lo, hi)
        parts = [self.align(t, frac) for t in signals] + ([self.const(c, frac)] if c else [])
        err = sum(self.align_error(t, frac) for t in signals) + (const_error(c, frac) if c else 0)
        return Fx("(" + " + ".join(parts) + ")", frac, lo, hi, err)

    def scale(self, v: Fx, c: float) -> Fx | float:
        if c == 0.0:
            return 0.0
        if c == 1.0:
            return v
        cf = frac_for(c, c)
        lo, hi = sorted((v.lo * c, v.hi * c))
        err = abs(c) * v.err + const_error(c, cf) * v.magnitude
        return self.fitted(f"(int64_t)({v.code}) * {self.const(c, cf)}", v.frac + cf, lo, hi, err)

    def mul(self, factors: list) -> Fx | float:
        c = math.prod(f for f in factors if isinstance(f, float))
        signals = [f for f in factors if isinstance(f, Fx)]
        if not signals:
            return c
        acc = signals[0]
        for f in signals[1:]:
            corners = [a * b for a in (acc.lo, acc.hi) for b in (f.lo, f.hi)]
            err = (max(abs(acc.lo), abs(acc.hi)) * f.err + max(abs(f.lo), abs(f.hi)) * acc.err
                   + acc.err * f.err)
            acc = self.fitted(f"(int64_t)({acc.code}) * ({f.code})", acc.frac + f.frac,
                              min(corners), max(corners), err)
        return self.scale(acc, c)

    def extremum(self, args: list, smaller: bool) -> Fx | float:
        pick = min if smaller else max
        consts = [a for a in args if isinstance(a, float)]
        signals = [a for a in args if isinstance(a, Fx)]
        if not signals:
            return pick(consts)
        values = signals + ([pick(consts)] if consts else [])
        lo = pick(v if isinstance(v, float) else v.lo for v in values)
        hi = pick(v if isinstance(v, float) else v.hi for v in values)
        frac = frac_for(min(v if isinstance(v, float) else v.lo for v in values),
                        max(v if isinstance(v, float) else v.hi for v in values))
        name = f"{self.p}{'lesser' if smaller else 'greater'}"
        code = self.align(values[0], frac)
        for v in values[1:]:
            code = f"{name}({code}, {self.align(v, frac)})"
        return self.fitted(code, frac, lo, hi, max(self.align_error(v, frac) for v in values))

    def saturate(self, v: Fx | float, lo: float, hi: float) -> Fx:
        """v held to [lo, hi] (a declared range), at the precision of that range."""
        v = self.constant(v)
        frac = frac_for(lo, hi)
        code = f"{self.p}sat({self.align(v, frac)}, {self.const(lo, frac)}, " \
               f"{self.const(hi, frac)})"
        # the bounds' own rounding moves the clamp by at most const_error
        err = self.align_error(v, frac) + max(const_error(lo, frac), const_error(hi, frac))
        return Fx(code, frac, max(lo, min(v.lo, hi)), min(hi, max(v.hi, lo)), err)

    def constant_power(self, e: sympy.Expr, base: float, exponent: float) -> float:
        """A power of parameters (`1/GE`) is a constant of the header."""
        try:
            value = base ** exponent
        except ZeroDivisionError:
            value = math.inf
        if not isinstance(value, float) or not math.isfinite(value):
            raise _fail(f"`{e}` in {self.where} is not a finite real number with the "
                        f"parameters' values")
        return value

    # -- sympy expressions --------------------------------------------------------------------

    def expr(self, e: sympy.Expr) -> Fx | float:
        if isinstance(e, sympy.Symbol):
            if e.name in self.params:
                return self.params[e.name]
            return self.symbols[e.name]
        if e.is_number:
            return float(e)
        args = [self.expr(a) for a in e.args]
        if isinstance(e, sympy.Add):
            return self.add(args)
        if isinstance(e, sympy.Mul):
            return self.mul(args)
        if isinstance(e, (sympy.Min, sympy.Max)):
            return self.extremum(args, isinstance(e, sympy.Min))
        if isinstance(e, sympy.Pow) and all(isinstance(a, float) for a in args):
            return self.constant_power(e, *args)
        raise _fail(f"the fixed-point chain does not emit `{e}` ({type(e).__name__}) in "
                    f"{self.where}; write it with + - * by constants and signals, powers of "
                    f"parameters, min, max, clamp, delta, prev, lowpass")

    # -- the chain ----------------------------------------------------------------------------

    def bind(self, name: str, v: Fx | float) -> tuple[str, Fx]:
        """A C declaration of the named value and its Fx (a C variable from then on)."""
        v = self.constant(v)
        var = f"v_{c_identifier(name)}"
        self.symbols[name] = Fx(var, v.frac, v.lo, v.hi, v.err)
        return f"const int64_t {var} = {v.code};", self.symbols[name]

    def constant(self, v: Fx | float) -> Fx:
        if isinstance(v, Fx):
            return v
        frac = frac_for(v, v)
        return Fx(self.const(v, frac), frac, v, v, const_error(v, frac))

    def step(self, s) -> list[str]:
        """The statements of one chain step (memories in the state `s`, kept at 31 bits)."""
        self.code = []
        run_step(self, s)
        return self.code

    # -- the chain walk's fixed-point domain (fuzzyc.semantics.chain_ops): values are Fx --------

    def sub(self, a: Fx, b: Fx) -> Fx:
        frac = max(a.frac, b.frac)
        return self.fitted(f"({self.align(a, frac)} - {self.align(b, frac)})", frac,
                           a.lo - b.hi, a.hi - b.lo,
                           self.align_error(a, frac) + self.align_error(b, frac))

    def mix(self, a: float, x: Fx, b: float, y: Fx) -> Fx:
        """a x + b y at x's precision and within x's range (a filter's memory bounds it)."""
        v = self.add([self.scale(x, a), self.scale(y, b)])
        return Fx(self.align(v, x.frac), x.frac, x.lo, x.hi, self.align_error(v, x.frac))

    @staticmethod
    def zero_unless_nan(x: Fx) -> float:
        return 0.0      # integers are never NaN

    def argument(self, s, stateful: bool) -> Fx | float:
        self.where = f"`let {s.name}`"
        arg = self.expr(s.expr)
        if not stateful:
            if s.lo is not None and s.hi is not None:
                arg = self.saturate(arg, s.lo, s.hi)
            return arg
        arg = self.constant(arg)
        self.code += [f"int64_t v_{c_identifier(s.name)};", "{",
                      f"    const int64_t arg = {arg.code};"]
        return Fx("arg", arg.frac, arg.lo, arg.hi, arg.err)

    def memory(self, s, rule, arg: Fx) -> Fx:
        """The memory as an Fx: an earlier argument at the argument's precision, or a value at
        the precision its bounds allow, off by the fixed point E = f(E) of its recursion's
        error (f affine: slope below 1 or no bound), from the first sample's (arg itself)."""
        mem = f"s->memory_{c_identifier(s.name)}"
        if rule.keeps == "argument":
            return Fx(mem, arg.frac, arg.lo, arg.hi, arg.err)
        bounds = rule.memory_bounds(s.coeffs, arg.lo, arg.hi)
        if bounds is None:
            coeffs = ", ".join(f"{n} = {c:g}" for n, c in zip("ab", s.coeffs))
            raise _fail(f"the fixed-point chain emits {rule.word} for {rule.bounded_when} only "
                        f"(bounded memory); {self.where} has {coeffs}")
        lo, hi = bounds
        frac = frac_for(lo, hi)

        def kept_error(memory_err: float) -> float:
            trial = Fx(mem, frac, lo, hi, memory_err)
            return rule.kept(arg, rule.when_seen(self, arg, trial, s.coeffs)).err
        slope = kept_error(1.0) - kept_error(0.0)
        start = self.align_error(arg, frac)
        memory_err = max(start, kept_error(0.0) / (1.0 - slope)) if slope < 1 else math.inf
        return Fx(mem, frac, lo, hi, memory_err)

    @staticmethod
    def may_be_seen(s) -> bool:
        return True

    @staticmethod
    def may_be_fresh(s) -> bool:
        return True

    def select(self, s, seen: Fx, fresh: Fx | float) -> Fx:
        ident = c_identifier(s.name)
        out = f"v_{ident}"
        self.code.append(f"    {out} = s->seen_{ident} ? {seen.code} : "
                         f"{self.align(fresh, seen.frac)};")
        self.symbols[s.name] = Fx(out, seen.frac, seen.lo, seen.hi, seen.err)
        return self.symbols[s.name]

    def store(self, s, keep: Fx) -> None:
        ident = c_identifier(s.name)     # integers are always finite: always stored
        self.memories.append(ident)
        self.code.append(f"    s->memory_{ident} = (int32_t){keep.code}; s->seen_{ident} = 1;")

    def define(self, s, value: Fx | float) -> None:
        if STEP_OPS[s.op].stateful:     # declared and set in its block: close it
            self.code.append("}")
        else:
            self.code.append(self.bind(s.name, value)[0])

    def rulebase_io(self, rb, full: int, rb_prefix: str, input_guard: int,
                    guards: list[int], suffix: str = "") -> list[str]:
        """Scale the rule-base inputs to [0, FULL] at 2^-input_guard of an LSB, call the wide
        rule base (so the chain does not round its inputs and outputs to the I/O LSB), read
        its outputs (output o at 2^-guards[o] of an LSB); xg and yw carry `suffix` (the
        block's number where a header has several)."""
        xg, yw = f"xg{suffix}", f"yw{suffix}"
        code = [f"int64_t {xg}[{len(rb.inputs)}], {yw}[{len(rb.outputs)}];"]
        input_errors = []     # in LSBs of the I/O scale, None where the engine is not clamped
        for i, var in enumerate(rb.inputs):
            self.where = f"the rule-base input `{var.name}`"
            x = self.constant(self.expr(sympy.Symbol(var.name)))
            gain = full * 2.0 ** input_guard / (var.hi - var.lo)
            cf = frac_for(gain, gain)
            # xg = (x - lo) gain rounded to an integer, in 2^-GI LSBs; the C clamps it to the
            # range, the engine does not: derived only where x stays in the range
            off = x.err + const_error(var.lo, x.frac)
            err = gain * off + const_error(gain, cf) * (max(abs(x.lo - var.lo),
                                                             abs(x.hi - var.lo)) + off) + 0.5
            inside = var.lo <= x.lo and x.hi <= var.hi
            input_errors.append(err / 2.0 ** input_guard if inside else None)
            shifted = f"(int64_t)({x.code} - {self.const(var.lo, x.frac)}) * " \
                      f"{self.const(gain, cf)}"
            code.append(f"{xg}[{i}] = {self.p}sat({self.rescale(shifted, x.frac + cf, 0)}, "
                        f"0, INT64_C({full << input_guard}));")
        code.append(f"{rb_prefix}rulebase_wide({xg}, {yw});")
        rb_errors = None
        if self.rulebase_error is not None and None not in input_errors:
            rb_errors = self.rulebase_error(input_errors)     # fractions of the ranges
        for o, var in enumerate(rb.outputs):
            # at most 31 bits, as every chain value (so the scaling product fits in int64)
            drop = max(0, (full << guards[o]).bit_length() - CHAIN_BITS)
            top = float(full << guards[o]) / 2.0 ** drop
            raw = f"{self.p}shr({yw}[{o}], {drop})" if drop else f"{yw}[{o}]"
            raw_err = math.inf if rb_errors is None else \
                rb_errors[o] * top + (0.5 if drop else 0.0)
            y = self.add([self.scale(Fx(raw, 0, 0.0, top, raw_err), (var.hi - var.lo) / top),
                          float(var.lo)])
            code.append(self.bind(var.name, y)[0])
        return code

    def output(self, k: int, o, io_frac: int, io_max: int) -> list[str]:
        """Statements updating output k's state (31 bits) and writing out[k]."""
        self.io_frac, self.io_max, self.code = io_frac, io_max, []
        run_output(self, k, o)
        return self.code

    def state_fields(self) -> list[str]:
        """The state struct's fields (after the steps: their memories are known)."""
        fields = [f"    int32_t memory_{i};\n    unsigned char seen_{i};" for i in self.memories]
        return fields + ([f"    {'int64_t' if OUTPUT_OPS[o.kind].integrates else 'int32_t'} "
                          f"out_{c_identifier(o.name)};   /* at 2^-{self.state_frac(o)} */"
                          for o in self.model.outputs] or ["    unsigned char unused;"])

    def init_lines(self) -> list[str]:
        init = [f"    s->memory_{i} = 0; s->seen_{i} = 0;" for i in self.memories]
        return init + [f"    s->out_{c_identifier(o.name)} = "
                       f"{self.const(self.initial_state(o), self.state_frac(o))};"
                       for o in self.model.outputs]

    def initial_state(self, o) -> float:
        """The state's start, held to its range (an integer state must lie there; the first
        update saturates the engine's too)."""
        lo, hi = self.state_range(o)
        return min(max(OUTPUT_OPS[o.kind].initial_state(o), lo), hi)

    # -- outputs in the chain walk's domain ------------------------------------------------------

    def limits(self, o) -> tuple[float, float]:
        return self.state_range(o)

    def output_value(self, k: int, o) -> Fx:
        self.where = f"the output `{o.name}`"
        return self.constant(self.expr(o.expr))

    def output_state(self, o) -> Fx:
        frac = self.state_frac(o)
        lo, hi = self.state_range(o)
        return Fx(f"s->out_{c_identifier(o.name)}", frac, lo, hi,
                  const_error(self.initial_state(o), frac))

    def clamp(self, x: Fx | float, lo: float, hi: float) -> Fx:
        return self.saturate(x, lo, hi)

    @staticmethod
    def if_finite(test: Fx, then: Fx, otherwise: Fx) -> Fx:
        return then     # integers are always finite

    @staticmethod
    def finite_or_zero(x: Fx) -> Fx:
        return x

    def saturating_add(self, state: Fx, x: Fx, lo: float, hi: float) -> Fx:
        """state + x held to [lo, hi] at the state's precision; its error after `steps`
        samples: the start's plus `steps` times the increment's and the bounds' rounding."""
        frac = state.frac
        bounds_err = max(const_error(lo, frac), const_error(hi, frac))
        code = f"{self.p}sat_add({state.code}, {self.align(x, frac)}, {self.const(lo, frac)}, " \
               f"{self.const(hi, frac)})"
        return Fx(code, frac, lo, hi, state.err + self.steps * (self.align_error(x, frac)
                                                                + bounds_err))

    def set_state(self, o, state: Fx) -> None:
        cast = "" if OUTPUT_OPS[o.kind].integrates else "(int32_t)"
        self.code.append(f"s->out_{c_identifier(o.name)} = {cast}{state.code};")
        self.state_errors[o.name] = state.err

    def read_state(self, o) -> Fx:
        """The state rounded back to 31 bits (integrators keep STATE_GUARD more)."""
        frac = self.state_frac(o)
        guard = frac - frac_for(*self.state_range(o))
        base = frac - guard
        state = f"s->out_{c_identifier(o.name)}"
        read = f"{self.p}shr({state}, {guard})" if guard else state
        return Fx(read, base, o.lo, o.hi, self.state_errors[o.name] + drop_error(frac, base))

    def reciprocal(self, o, state: Fx) -> Fx:
        """u = 1/v, rounded to nearest, at the precision of the output's range."""
        uf = frac_for(o.lo, o.hi)
        one = 1 << (uf + state.frac)
        v_min, v_err = 1.0 / o.hi, state.err
        u_err = v_err / (v_min * (v_min - v_err)) if v_err < v_min else math.inf
        result = Fx(f"u_{c_identifier(o.name)}", uf, o.lo, o.hi,
                    u_err + 0.5 * 2.0 ** -uf + max(const_error(o.lo, uf),
                                                   const_error(o.hi, uf)))
        v = f"reciprocal_{c_identifier(o.name)}"    # v = 1/u, 31 bits
        self.code.append(f"const int64_t {v} = {state.code};")
        self.code.append(f"const int64_t {result.code} = {self.p}sat(({one} + {v} / 2) / "
                         f"{v}, {self.const(o.lo, uf)}, {self.const(o.hi, uf)});")
        return result

    def emit_output(self, k: int, o, result: Fx) -> None:
        self.code.append(f"out[{k}] = ({self.io}){self.p}sat("
                         f"{self.align(result, self.io_frac)}, {-self.io_max}, {self.io_max});")
        self.symbols[o.name] = result
        self.output_errors[o.name] = self.align_error(result, self.io_frac)

    def state_range(self, o) -> tuple[float, float]:
        rule = OUTPUT_OPS[o.kind]
        if rule.reciprocal and not o.lo > 0:
            raise _fail(f"the fixed-point chain needs 0 < lo for the 1/integrate output "
                        f"`{o.name}`")
        return rule.state_limits(o)

    def state_frac(self, o) -> int:
        """Fraction bits of output o's state: integrators keep STATE_GUARD more (int64)."""
        return frac_for(*self.state_range(o)) + (STATE_GUARD if OUTPUT_OPS[o.kind].integrates
                                                 else 0)
