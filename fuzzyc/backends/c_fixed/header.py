"""Fixed-point rule bases (q15, q31) for boards without an FPU: integer arithmetic only,
and with them the whole signal chain (`c_fixed_chain`).

Scaling (written into the header): an input x of variable [lo, hi] is the integer
xq = round((x - lo) / (hi - lo) * FULL) in [0, FULL] (FULL = 32767 for q15 in int16_t, 2**31 - 1
for q31 in int32_t); an output is read back the same way, y = lo + yq / FULL * (hi - lo).
Inputs outside [0, FULL] are saturated; so is every intermediate (memberships to [0, 1],
outputs to [0, FULL]).  Memberships are fractions with MF bits (15 for q15, 28 for q31, so
products and the centre-of-area sums fit in int64), rounded to nearest (a truncation would
bias them all low, and an integrator downstream sums a bias).  Inside, the rule base works
at guard precision (`NAME_rulebase_wide`): the input pieces (break points, anchors, widths)
at 2^-GI of an input LSB and the outputs at 2^-g of an output LSB, as many bits as int64
allows (up to 16; q31 gets 1-5); `NAME_rulebase` on the I/O integers rounds once at the end,
and the chain calls the wide one, so it does not round to the I/O LSB between its steps.

Emitted for the case the fixed-point arithmetic is exact enough and simple: inputs that are
partitions with at most two positive terms (`FixedTables`), AND rules in which an input may be
`*` (any: membership exactly 1 << MF, a third slot of that input), and the defuzzifiers
center of area and weighted average (a convex combination of the output peaks) and weighted
sum (sum_j alpha_j z_j, not normalised, saturated to the output's range; its peaks carry G
guard bits below the output LSB).  Others raise a diagnostic.  The C output is saturated to
the output's range, so it is held against the engine's value clipped to that range (the two
differ only where the engine leaves the range, which a weighted sum can).

Vanishing activations: the engine drops an activation below `fuzzyc.semantics.model.ACTIVATION_FLOOR`
(1e-12).  Here an activation is an integer of 2^-MF (a product of memberships or a weighted
activation rounded to nearest), so the smallest that fires is one LSB, 2^-15 = 3.1e-5 (q15) or
2^-28 = 3.7e-9 (q31), and below half an LSB an activation is already 0: everything the engine
drops is 0 here as well (checked at import).  Between the floor and half an LSB the engine
still fires a rule that the header does not; `derived_error_bound` holds only where every
sample fires a concluding rule far above that (at least S_min), and says "not derived"
otherwise.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ...engine.strength_grid import place_values
from ...language.limits import MAX_C_SLOT_COMBINATIONS, MAX_C_TABLE_CELLS
from ...engine.membership import LocalPartition, memberships
from ...errors import Diagnostic, FuzzycError
from ...semantics.model import (ACTIVATION_FLOOR, Aggregation, Connective, Defuzzifier, Hedge, Model,
                     RuleBase, TermKind, TNorm)
from ...semantics.operators import AGGREGATIONS, DEFUZZIFIERS, T_NORMS, emitted_in_fixed, names
from ...escape import c_comment, c_identifier
from ..rule_blocks import emitted_blocks
from ...semantics.shapes import SHAPES
from ..c.header import check_c_model_names, check_supported
from ..c.cells import active_codes, cell_row_c, cell_table, cell_table_c
from .chain import FixedChain, Fx, frac_for
from ..c.guard import checked_header
from .helpers import defines, helper_lines

FORMATS = {
    # name: (io type, full scale, membership fraction bits)
    "q15": ("int16_t", (1 << 15) - 1, 15),
    "q31": ("int32_t", (1 << 31) - 1, 28),
}
# the engine's floor lies below half an activation LSB of every format: what it drops is 0 here
assert all(ACTIVATION_FLOOR < 2.0 ** -(mf + 1) for _, _, mf in FORMATS.values())
# Stated worst-case |C - engine| as a fraction of each output's range, for inputs on the
# fixed-point grid (the engine evaluated at the dequantized input).  Checked by
# tests/test_c_fixed.py on >= 100,000 random inputs and every edge of every shipped rule base.
ERROR_BOUND = {"q15": 2.0 ** -11, "q31": 2.0 ** -24}
# The whole chain (step) against the engine's Controller fed the same dequantized inputs, as a
# fraction of each output's range over 10,000 steps of random walks (the four paper chains).
# Measured, with a margin of about 5 (q15: WEDM 2.1e-5, EDM 1.8e-5, corner 3.1e-5, milling
# 4.7e-5 -- mostly the q15 output's own half LSB; milling, the integrated du of 49 random
# weights, was 4.8e-4 before the rule base got guard bits and rounded memberships; q31: WEDM
# 1.1e-8, the others <= 6.9e-9 -- WEDM's t_off was 1.4e-5 while integrator states had 31 bits,
# see c_fixed_chain.STATE_GUARD) -- not derived: an integrator sums the per-step errors, so
# the bound grows with the run length.
CHAIN_ERROR_BOUND = {"q15": 2.0 ** -12, "q31": 2.0 ** -24}
# The run length the header states the derived chain bound for (chain_error_bound).
CHAIN_STEPS = 10_000
# assumption: break points of one input closer than 2^-40 of its range are one break point.
# A partition written by hand or imported (computed as peak +- step, say) can put a shared
# break point of two neighbouring terms 1 ulp apart (the builder's `uniform` did, -1/3 as
# -0.33333333333333343, ...37 and ...31, until its knots were shared), which leaves slivers
# where three terms are positive; 2^-40 of the range is 2^-9 of a q31 LSB, far below any grid
# the C uses, and the move is carried into the derived bound.
SNAP = 2.0 ** -40
# assumption: the most guard bits of the input pieces (break points, anchors, widths at
# 2^-GI of an input LSB): 16 make their rounding 2^-17 LSB, so a q15 membership is off by
# little more than its own rounding 2^-16 (at GI = 0 the anchor's 0.5 LSB over a width of a
# few thousand LSB was several times that); q31 gets what int64 allows (3-5 on the paper
# rule bases).
MAX_INPUT_GUARD = 16
# assumption: the most guard bits of an output below its LSB (peaks and the wide result):
# 16 make the peaks' rounding 2^-17 LSB; more buys nothing against the final rounding of
# 0.5 LSB.  q31 gets what int64 allows (1-2 on the paper rule bases).
MAX_GUARD = 16
# assumption: the derived error bound sums over at most this many cells (cell codes, tuples of
# terms, combinations of segments: 32 MB of float64); past it the header says "not derived".
# 10 inputs of 3 terms take 59,049 codes; 9 inputs of 4 terms with `*` on each 1,953,125.
MAX_DERIVED_CELLS = 1 << 22


# The operators these headers emit: those with a fixed-point text in the operator registry
# (no s-norm and no hedge has one: the rules must be plain AND rules).
FIXED_TNORMS = emitted_in_fixed(T_NORMS)
FIXED_DEFUZZIFIERS = emitted_in_fixed(DEFUZZIFIERS)
# each fixed t-norm names a helper of fixed_helpers.c
assert all(defines(T_NORMS[t].fixed) for t in FIXED_TNORMS)


FLOAT_HINT = ("; use the float or double header (`--numeric float`, the default, or `double`) "
              "or the lookup table (`--target lut`), which take what fixed point does not")


def _fail(message: str) -> FuzzycError:
    """What the q15/q31 back end cannot emit, and what can."""
    return FuzzycError([Diagnostic(None, message + FLOAT_HINT)])


def _snapped(var):
    """(var with its break points closer than SNAP of the range merged, the largest move as a
    fraction of the range)."""
    p = np.array(var.params, dtype=float)
    finite = np.isfinite(p)
    values = np.unique(p[finite])
    if len(values) == 0:
        return var, 0.0
    start = np.concatenate([[True], np.diff(values) > SNAP * (var.hi - var.lo)])
    first = values[start][np.cumsum(start) - 1]      # each value -> the first of its cluster
    p[finite] = first[np.searchsorted(values, p[finite])]
    moved = float(np.abs(p[finite] - np.asarray(var.params, dtype=float)[finite]).max())
    return dataclasses.replace(var, params=p), moved / (var.hi - var.lo)


class FixedTables:
    """What the fixed-point rule base is built from: per input its partition (`LocalPartition`
    of the snapped terms) and whether some rule leaves it open (`*`), and the cell table.

    Codes of input i in the cell table (`c_cells`): 0..T_i-1 its terms, T_i the wildcard
    (membership 1, only where a rule has `*` there: a third slot).  A slot without a term
    reads term 0 at membership 0.  A rule lies in the cell of its antecedent codes, so per
    sample each rule is met once with its terms' memberships, in the combination of its
    terms' slots and the wildcard slots -- the min/product over the remaining inputs, as the
    engine's dense path (an absent clause is 1) -- and where it is met again through a slot
    without a term its activation is exactly 0 (min or product with 0)."""

    def __init__(self, rb: RuleBase, numeric: str):
        self.rb = rb
        if rb.n_rules == 0 or not rb.inputs:
            raise _fail(f"the {numeric} back end needs inputs and some rules")
        if rb.inference.and_ not in FIXED_TNORMS:
            raise _fail(f"the {numeric} back end emits and = "
                        + " | ".join(T_NORMS[t].word for t in FIXED_TNORMS)
                        + f", not {T_NORMS[rb.inference.and_].word}")
        if not np.all(rb.connective == Connective.AND) or np.any(rb.negated) or \
                np.any(rb.hedges != Hedge.NONE):
            raise _fail(f"the {numeric} back end needs plain AND rules (no `or`, `not` or "
                        f"hedges; `*` = any is fine)")
        self.partitions, self.moved = [], []
        for var in rb.inputs:
            other = sorted({SHAPES[TermKind(int(k))].name for k in var.kinds
                            if not SHAPES[TermKind(int(k))].c_fixed_input})
            if other:       # the shape records say which shapes the partitions take
                raise _fail(f"the {numeric} back end needs each input to be a partition of "
                            f"trapezoids where at most two terms are positive at a time; "
                            f"`{var.name}` has {', '.join(other)} terms")
            snapped, moved = _snapped(var)
            part = LocalPartition.build(snapped)
            if part is None:
                raise _fail(f"the {numeric} back end needs each input to be a partition of "
                            f"trapezoids where at most two terms are positive at a time; "
                            f"`{var.name}` is not")
            self.partitions.append(part)
            self.moved.append(moved)
        for var in rb.inputs + rb.outputs:
            if var.n_terms + 2 > 255:
                raise _fail(f"the {numeric} back end holds term ids in a byte: `{var.name}` "
                            f"has {var.n_terms} terms")
        self.wild = np.any(rb.antecedents < 0, axis=0)
        self.slots = np.where(self.wild, 3, 2)
        self.combos = int(np.prod(self.slots.astype(float)))    # slot combinations per sample
        if self.combos > MAX_C_SLOT_COMBINATIONS:
            raise _fail(f"the {numeric} back end visits every combination of the inputs' "
                        f"active terms (2 per input, 3 where a rule has `*`): {self.combos} "
                        f"per call, at most {MAX_C_SLOT_COMBINATIONS} "
                        f"(fuzzyc.language.limits.MAX_C_SLOT_COMBINATIONS)")
        radix = np.array([v.n_terms for v in rb.inputs]) + self.wild
        ids = np.where(rb.antecedents >= 0, rb.antecedents, radix - 1)
        self.cells = cell_table(ids, radix)
        if self.cells is None:
            cells = np.prod(radix.astype(float))
            raise _fail(f"the {numeric} back end's cell table cannot be kept: {cells:.0f} "
                        f"codes (the product over the inputs of terms, + 1 where a rule has "
                        f"`*`) " + ("pass 32 bits" if cells > 2.0 ** 32 else
                                    f"with {len(np.unique(ids @ place_values(radix)))} "
                                    f"occupied cells, more than {MAX_C_TABLE_CELLS} "
                                    f"(fuzzyc.language.limits.MAX_C_TABLE_CELLS)"))
        self.rule_codes = ids @ self.cells.place
        full, mf = FORMATS[numeric][1], FORMATS[numeric][2]
        # |x - anchor| <= |width| inside a segment (outer segments are constant), so
        # (x - anchor) * ONE stays below 2^62 with the widest piece
        widest = max([float(np.abs(p.table[:, 2:4][np.isfinite(p.table[:, 2:4])]).max(
            initial=0.0)) / (v.hi - v.lo) for p, v in zip(self.partitions, rb.inputs)])
        self.input_guard = max([g for g in range(MAX_INPUT_GUARD + 1)
                                if (widest * full + 2) * 2.0 ** (g + mf) < 2.0 ** 62],
                               default=-1)
        if self.input_guard < 0:
            raise _fail(f"the {numeric} back end cannot hold a membership's numerator in "
                        f"int64 (a piece wider than the input's range)")
        self.candidates = self.combos * self.cells.depth     # rules met per sample, at most

    def summed_over_sets(self, values: np.ndarray, sets: list[np.ndarray]) -> np.ndarray | None:
        """sets[i] (S_i, T_i), booleans: sets of the terms of input i.  Per combination of
        sets (one per input, first input slowest), the sum of `values` (one per rule) over
        the rules whose every term lies in its input's set (`*` lies in every set); None
        where that or the cell codes pass MAX_DERIVED_CELLS.  Each cell's sum contracted
        with one input's membership matrix at a time (`tensordot`)."""
        radix = self.cells.radix
        widest = np.maximum(radix, [len(s) for s in sets])
        if np.prod(widest.astype(float)) > MAX_DERIVED_CELLS:
            return None
        total = np.bincount(self.rule_codes, weights=values,
                            minlength=int(np.prod(radix))).reshape(radix)
        for member, wild in zip(sets, self.wild):
            if wild:
                member = np.hstack([member, np.ones((len(member), 1), bool)])
            total = np.tensordot(total, member.astype(float), axes=([0], [1]))
        return total

    def tuple_sets(self) -> list[np.ndarray]:
        """Per input, each term alone: summed_over_sets gives every tuple of real terms."""
        return [np.eye(v.n_terms, dtype=bool) for v in self.rb.inputs]

    def segment_sets(self) -> list[np.ndarray]:
        """Per input, the sets of terms positive together on a segment between its break
        points, those inside another left out (summed_over_sets adds values >= 0, so the
        worst segment of the input grid is among these)."""
        out = []
        for part in self.partitions:
            sets = np.zeros((len(part.table), part.n_terms), bool)
            for k, ids in enumerate(part.table[:, 6:8].astype(int)):
                sets[k, ids[ids < part.n_terms]] = True
            sets = np.unique(sets, axis=0)
            inside = [any(np.all(a <= b) and np.any(a != b) for b in sets) for a in sets]
            out.append(sets[~np.array(inside)])
        return out


def _least_top(var, part) -> float:
    """min over x in [lo, hi] of the largest membership of var's terms: exact, as max of the
    (at most two) linear pieces is smallest at a break point, a crossing or a range end."""
    points = [var.lo, var.hi] + [b for b in part.breaks if var.lo < b < var.hi]
    for r in part.table:
        (a0, a1), (w0, w1), (o0, o1) = r[0:2], r[2:4], r[4:6]
        s0 = 1.0 / w0 if np.isfinite(w0) else 0.0
        s1 = 1.0 / w1 if np.isfinite(w1) else 0.0
        if s0 != s1:        # (x - a0) s0 + o0 = (x - a1) s1 + o1
            x = (o1 - o0 + a0 * s0 - a1 * s1) / (s0 - s1)
            if var.lo < x < var.hi:
                points.append(x)
    return float(memberships(var, np.array(points)).max(axis=1).min())


def alpha_bounds(tables: FixedTables, o: int, numeric: str) -> tuple[int, int]:
    """(A, the largest sum_j alpha_j of output o; the largest single alpha_j), at 2^-MF:
    A = n max(w) ONE (n = min(terms, C) levels with max aggregation, C rules met per sample
    with sum); one alpha_j is at most max(w) ONE with max aggregation, A with sum."""
    rb, var = tables.rb, tables.rb.outputs[o]
    one = 1 << FORMATS[numeric][2]
    summed = rb.inference.defuzzifier in (Defuzzifier.WEIGHTED_AVERAGE,
                                          Defuzzifier.WEIGHTED_SUM) or \
        rb.inference.aggregation == Aggregation.SUM
    n = tables.candidates if summed else min(var.n_terms, tables.candidates)
    w = max([one] + [abs(round(w * one)) for w in rb.weights])
    return n * w, (n * w if summed else w)


def output_guard(tables: FixedTables, o: int, numeric: str) -> int:
    """Guard bits g of output o below its LSB (its peaks, and the rule base's wide output, at
    2^-g of an output LSB): the most, up to MAX_GUARD, with which the numerator fits in int64
    -- |sum_j alpha_j| <= A = n max(w) ONE (n = min(terms, C) levels with max aggregation, C
    rules met per sample with sum), times the largest |peak| (relative to lo for the ratios,
    to the value 0 for the weighted sum), plus the offset of 0 and the rounding -- or -1."""
    rb, var = tables.rb, tables.rb.outputs[o]
    full, mf = FORMATS[numeric][1], FORMATS[numeric][2]
    one = 1 << mf
    a, _ = alpha_bounds(tables, o, numeric)
    weighted_sum = rb.inference.defuzzifier == Defuzzifier.WEIGHTED_SUM
    origin = 0.0 if weighted_sum else var.lo
    for g in range(MAX_GUARD, -1, -1):
        scale = full * 2.0 ** g / (var.hi - var.lo)
        z = max(abs(round((v - origin) * scale)) for v in var.peaks()) + 1
        zero = abs(round(-var.lo * scale)) * one if weighted_sum else 0
        if a * z + zero + a < 2 ** 63:
            return g
    return -1


def derived_error_bound(model: Model, numeric: str, input_error=None,
                        wide: bool = False, block: int | None = None) -> np.ndarray | None:
    """Per rule-base output, a worst-case |C - engine| as a fraction of its range, derived from
    the arithmetic (the engine at the dequantized input, clipped to the output's range), or
    None where the argument below does not apply (weights with a ratio defuzzifier, weights
    <= 0, an input point where no rule concludes the output, S_min <= D below, or sums over
    more than MAX_DERIVED_CELLS cells).  With `input_error` (per
    input, in LSBs of the I/O scale) the C's inputs are that far from the engine's, which moves
    each membership by at most that over the C's narrowest piece; `wide` bounds
    NAME_rulebase_wide, whose result keeps the guard bits (no final rounding to the LSB);
    `block` names the rule block of a model of several (None: the model's one rule base):

    - a membership of a piece of scaled width w (input LSBs; anchor, width and break point
      rounded to r = 0.5 2^-GI LSB, GI the input guard bits; each also moved by m LSB where
      break points were merged, see SNAP) is off by at most
      eps = (3 r + 2 m) / (w - r - m) + 2^-MF (the division rounds to nearest, 0.5 2^-MF,
      and so does each product of the product t-norm, another 0.5 2^-MF);
    - min and max are exact, a wildcard is exactly 1 and a slot without a term exactly 0, so
      an activation is off by
      eps_act = eps (min) or I eps (1 + eps)^(I-1) (product of I);
    - S_min = T-norm over inputs of the least top membership: every term tuple has a rule
      (its own or one with `*` there) concluding the output, so that rule fires at least this
      much, in the engine, and in C at least S_min - eps_act;
    - ratio defuzzifiers (unit weights): the levels alpha_j differ by D = eps_act * min(terms,
      C) in sum for max aggregation, eps_act * C for sum, C the rules met per sample (slot
      combinations x rules per cell); center of area y = sum alpha_j z_j / S moves by
      sum |delta_j| |z_j - y'| / S' <= D Z / (S_min - D), Z the spread of the peaks; peaks
      rounded (0.5 2^-g LSB), the division rounded to nearest (0.5 2^-g LSB) and the result
      to the LSB (0.5, not when wide): + (2^-g + 0.5) / FULL;
    - weighted sum y = sum_r act_r w_r z_r (weights w_r > 0): act_r w_r is off by
      eps_act w_r (+ 2^-MF for the rounded weight and the rounded product), so y by
      sum_r that * |z_r|, the sum over the rules that can fire in one cell of the input grid
      (one segment per input), worst cell; the peaks rounded to 0.5 2^-g LSB (g the output's
      guard bits) add (sum_r w_r + 2) 0.5 2^-g / FULL (the 2 for the offset of the value 0
      and the rounding of the wide result), the final rounding 0.5 / FULL; the saturation to
      the range only brings C nearer the clipped engine.
    """
    rb = model.rulebase if block is None else emitted_blocks(model)[block]
    if block is None and rb.output_choices:     # the header splits it (rule_blocks)
        return None
    try:
        tables = FixedTables(rb, numeric)
    except FuzzycError:
        return None
    method = rb.inference.defuzzifier
    weighted_sum = method == Defuzzifier.WEIGHTED_SUM
    unit = bool(np.all(rb.weights == 1.0))
    if not unit and not (weighted_sum and np.all(rb.weights > 0)):
        return None
    full, mf = FORMATS[numeric][1], FORMATS[numeric][2]
    n_in = len(rb.inputs)
    eps = 0.0
    tops = []
    shift = np.zeros(n_in) if input_error is None else np.asarray(input_error, dtype=float)
    for var, part, moved, e in zip(rb.inputs, tables.partitions, tables.moved, shift):
        widths = np.abs(part.table[:, 2:4])
        widths = widths[np.isfinite(widths)] * full / (var.hi - var.lo)
        m = moved * full
        r = 0.5 * 2.0 ** -tables.input_guard
        if len(widths):
            eps = max(eps, (3 * r + 2 * m + e) / (widths.min() - r - m))
        tops.append(_least_top(var, part))
    eps += 2.0 ** -mf
    product = rb.inference.and_ == TNorm.PRODUCT
    eps_act = n_in * eps * (1 + eps) ** (n_in - 1) if product else eps
    s_min = float(np.prod(tops)) if product else min(tops)
    summed = method == Defuzzifier.WEIGHTED_AVERAGE or \
        rb.inference.aggregation == Aggregation.SUM
    tuples = tables.tuple_sets()
    segments = tables.segment_sets() if weighted_sum else None
    bounds = []
    for o, var in enumerate(rb.outputs):
        J = rb.consequents[:, o]
        concludes = J >= 0
        covered = tables.summed_over_sets(concludes.astype(float), tuples)
        if covered is None or not np.all(covered > 0):     # per tuple of real terms
            return None
        span = var.hi - var.lo
        if weighted_sum:
            g = output_guard(tables, o, numeric)
            w = rb.weights.astype(float) * concludes
            rounding = 0.0 if unit else 2.0 ** -mf
            if g < 0 or (s_min - eps_act) * w[concludes].min() - rounding <= 0:
                return None
            z = np.where(concludes, var.peaks()[J], 0.0)
            err = (eps_act * w + rounding * (w > 0)) * np.abs(z) / span
            # per cell of the input grid (a segment per input), the rules that can fire
            worst_err = tables.summed_over_sets(err, segments)
            total_w = tables.summed_over_sets(w, segments)
            if worst_err is None or total_w is None:
                return None
            bounds.append(worst_err.max() + (total_w.max() + 2) * 0.5 * 2.0 ** -g / full
                          + (0 if wide else 0.5 / full))
            continue
        d = eps_act * (tables.candidates if summed else min(var.n_terms, tables.candidates))
        if s_min <= d:
            return None
        peaks = var.peaks()
        spread = (max(peaks) - min(peaks)) / span
        # peaks and division at 2^-g of an LSB; then the result to the LSB, unless wide
        g = output_guard(tables, o, numeric)
        bounds.append(d * spread / (s_min - d) + (2.0 ** -g + (0 if wide else 0.5)) / full)
    return np.array(bounds)


def chain_error_bound(model: Model, numeric: str, steps: int = CHAIN_STEPS) -> dict[str, float]:
    """Per chain output, a worst-case |C step - the engine's Controller| as a fraction of its
    range after `steps` steps, derived from the rounding of every operation (see
    c_fixed_chain's docstring), for inputs within their declared ranges; inf where the
    argument does not apply (a rule-base input outside the rule base's range, or
    derived_error_bound not applying).  The engine's Controller is taken as exact."""
    return FixedPointWriter(model, numeric).chain_errors_after(steps)


def io_frac(lo: float, hi: float, numeric: str) -> int:
    """Fraction bits of a chain input or output of range [lo, hi] in the I/O arrays."""
    return frac_for(lo, hi, 15 if numeric == "q15" else 31)


def _ints(values) -> str:
    return "{" + ", ".join(f"{int(v)}" for v in values) + "}"


class FixedPointWriter:
    def __init__(self, model: Model, numeric: str, block: int | None = None):
        """The writer of the whole header (block None), or of rule block `block`'s part of
        it: its tables, helpers, NAME_bK_rulebase_wide and NAME_bK_rulebase, named with the
        prefix NAME_q15_bK_; the header's chain calls each block's in order."""
        self.model, self.numeric, self.block = model, numeric, block
        emitted = emitted_blocks(model)
        self.block_writers = [] if block is not None or len(emitted) == 1 else \
            [FixedPointWriter(model, numeric, k) for k in range(len(emitted))]
        self.rb = emitted[block or 0]
        self.io, self.full, self.mf = FORMATS[numeric]
        rb = self.rb
        check_supported(rb)   # what the float back end cannot emit, fixed point cannot either
        method = rb.inference.defuzzifier
        if method not in FIXED_DEFUZZIFIERS:
            raise _fail(f"the {numeric} back end emits {names(DEFUZZIFIERS, FIXED_DEFUZZIFIERS)}"
                        f"; `{DEFUZZIFIERS[method].word}` is not supported")
        for var in rb.outputs:
            if np.any(var.kinds == TermKind.LINEAR) or not np.all(np.isfinite(var.peaks())):
                raise _fail(f"the {numeric} back end needs a fixed value per output term; "
                            f"`{var.name}` has linear (Takagi-Sugeno) terms")
        self.tables = FixedTables(rb, numeric)
        self.guard = [output_guard(self.tables, o, numeric) for o in range(len(rb.outputs))]
        self.weighted_sum = method == Defuzzifier.WEIGHTED_SUM
        self.unit = bool(np.all(rb.weights == 1.0))
        # the levels alpha_j are sums of activations (else the aggregation's maximum)
        self.summed = method in (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM) or \
            rb.inference.aggregation == Aggregation.SUM
        if min(self.guard) < 0:
            raise _fail(f"the {numeric} back end cannot hold the defuzzifier's numerator in "
                        f"int64: {self.tables.candidates} rules x weight x peak x 2^{self.mf} "
                        f"exceeds 2^63")
        if block is None:
            check_c_model_names(model)
        self.name = c_identifier(model.name)
        part = "" if block is None else f"b{block}_"
        self.p = f"{self.name}_{numeric}_{part}"
        self.P = self.p.upper()

    def derived_text(self) -> str:
        bound = derived_error_bound(self.model, self.numeric, block=self.block)
        if bound is None:
            return ("not derived (weights with a ratio defuzzifier, weights <= 0, an input "
                    "point where no rule concludes an output, a rounding that can outweigh "
                    "the least activation, or more than MAX_DERIVED_CELLS cells to sum over)")
        return "; ".join(f"{c_comment(v.name)} {e:.3g}"
                         for v, e in zip(self.rb.outputs, bound)) + " of the output's range"

    def chain_text(self) -> str:
        after = [self.chain_errors_after(n) for n in (1, CHAIN_STEPS)]
        return "; ".join(f"{c_comment(o.name)} {after[0][o.name]:.3g}, {after[1][o.name]:.3g}"
                         for o in self.model.outputs)

    def chain_errors_after(self, steps: int) -> dict[str, float]:
        self.chain(steps)
        return {o.name: self.chain_errors[o.name] / (o.hi - o.lo) for o in self.model.outputs}

    def q(self, value: float, var, guard: int = 0) -> int:
        """A position in var's range as an integer of the I/O scale, at 2^-guard of its LSB
        (may lie outside the range)."""
        return int(round((value - var.lo) / (var.hi - var.lo) * self.full * 2.0 ** guard))

    def input_tables(self, i: int, part, var) -> list[str]:
        P, gi = self.P, self.tables.input_guard
        breaks = [self.q(b, var, gi) for b in part.breaks]
        rows = []
        for r in part.table:
            row = []
            for s in range(2):
                anchor, width, offset = r[s], r[2 + s], r[4 + s]
                finite = np.isfinite(width)
                row += [self.q(anchor, var, gi) if finite else 0,
                        int(round(width / (var.hi - var.lo) * self.full * 2.0 ** gi))
                        if finite else 0,
                        int(offset) << self.mf]
            rows.append(row)
        ids = active_codes(part)
        nb = len(breaks)
        return [f"/* {c_comment(var.name)}: break points, and per segment (anchor, width, "
                f"offset) x 2 in input units at 2^-{gi} of an LSB (width 0 = constant). */",
                f"static const int64_t {P}BREAKS_{i}[{nb}] = {_ints(breaks)};",
                f"static const int64_t {P}PIECES_{i}[{nb + 1}][6] = "
                "{" + ", ".join(_ints(r) for r in rows) + "};",
                f"static const unsigned char {P}ACTIVE_{i}[{nb + 1}][2] = "
                "{" + ", ".join(_ints(r) for r in ids) + "};"]

    def header(self) -> str:
        guard = f"FUZZYC_{self.name.upper()}_{self.numeric.upper()}_H"
        out = [*self.comment(), f"#ifndef {guard}", f"#define {guard}", "",
               "#include <stdint.h>", ""]
        if self.block_writers:       # the chain's helpers, then each block under its prefix
            out += self.format_macros() + [""] + helper_lines(self.p, self.P)
            for k, w in enumerate(self.block_writers):
                out += ["", f"/* Rule block {k}: {c_comment(w.rb.name)}. */", *w.rule_base()]
        else:
            out += self.rule_base()
        out += self.chain()
        out += ["", f"#endif /* {guard} */", ""]
        return "\n".join(out)

    def rule_base(self) -> list[str]:
        """This rule base's macros, tables, helpers, NAME_rulebase_wide and NAME_rulebase."""
        which = self.distinct_inputs()
        out = self.macros()
        out += [line for i, k in enumerate(which) if k == i
                for line in self.input_tables(i, self.tables.partitions[i], self.rb.inputs[i])]
        out += self.rule_tables() + self.peak_tables()
        out += helper_lines(self.p, self.P)
        return out + self.rulebase_wide(which) + self.rulebase_io()

    def comment(self) -> list[str]:
        """The header's opening comment: scaling, the stated and derived error bounds."""
        m = self.model
        variables = list({v.name: v for rb in m.blocks for v in (*rb.inputs, *rb.outputs)}
                         .values())
        return ["/*",
                f" * {self.name}_{self.numeric}.h - generated by fuzzyc from "
                f"{c_comment(m.source_path or '(built in memory)')}",
                f" * source hash (sha256, first 16 hex): {m.source_hash}",
                f" * numeric: {self.numeric} (integer arithmetic only, saturating)",
                *self.blocks_comment(),
                " * Scaling: xq = round((x - lo) / (hi - lo) * FULL), FULL = "
                f"{self.full}, y = lo + yq / FULL * (hi - lo), with",
                " *   " + "; ".join(f"{c_comment(v.name)} [{v.lo:g}, {v.hi:g}]"
                                    for v in variables),
                f" * Memberships are fractions of 2^{self.mf}.  Worst-case error against the "
                f"engine at the dequantized input: {ERROR_BOUND[self.numeric]:.3g} of each "
                "output's range",
                " * (checked on >= 100,000 random inputs and every edge; the output saturates "
                "to its range).",
                " * A `*` (any) in a rule counts as membership ONE exactly (min/product over "
                "the other inputs).",
                f" * Activations are integers of 2^-{self.mf}: below half an LSB one is 0 (the "
                f"engine's floor, {ACTIVATION_FLOOR:g}, lies below that).",
                *self.derived_comment(), *self.chain_comment(), " */"]

    def blocks_comment(self) -> list[str]:
        """The opening comment's inference line, one per rule block where there are several."""
        if not self.block_writers:
            return [f" * inference: {self.rb.inference.describe()}"]
        return [f" * {len(self.block_writers)} rule blocks, evaluated in this order:"] + [
            f" *   {k}: {c_comment(w.rb.name)} ({w.p}rulebase), inference: "
            f"{w.rb.inference.describe()}" for k, w in enumerate(self.block_writers)]

    def derived_comment(self) -> list[str]:
        """The opening comment's derived bound of the bare rule base, or of each block."""
        lines = []
        for k, w in enumerate(self.block_writers or [self]):
            which = f" of block {k}" if self.block_writers else ""
            lines += [f" * Derived worst case{which} (membership rounding + exact min/max + "
                      "rounded " + ("weighted sum" if w.weighted_sum else "COA division")
                      + ", see",
                      " * fuzzyc.backends.c_fixed.header.derived_error_bound): "
                      + w.derived_text() + "."]
        return lines

    def chain_comment(self) -> list[str]:
        """The opening comment's lines on the whole chain: measured and derived bounds."""
        return [" * The whole chain (NAME_step) is in fixed point too (it calls "
                "NAME_rulebase_wide,",
                " * which keeps the guard bits below the I/O LSB): every value at the binary",
                " * point its range allows in 31 bits (memories included; integrator states "
                "16 bits finer, in int64),",
                " * in[]/out[] at the *_FRAC points below, inputs saturated to their ranges;",
                " * against the engine's Controller within "
                f"{CHAIN_ERROR_BOUND[self.numeric]:.3g} of each output's range over",
                " * 10,000 steps (measured on the shipped chains; integrators sum per-step "
                "errors).",
                " * Derived worst case of the chain (interval reasoning over every rounding, see",
                " * fuzzyc.backends.c_fixed.header.chain_error_bound; inputs within their "
                "ranges), as a fraction of the range,",
                " * after 1 and after 10,000 steps: " + self.chain_text() + ".",
                " * static inline: self-contained, no heap, no recursion, constant loop bounds."]

    def format_macros(self) -> list[str]:
        """FULL, ONE and MF: the helpers' format (see fixed_helpers.c)."""
        P = self.P
        return [f"#define {P}FULL {self.full}", f"#define {P}ONE {1 << self.mf}",
                f"#define {P}MF {self.mf}"]

    def macros(self) -> list[str]:
        """The format and the rule base's sizes."""
        P = self.P
        return [*self.format_macros(), f"#define {P}N_RB_INPUTS {len(self.rb.inputs)}",
                f"#define {P}N_RB_OUTPUTS {len(self.rb.outputs)}", ""]

    def distinct_inputs(self) -> list[int]:
        """Per input, the first input with the same partition and range (whose tables it
        reads)."""
        seen: dict[bytes, int] = {}
        which = []
        for i, (part, var) in enumerate(zip(self.tables.partitions, self.rb.inputs)):
            key = part.breaks.tobytes() + part.table.tobytes() + np.array(
                [var.lo, var.hi]).tobytes()
            which.append(seen.setdefault(key, i))
        return which

    def rule_tables(self) -> list[str]:
        """The cell table, each rule's consequents (a last row of `none`) and its weights,
        where any is not 1."""
        rb, P = self.rb, self.P
        cons = np.vstack([np.where(rb.consequents >= 0, rb.consequents,
                                   [v.n_terms for v in rb.outputs]),
                          [v.n_terms for v in rb.outputs]])
        weights = np.array([round(w * (1 << self.mf)) for w in rb.weights] + [0])
        out = [f"#define {P}N_RULES {rb.n_rules}"]
        if self.per_cell:     # indexed by the cell: an empty cell reads the last row
            rows = self.tables.cells.rows[:, 0]
            cons, weights = cons[rows], weights[rows]
            out.append("/* Per cell (tuple of term ids) and output: its rule's consequent "
                       "term (n_terms: no rule or the rule says nothing). */")
        else:
            out += cell_table_c(self.tables.cells, P, self.p, rb.n_rules)
        out.append(f"static const unsigned char {P}{self.prefix}CONSEQUENTS[{len(cons)}]"
                   f"[{len(rb.outputs)}] = " + "{" + ", ".join(_ints(r) for r in cons) + "};")
        if not self.unit:
            out.append(f"static const int64_t {P}{self.prefix}WEIGHTS[{len(weights)}] = "
                       + _ints(weights) + ";")
        return out

    @property
    def per_cell(self) -> bool:
        """A direct cell table of one rule per cell: its consequents and weight are tabled
        per cell, one load fewer per slot combination (as the float header's per_cell)."""
        return self.tables.cells.one_rule_per_cell

    @property
    def prefix(self) -> str:
        return "CELL_" if self.per_cell else ""

    def peak_tables(self) -> list[str]:
        """Each output's peaks at its guard bits below the LSB."""
        out = []
        for o, var in enumerate(self.rb.outputs):
            g = self.guard[o]
            if self.weighted_sum:   # value / range * FULL * 2^G: relative to 0, not to lo
                scale = self.full * 2.0 ** g / (var.hi - var.lo)
                out.append(f"/* {c_comment(var.name)}: peaks at 2^-{g} of an output "
                           "LSB, relative to the value 0 (a weighted sum is not normalised). */")
                peaks = [round(v * scale) for v in var.peaks()]
            else:
                out.append(f"/* {c_comment(var.name)}: peaks at 2^-{g} of an output LSB. */")
                peaks = [self.q(v, var, g) for v in var.peaks()]
            out.append(f"static const int64_t {self.P}PEAKS_{o}[{var.n_terms}] = "
                       + _ints(peaks) + ";")
        return out

    def chain(self, steps: int = CHAIN_STEPS) -> list[str]:
        """State, init and step of the whole signal chain on integers (see c_fixed_chain);
        the outputs' derived error bounds after `steps` steps are left in self.chain_errors
        (absolute, inf where not derived)."""
        m, p, P, io = self.model, self.p, self.P, self.io
        chain = FixedChain(m, p)
        chain.io = io
        chain.steps = steps
        self.chain_errors = chain.output_errors
        body = []
        for k, sig in enumerate(m.signals):
            frac = io_frac(sig.lo, sig.hi, self.numeric)
            v = Fx(f"{p}sat(in[{k}], {chain.const(sig.lo, frac)}, {chain.const(sig.hi, frac)})",
                   frac, sig.lo, sig.hi)
            body.append(chain.bind(sig.name, v)[0])
        for step in m.steps:
            body += chain.step(step)
        for k, w in enumerate(self.block_writers or [self]):
            chain.rulebase_error = lambda errors, b=w.block: derived_error_bound(
                m, self.numeric, errors, wide=True, block=b)
            body += chain.rulebase_io(w.rb, self.full, w.p, w.tables.input_guard, w.guard,
                                      str(k) if self.block_writers else "")
        io_max = self.full
        for k, o in enumerate(m.outputs):
            body += chain.output(k, o, io_frac(o.lo, o.hi, self.numeric), io_max)
        # A file may leave signals unused (or have no output at all): no warnings.
        body += [f"(void){chain.symbols[name].code};"
                 for name in [*(g.name for g in m.signals), *(g.name for g in m.steps),
                              *(v.name for rb in m.blocks for v in rb.outputs)]]
        if not m.outputs:
            body += ["(void)s;", "(void)out;"]
        fields, init = chain.state_fields(), chain.init_lines()
        scales = [f"#define {P}IN_{c_identifier(sig.name).upper()}_FRAC "
                  f"{io_frac(sig.lo, sig.hi, self.numeric)}" for sig in m.signals]
        scales += [f"#define {P}OUT_{c_identifier(o.name).upper()}_FRAC "
                   f"{io_frac(o.lo, o.hi, self.numeric)}" for o in m.outputs]
        return ["", "/* The chain's I/O: in[k] = round(x * 2^FRAC), saturated to the input's "
                "range; out[k] likewise. */", *scales,
                f"#define {P}N_SIGNALS {max(1, len(m.signals))}",
                f"#define {P}N_OUTPUTS {max(1, len(m.outputs))}",
                "typedef struct {", *fields, f"}} {p}state;", "",
                f"static inline void {p}init({p}state *s) {{",
                *(init or ["    s->unused = 0;"]), "}", "",
                "/* One sample of the whole chain on integers: in[N_SIGNALS] -> out[N_OUTPUTS]. */",
                f"static inline void {p}step({p}state *s, const {io} in[{P}N_SIGNALS], "
                f"{io} out[{P}N_OUTPUTS]) {{",
                *("    " + line for line in body), "}"]

    def numerator(self, o: int, terms: list[str]) -> list[str]:
        """The C declaring `num` = sum_j alpha_j z_j of output o.  |num| <= A max|z_j| < 2^63
        (output_guard), but a value analysis bounds each alpha_j alone, up to sum_j
        max(alpha_j) |z_j|; where that exceeds int64 the sum is formed modulo 2^64 (unsigned:
        defined wrap-around, exact as the true sum fits) and read back within +-A max|z_j|."""
        var, g = self.rb.outputs[o], self.guard[o]
        a, one_alpha = alpha_bounds(self.tables, o, self.numeric)
        origin = 0.0 if self.weighted_sum else var.lo
        scale = self.full * 2.0 ** g / (var.hi - var.lo)
        z = [abs(round((v - origin) * scale)) for v in var.peaks()]
        if one_alpha * (sum(z) + len(z)) < 2 ** 62:      # each term alone bounds the sum
            return ["        int64_t num = " + " + ".join(terms) + ";"]
        wrapped = " + ".join(f"(uint64_t)({t})" for t in terms)
        return [f"        const uint64_t wrapped = {wrapped};",
                "        int64_t num = wrapped > (uint64_t)INT64_MAX ? -(int64_t)~wrapped - 1 "
                ": (int64_t)wrapped;",
                f"        num = {self.p}sat(num, INT64_C({-a * max(z)}), INT64_C({a * max(z)}));"]

    def rulebase_wide(self, which: list[int]) -> list[str]:
        """NAME_rulebase_wide: the inputs' memberships, the rules of each slot combination
        accumulated into alpha, each output defuzzified (the chain calls this one)."""
        rb, tables = self.rb, self.tables
        code = ["",
                f"/* The rule base at guard precision: inputs at 2^-{tables.input_guard} of an "
                "LSB (xg = xq * 2^GI), outputs at",
                "   2^-" + ", 2^-".join(str(g) for g in self.guard)
                + " of an LSB (the chain calls this one). */",
                f"static inline void {self.p}rulebase_wide(const int64_t xg[{len(rb.inputs)}], "
                f"int64_t yw[{len(rb.outputs)}]) {{",
                f"    int64_t m[{len(rb.inputs)}][{tables.slots.max()}];",
                f"    unsigned char id[{len(rb.inputs)}][{tables.slots.max()}];",
                "    int c;" if self.per_cell else "    int c, d;"]
        code += [f"    int64_t alpha{o}[{var.n_terms + 1}] = {{0}};"
                 for o, var in enumerate(rb.outputs)]
        code += self.memberships(which) + self.combinations()
        for o in range(len(rb.outputs)):
            code += self.wide_output(o)
        return code + ["}"]

    def memberships(self, which: list[int]) -> list[str]:
        """Each input's slots: its two active terms (the tables of input which[i]), and where
        a rule has `*` there a third, membership exactly 1."""
        p, P, tables = self.p, self.P, self.tables
        code = []
        for i, k in enumerate(which):
            nb = len(tables.partitions[k].breaks)
            code.append(f"    {p}active({p}sat(xg[{i}], 0, "
                        f"INT64_C({self.full << tables.input_guard})), {P}BREAKS_{k}, {nb}, "
                        f"{P}PIECES_{k}, {P}ACTIVE_{k}, m[{i}], id[{i}]);")
            if tables.wild[i]:
                code.append(f"    m[{i}][2] = {P}ONE; id[{i}][2] = {self.rb.inputs[i].n_terms};")
        return code

    def combinations(self) -> list[str]:
        """The loop over the slot combinations: the cell of their terms, its rules' (weighted)
        activations accumulated into alpha by the aggregation's fixed-point text."""
        rb, p, P, tables = self.rb, self.p, self.P, self.tables
        slots, cells, n_in = tables.slots, tables.cells, len(rb.inputs)
        # the slot of input i in combination c (mixed radix, input 0 slowest)
        stride = place_values(slots)
        digit = [(f"(c >> {int(stride[i]).bit_length() - 1}) & 1" if np.all(slots == 2) else
                  f"c / {int(stride[i])} % {int(slots[i])}") for i in range(n_in)]
        tnorm = T_NORMS[rb.inference.and_].fixed      # a helper of fixed_helpers.c
        act = f"m[0][{digit[0]}]"
        for i in range(1, n_in):
            act = f"{p}{tnorm}({act}, m[{i}][{digit[i]}])"
        # codes past 16 bits (sorted codes only) are formed in unsigned long
        wide = "" if cells.codes is None else f"({cells.cell_type})"
        cell = " + ".join(f"{wide}id[{i}][{digit[i]}] * {int(cells.place[i])}"
                          for i in range(n_in))
        accumulate = AGGREGATIONS[Aggregation.SUM if self.summed
                                  else rb.inference.aggregation].fixed
        if self.per_cell:
            weighted = "act" if self.unit else f"{p}shr(act * {P}CELL_WEIGHTS[cell], {self.mf})"
            return [f"    for (c = 0; c < {tables.combos}; ++c) {{",
                    f"        int cell = {cell};",
                    f"        int64_t act = {act};",
                    f"        int64_t a = {weighted};",
                    *("        " + accumulate.format(
                        acc=f"alpha{o}[{P}CELL_CONSEQUENTS[cell][{o}]]", x="a")
                      for o in range(len(rb.outputs))),
                    "    }"]
        weighted = "act" if self.unit else f"{p}shr(act * {P}WEIGHTS[rule], {self.mf})"
        return [f"    for (c = 0; c < {tables.combos}; ++c) {{",
                f"        int cell = {cell_row_c(cells, p, cell)};",
                f"        int64_t act = {act};",
                f"        for (d = 0; d < {cells.depth}; ++d) {{",
                f"            int rule = {P}CELLS[cell][d];",
                f"            int64_t a = {weighted};",
                *("            " + accumulate.format(acc=f"alpha{o}[{P}CONSEQUENTS[rule][{o}]]",
                                                     x="a") for o in range(len(rb.outputs))),
                "        }", "    }"]

    def wide_output(self, o: int) -> list[str]:
        """Output o from its levels alpha: the centre of area / weighted average (ratio,
        rounded to nearest) or the weighted sum, at its guard bits, saturated to its range."""
        var, g, p = self.rb.outputs[o], self.guard[o], self.p
        num = [f"alpha{o}[{j}] * {self.P}PEAKS_{o}[{j}]" for j in range(var.n_terms)]
        den = " + ".join(f"alpha{o}[{j}]" for j in range(var.n_terms))
        top = self.full << g
        default = max(0, min(top, self.q(var.default, var, g)))
        if self.weighted_sum:
            # yw = sum alpha_j z_j / span * FULL 2^g + the position of 0 (-lo / span *
            # FULL 2^g), all at 2^-MF more: rounded to nearest once
            zero = round(-var.lo / (var.hi - var.lo) * self.full * 2.0 ** g) << self.mf
            value = f"{p}shr(num + INT64_C({zero}), {self.mf})"
        else:
            value = "(num + den / 2) / den"
        return ["    {", *self.numerator(o, num), f"        int64_t den = {den};",
                f"        int64_t v = den > 0 ? {value} : INT64_C({default});",
                f"        yw[{o}] = {p}sat(v, 0, INT64_C({top}));", "    }"]

    def rulebase_io(self) -> list[str]:
        """NAME_rulebase on the I/O integers: the wide one, rounded once at the end."""
        p, io, n_in, n_out = self.p, self.io, len(self.rb.inputs), len(self.rb.outputs)
        code = ["",
                "/* The bare rule base on scaled integers: xq[N_RB_INPUTS] -> yq[N_RB_OUTPUTS]. */",
                f"static inline void {p}rulebase(const {io} xq[{n_in}], {io} yq[{n_out}]) {{",
                f"    int64_t xg[{n_in}], yw[{n_out}];",
                "    int i;",
                f"    for (i = 0; i < {n_in}; ++i) xg[i] = {p}sat(xq[i], 0, {self.P}FULL) * "
                f"{1 << self.tables.input_guard};",
                f"    {p}rulebase_wide(xg, yw);"]
        for o, g in enumerate(self.guard):
            code.append(f"    yq[{o}] = ({io})" + (f"{p}shr(yw[{o}], {g});" if g else f"yw[{o}];"))
        return code + ["}"]


def generate_fixed_header(model: Model, numeric: str) -> str:
    """The q15/q31 header for model's rule base."""
    return checked_header(FixedPointWriter(model, numeric).header(), model)
