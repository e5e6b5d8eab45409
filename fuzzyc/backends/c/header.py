"""The C99 back end: a model as one self-contained header of static inline functions.

`generate_header(model, numeric)` returns the text of NAME.h with
- NAME_state, NAME_init(), NAME_step(): the whole signal chain (preprocessing with its memory,
  rule base, incremental and saturated outputs), the C twin of `fuzzyc.engine.chain.Controller`;
- NAME_rulebase(): the bare rule base, the C twin of `fuzzyc.engine.inference.evaluate`;
- constant tables for terms and rules, sizes as #defines.
Two ways to find the activations, chosen like the engine chooses: a dense loop over all rules
(any rule base), or, for plain AND rules over partitions where at most two terms are positive
at a time, the at most 2**I rules of the active term tuples through a cell table.
Outputs are defuzzified from the terms' strengths alpha_j, accumulated in the rule loop, except
the area-based ones of sum-aggregated min-implied rules, which keep every rule's level as its
own item (c_items).
"""
from __future__ import annotations

import numpy as np

from ...engine.inference import CompiledRuleBase
from ...errors import Diagnostic, FuzzycError
from ...escape import c_comment, c_identifier, check_c_names
from ...semantics.model import (ACTIVATION_FLOOR, Aggregation, Connective, Defuzzifier, Hedge, Model,
                     RuleBase, TermKind)
from ...semantics.operators import (AGGREGATIONS, DEFUZZIFIERS, HEDGES, S_NORMS, T_NORMS,
                                    emitted_in_c, members)
from ...semantics.shapes import SHAPES, c_kinds
from .area import AreaWriter, is_sampled
from .cells import active_codes, cell_row_c, cell_table, cell_table_c, index_type, int_table
from .centroid import CentroidEmitter, area_segments, supported
from .chain import CChain
from .expressions import REAL_TYPES, RealType
from ..rule_blocks import emitted_blocks
from .guard import checked_header
from .helpers import helper_lines
from .rule_items import ItemWriter, per_item

PEAK_BASED = members(DEFUZZIFIERS, lambda rec: rec.family == "peaks")


def _fail(message: str) -> FuzzycError:
    return FuzzycError([Diagnostic(None, message)])


# The headers' step functions hold each signal in a local `v_NAME` (an output of the fixed-point
# chain also in `u_NAME`, `reciprocal_NAME`): a user name is always behind one of these prefixes,
# so a C keyword (`int`, `return`) is a name like any other.  The functions and types of the
# header start with the controller's name and `_`, so that must not begin with one of them
# (`v_clamp` for a signal `clamp` would hide the function v_clamp of a controller `v`).
LOCAL_PREFIXES = ("v_", "u_", "reciprocal_")


def check_c_model_names(model: Model) -> None:
    """Every name that becomes part of a C identifier in the headers, checked for clashes."""
    variables = [v for rb in model.blocks for v in (*rb.inputs, *rb.outputs)]
    check_c_names([x.name for x in (*model.signals, *model.steps, *model.outputs,
                                    *variables)] + list(model.params))
    prefix = c_identifier(model.name) + "_"
    if prefix.startswith(LOCAL_PREFIXES):
        raise _fail(f"the controller's name `{model.name}` makes the header's functions start "
                    f"with `{prefix}`, as its local variables do (v_NAME, u_NAME, "
                    "reciprocal_NAME for the signals): rename the controller")


def _table(real: RealType, rows) -> str:
    return "{" + ", ".join("{" + ", ".join(real.lit(v) for v in row) + "}" for row in rows) + "}"


def _uses_peaks(var, method: Defuzzifier) -> bool:
    return method in PEAK_BASED or bool(np.all(var.kinds == TermKind.SINGLETON))


def check_supported(rb: RuleBase) -> None:
    """Raise FuzzycError for the inference choices this back end does not emit."""
    _check_constructs(rb)
    method = rb.inference.defuzzifier
    for var in rb.outputs:
        if _uses_peaks(var, method):
            continue
        if not supported(rb.inference) and not per_item(rb.inference):
            raise _fail(f"the C back end does not emit the {method.name.lower()} of "
                        f"{rb.inference.aggregation.name.lower()}-aggregated "
                        f"{rb.inference.implication.name.lower()}-implied rules")


# The operators this back end emits: those with a C text in the operator registry.
C_TNORMS, C_SNORMS = emitted_in_c(T_NORMS), emitted_in_c(S_NORMS)
C_TERM_KINDS = c_kinds()       # the shapes whose registry record has a C emission
C_HEDGES = emitted_in_c(HEDGES)
C_AGGREGATIONS = emitted_in_c(AGGREGATIONS)
C_DEFUZZIFIERS = emitted_in_c(DEFUZZIFIERS)
SUMMED_PER_RULE = (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM)  # no aggregation


def _words(table: dict, allowed, sep: str = " | ") -> str:
    return sep.join(table[k].word for k in allowed)


LUT_HINT = "use the lookup-table back end (`--target lut`)"  # takes any rule base without state


def _check_constructs(rb: RuleBase) -> None:
    """The norms, hedges and term shapes the C back end emits (the engine has more): every
    operator without a C text in the registry is refused by name."""
    inf = rb.inference
    if rb.n_rules == 0:     # C has no empty arrays
        raise _fail("the C back end needs at least one rule; this rule base has none")
    for var in rb.outputs:
        if var.n_terms == 0:
            raise _fail(f"the C back end needs a term on every output; `{var.name}` has none")
    if inf.defuzzifier not in C_DEFUZZIFIERS:
        raise _fail(f"the C back end does not emit the {DEFUZZIFIERS[inf.defuzzifier].word} "
                    f"defuzzifier (it emits {_words(DEFUZZIFIERS, C_DEFUZZIFIERS, ', ')}); "
                    f"{LUT_HINT}")
    held = [v.name for v in rb.outputs if v.lock_previous]
    if held:
        raise _fail(f"the C back end does not emit lock-previous (`{held[0]}` holds its last "
                    "value where no rule fires: state the header's evaluation has not)")
    own = [(name, choice) for name, choice in rb.output_choices.items()
           if choice != (inf.aggregation, inf.defuzzifier)]
    if own:
        name, (agg, defuzz) = own[0]
        raise _fail(f"the C back end emits one aggregation and defuzzifier per rule base; "
                    f"output `{name}` has its own ({agg.name.lower()}, "
                    f"{defuzz.name.lower()})")
    if rb.conditions:
        raise _fail(f"the C back end emits rules that are one and/or over one clause per input; "
                    f"{rb.nested_rules()} has a nested condition; {LUT_HINT}, or split the "
                    "rule")
    if inf.and_ not in C_TNORMS or inf.or_ not in C_SNORMS:
        raise _fail(f"the C back end emits and = {_words(T_NORMS, C_TNORMS)} and "
                    f"or = {_words(S_NORMS, C_SNORMS)}; "
                    f"this rule base has and = {T_NORMS[inf.and_].word}, "
                    f"or = {S_NORMS[inf.or_].word}; {LUT_HINT}")
    if inf.aggregation not in C_AGGREGATIONS and inf.defuzzifier not in SUMMED_PER_RULE:
        raise _fail(f"the C back end emits aggregation = {_words(AGGREGATIONS, C_AGGREGATIONS)}; "
                    f"this rule base has aggregation = {AGGREGATIONS[inf.aggregation].word}"
                    f"; {LUT_HINT}, or weighted_average / weighted_sum, which sum over rules")
    hedges = sorted({Hedge(int(h)) for h in np.unique(rb.hedges)} - set(C_HEDGES))
    if hedges:
        raise _fail("the C back end emits the hedges "
                    + ", ".join(HEDGES[h].word for h in C_HEDGES if h != Hedge.NONE)
                    + "; not " + ", ".join(HEDGES[h].word for h in hedges) + f"; {LUT_HINT}")
    for var in rb.inputs + rb.outputs:
        for name, kind in zip(var.names, var.kinds):
            if kind not in C_TERM_KINDS:
                raise _fail(f"the C back end does not emit {SHAPES[TermKind(int(kind))].name} "
                            f"terms (`{name}` of `{var.name}`); use the lookup-table back end")


def _c_text(record) -> str:
    """The record's C text; an operator without one was refused by _check_constructs, so
    reaching here without one is a bug, never silently another operator."""
    if record.c_float is None:
        raise AssertionError(f"no C emission for {record.word}: _check_constructs lets it by")
    return record.c_float


class HeaderWriter:
    """Builds the header text for one model and one real type."""

    def __init__(self, model: Model, real: RealType, block: int | None = None):
        """The writer of the whole header (block None), or of rule block `block`'s part of
        it: its tables, helpers and NAME_bK_rulebase, named with the prefix NAME_bK_."""
        self.model, self.real = model, real
        if block is None:
            check_c_model_names(model)
        self.name = c_identifier(model.name) + ("" if block is None else f"_b{block}")
        # a model of several blocks: one writer per block under its own prefix; the header's
        # chain calls each block's rulebase in order (fuzzyc.semantics.model, "Rule blocks")
        emitted = emitted_blocks(model)
        self.block_writers = [] if block is not None or len(emitted) == 1 else \
            [HeaderWriter(model, real, k) for k in range(len(emitted))]
        self.rb = emitted[block or 0]
        check_supported(self.rb)
        self.p = self.name + "_"
        self.P = self.name.upper() + "_"
        # The cell table is the fast path (c_cells: direct up to MAX_C_TABLE_CELLS cells, 10
        # inputs of 3 terms; sorted codes past that); where it cannot be kept every rule is
        # looped over (a 1.8M-cell table took 19 s, 1.9 GB and gcc rejected it).
        self.partitions = CompiledRuleBase.sparse_partitions(self.rb)
        self.cells = None if self.partitions is None else cell_table(
            self.rb.antecedents, [v.n_terms for v in self.rb.inputs])
        self.sparse = self.cells is not None
        self.depth = self.cells.depth if self.sparse else 0   # rules per cell
        self.area = AreaWriter(real, self.p, self.rb.inference)
        self.items = self.item_writer()
        # One rule per cell of a direct table, read only for its consequents and weight: those
        # are tabled per cell, which saves the load of the rule between cell and consequent
        # on every active tuple (issue 29: the header against a hand-written version)
        self.per_cell = self.sparse and self.cells.one_rule_per_cell and self.items is None
        self.lines: list[str] = []

    def item_writer(self) -> ItemWriter | None:
        """The writer of the outputs kept rule by rule (c_items), where there are any; the
        items are the engine's candidates: every rule, or the sparse path's cell slots."""
        if not any(self.by_items(var) for var in self.rb.outputs):
            return None
        if not self.sparse:
            return ItemWriter(self.area, self.P, self.rb.n_rules, None)
        return ItemWriter(self.area, self.P, self.depth << len(self.rb.inputs),
                          index_type(self.rb.n_rules))

    def by_items(self, var) -> bool:
        """Whether this output is defuzzified item by item (SUM of MIN-clipped rules)."""
        return not _uses_peaks(var, self.rb.inference.defuzzifier) and \
            per_item(self.rb.inference)

    # -- small helpers ----------------------------------------------------------------------

    def out(self, *lines: str) -> None:
        self.lines.extend(lines)

    def helpers(self) -> None:
        """real_helpers.c's common section, after the one constant it needs."""
        self.out(f"#define {self.P}ACTIVATION_FLOOR {self.real.lit(ACTIVATION_FLOOR)}",
                 *helper_lines(["common"], self.p, self.P), "")

    # -- membership -------------------------------------------------------------------------

    def term_value(self, kind: TermKind, row: str, x: str) -> str:
        """C expression of one term's membership at x (NaN x -> 0, infinities -> limits):
        the shape record's emission."""
        return SHAPES[kind].c_float(row, x, self.p, self.real.fn, self.real.lit)

    @staticmethod
    def term_rows(var) -> list[list[float]]:
        """Each term's row of the C table (6 numbers), as its shape record lays it out."""
        return [SHAPES[TermKind(int(kind))].c_row(params)
                for kind, params in zip(var.kinds, np.asarray(var.params, dtype=float))]

    def membership_functions(self) -> None:
        t, p, P = self.real.name, self.p, self.P
        for i, var in enumerate(self.rb.inputs):
            table = f"{P}TERMS_{c_identifier(var.name).upper()}"
            self.out(f"/* {c_comment(var.name)} in [{var.lo:g}, {var.hi:g}]: "
                     + ", ".join(f"{c_comment(n)} ({TermKind(int(k)).name.lower()})"
                                 for n, k in zip(var.names, var.kinds)) + " */",
                     f"static const {t} {table}[{var.n_terms}][6] = "
                     f"{_table(self.real, self.term_rows(var))};",
                     f"static inline void {p}memberships_{i}({t} x, {t} mu[{var.n_terms}]) {{")
            for j, kind in enumerate(var.kinds):
                self.out(f"    mu[{j}] = {self.term_value(TermKind(int(kind)), f'{table}[{j}]', 'x')};")
            self.out("}")

    # -- rule base ----------------------------------------------------------------------------

    def aggregation_of(self, var) -> Aggregation:
        method = self.rb.inference.defuzzifier
        if method in (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM):
            return Aggregation.SUM
        return self.rb.inference.aggregation

    def accumulate(self, act: str, rule: str, slot: str, table: str = "CONSEQUENTS"
                   ) -> list[str]:
        """Statements adding `act` of rule index `rule` into every output's term strengths,
        and storing it as item `slot` where outputs keep the rules on their own (`table`:
        CELL_CONSEQUENTS with `rule` a cell, see per_cell)."""
        code = [] if self.items is None else self.items.store(act, rule, slot)
        for o, var in enumerate(self.rb.outputs):
            if self.by_items(var):
                continue
            strength = f"alpha{o}[{self.P}{table}[{rule}][{o}]]"
            code.append(_c_text(AGGREGATIONS[self.aggregation_of(var)])
                        .format(acc=strength, x=act, p=self.p))
        return code

    def combine(self, a: str, b: str, conjunction: bool) -> str:
        """a (the rule base's t-norm or s-norm) b, as the registry writes it in C."""
        inf = self.rb.inference
        norm = T_NORMS[inf.and_] if conjunction else S_NORMS[inf.or_]
        return _c_text(norm).format(a=a, b=b, p=self.p)

    def consequent_table(self, extra_row: bool) -> None:
        """CONSEQUENTS and WEIGHTS per rule (and a last row, no rule, with extra_row); per
        cell instead where per_cell."""
        rb = self.rb
        cons = np.array(rb.consequents, dtype=int).copy()
        for o, var in enumerate(rb.outputs):   # "no consequent" goes to a dummy slot
            cons[cons[:, o] < 0, o] = var.n_terms
        if extra_row:
            cons = np.vstack([cons, [v.n_terms for v in rb.outputs]])
        # a rule weighted below the floor never fires (its truth is <= 1): weight 0, which
        # float holds where 1e-100 is no float at all (a NaN still reaches lit and fails)
        weights = np.array([0.0 if w < ACTIVATION_FLOOR else w for w in rb.weights]
                           + ([0.0] if extra_row else []))
        what, rows = "rule and output (n_terms = the rule says nothing)", slice(None)
        if self.per_cell:     # an empty cell reads the extra row
            what, rows = ("cell (tuple of term ids) and output, its rule's (n_terms = no rule "
                          "or the rule says nothing)"), self.cells.rows[:, 0]
        self.out(f"/* Consequent term per {what}. */",
                 f"static const unsigned char {self.P}{self.prefix}CONSEQUENTS"
                 f"[{len(cons[rows])}][{self.P}N_RB_OUTPUTS] = {int_table(cons[rows])};")
        if not np.all(rb.weights == 1.0):
            self.out(f"static const {self.real.name} {self.P}{self.prefix}WEIGHTS"
                     f"[{len(weights[rows])}] = "
                     "{" + ", ".join(self.real.lit(w) for w in weights[rows]) + "};")

    @property
    def prefix(self) -> str:
        """Of the consequent and weight tables: CELL_ where they are per cell (per_cell)."""
        return "CELL_" if self.per_cell else ""

    def weighted(self, act: str, rule: str) -> str:
        return act if np.all(self.rb.weights == 1.0) else \
            f"{act} * {self.P}{self.prefix}WEIGHTS[{rule}]"

    def dense_rules(self) -> list[str]:
        """The loop over all rules; memberships of all inputs in one array `mu`."""
        rb, t, P, lit = self.rb, self.real.name, self.P, self.real.lit
        offsets = np.cumsum([0] + [v.n_terms for v in rb.inputs])
        one, zero = int(offsets[-1]), int(offsets[-1]) + 1
        conj = rb.connective == Connective.AND
        only_wild = np.all(rb.antecedents < 0, axis=1)
        flat = np.where(rb.antecedents >= 0, rb.antecedents + offsets[:-1],
                        np.where((conj | only_wild)[:, None], one, zero))
        plain = bool(np.all(conj) and not np.any(rb.negated) and np.all(rb.hedges == Hedge.NONE))
        self.out("/* Per rule and input: index into mu (all terms, then 1 and 0 for an absent "
                 "clause). */",
                 f"static const {index_type(zero)} {P}ANTECEDENTS[{P}N_RULES][{P}N_RB_INPUTS] = "
                 f"{int_table(flat)};")
        if not plain:
            hedges = np.where(rb.antecedents >= 0, rb.hedges, 0)
            negated = np.where(rb.antecedents >= 0, rb.negated, False)
            self.out(f"static const unsigned char {P}HEDGES[{P}N_RULES][{P}N_RB_INPUTS] = "
                     f"{int_table(hedges)};",
                     f"static const unsigned char {P}NEGATED[{P}N_RULES][{P}N_RB_INPUTS] = "
                     f"{int_table(negated)};",
                     f"static const unsigned char {P}IS_OR[{P}N_RULES] = "
                     "{" + ", ".join(str(int(c and not w)) for c, w
                                     in zip(~conj, only_wild)) + "};")
        code = [f"{t} mu[{one + 2}];"]
        code += [f"{self.p}memberships_{i}(x[{i}], mu + {offsets[i]});"
                 for i in range(len(rb.inputs))]
        code += [f"mu[{one}] = {lit(1)}; mu[{zero}] = {lit(0)};",
                 f"for (r = 0; r < {P}N_RULES; ++r) {{"]
        clauses = []
        for i in range(len(rb.inputs)):
            g = f"mu[{P}ANTECEDENTS[r][{i}]]"
            if not plain:
                code.append(f"    {t} g{i} = {self.p}clause({g}, {P}HEDGES[r][{i}], "
                            f"{P}NEGATED[r][{i}]);")
                g = f"g{i}"
            clauses.append(g)
        if plain:
            act = clauses[0]
            for g in clauses[1:]:
                act = self.combine(act, g, True)
        else:
            a, o = clauses[0], clauses[0]
            for g in clauses[1:]:
                a, o = self.combine(a, g, True), self.combine(o, g, False)
            act = f"({P}IS_OR[r] ? {o} : {a})"
        code.append(f"    {t} act = {self.p}fired({self.weighted(act, 'r')});")
        code += ["    " + s for s in self.accumulate("act", "r", "r")]
        code.append("}")
        return code

    def clause_helper(self) -> None:
        t, p, f, lit = self.real.name, self.p, self.real.fn, self.real.lit
        # hedge == 1 ? <very> : (hedge == 2 ? <somewhat> : (... : mu)), each the registry's
        emitted = [h for h in C_HEDGES if h != Hedge.NONE]
        choice = HEDGES[Hedge.NONE].c_float.format(mu="mu")
        for n, h in enumerate(reversed(emitted)):
            text = HEDGES[h].c_float.format(mu="mu", sqrt=f("sqrt"))
            choice = f"hedge == {int(h)} ? {text} : " + (choice if n == 0 else f"({choice})")
        self.out(f"/* Hedge ({', '.join(HEDGES[h].word for h in C_HEDGES)}) then NOT, as in "
                 "the model. */",
                 f"static inline {t} {p}clause({t} mu, unsigned char hedge, unsigned char not_) {{",
                 f"    {t} g = {choice};",
                 f"    return not_ ? {lit(1)} - g : g;",
                 "}")

    @staticmethod
    def slope_intercept(piece) -> list[float]:
        """The engine's piece (anchor, width, offset), mu = (x - anchor) / width + offset, as
        mu = slope * x + intercept (width inf: constant)."""
        anchor, width, offset = (float(v) for v in piece)
        if not np.isfinite(width):
            return [0.0, offset]
        return [1.0 / width, offset - anchor / width]

    def sparse_tables(self) -> None:
        """Per distinct partition: break points and, per segment, the two active terms' linear
        pieces; one shared function finds them for every input (one copy of its code, which
        keeps the header small at -O2 too, where per-input copies would be inlined)."""
        t, P = self.real.name, self.P
        parts, part_of = self.distinct_partitions()
        # Same length for all: the last break repeated, so the count loop has one constant
        # bound and x past the last break lands in the last (constant) segment.
        nb = max(len(q.breaks) for q in parts)
        breaks, pieces, active = zip(*(self.padded_partition(q, nb) for q in parts))
        place = self.cells.place
        inputs = [[k, int(pl)] for k, pl in zip(part_of, place)]
        n_parts = len(parts)
        self.out("/* Partitions of the inputs: break points and per segment (slope, intercept) "
                 "x 2 with the two term ids. */",
                 f"static const {t} {P}BREAKS[{n_parts}][{nb}] = {_table(self.real, breaks)};",
                 f"static const {t} {P}PIECES[{n_parts}][{nb + 1}][4] = "
                 "{" + ", ".join(_table(self.real, rows) for rows in pieces) + "};",
                 f"static const unsigned char {P}ACTIVE[{n_parts}][{nb + 1}][2] = "
                 "{" + ", ".join(int_table(ids) for ids in active) + "};",
                 "/* Per rule-base input (" + ", ".join(c_comment(v.name) for v in self.rb.inputs)
                 + "): partition, place value in the cell index. */",
                 f"static const {index_type(int(max(np.max(place), n_parts)))} "
                 f"{P}INPUTS[{P}N_RB_INPUTS][2] = {int_table(inputs)};")
        self.active_function(nb)
        if not self.per_cell:
            self.out(*cell_table_c(self.cells, P, self.p, self.rb.n_rules))

    def distinct_partitions(self) -> tuple[list, list[int]]:
        """(the distinct partitions of the inputs, per input the index of its own)."""
        parts: list = []
        part_of: list[int] = []
        for part in self.partitions:
            keys = [q.breaks.tobytes() + q.table.tobytes() for q in parts]
            key = part.breaks.tobytes() + part.table.tobytes()
            if key not in keys:
                parts.append(part)
                keys.append(key)
            part_of.append(keys.index(key))
        return parts, part_of

    def padded_partition(self, q, nb: int) -> tuple[list, list, list]:
        """q's break points, per segment (slope, intercept) x 2 and its two term ids, padded
        to nb break points (the last break and the last segment repeated)."""
        pad = nb - len(q.breaks)
        rows = [self.slope_intercept(r[0::2][:3]) + self.slope_intercept(r[1::2][:3])
                for r in q.table]
        ids = active_codes(q).tolist()
        return (list(q.breaks) + [q.breaks[-1]] * pad, rows[:-1] + [rows[-1]] * (pad + 1),
                ids[:-1] + [ids[-1]] * (pad + 1))

    def active_function(self, nb: int) -> None:
        """NAME_active: the two positive terms of an input from the partition tables."""
        t, p, P, lit = self.real.name, self.p, self.P, self.real.lit
        self.out("/* The two positive terms of input i at x: memberships m and their place in "
                 "the cell index. */",
                 f"static inline void {p}active(int i, {t} x, {t} m[2], "
                 f"{self.cells.cell_type} cell[2]) {{",
                 f"    const {t} *b = {P}BREAKS[{P}INPUTS[i][0]];",
                 "    /* Outside the outer break points every term is constant: clamp. */",
                 f"    {t} xc = {p}clamp(x, b[0], b[{nb - 1}]);",
                 "    int k = 0, j, s;",
                 "    /* NaN: no term, i.e. term 0 at membership 0 (see ACTIVE) */",
                 f"    if (x != x) {{ m[0] = m[1] = {lit(0)}; cell[0] = cell[1] = 0; return; }}",
                 f"    for (j = 0; j < {nb}; ++j) k += xc >= b[j];",
                 "    for (s = 0; s < 2; ++s) {",
                 f"        const {t} *q = {P}PIECES[{P}INPUTS[i][0]][k] + 2 * s;",
                 "        m[s] = xc * q[0] + q[1];",
                 f"        cell[s] = {P}ACTIVE[{P}INPUTS[i][0]][k][s] * {P}INPUTS[i][1];",
                 "    }",
                 "}")

    def sparse_rules(self) -> list[str]:
        rb, t, P = self.rb, self.real.name, self.P
        n_in = len(rb.inputs)
        depth = self.depth
        code = [f"{t} m[{n_in}][2];",
                f"{self.cells.cell_type} part[{n_in}][2];   /* term id times place value */",
                "int i;",
                f"for (i = 0; i < {n_in}; ++i) {self.p}active(i, x[i], m[i], part[i]);",
                f"for (r = 0; r < {1 << n_in}; ++r) {{   /* the 2**I active term tuples */"]
        bits = [f"(r >> {n_in - 1 - i}) & 1" for i in range(n_in)]
        cell = " + ".join(f"part[{i}][{bits[i]}]" for i in range(n_in))
        act = f"m[0][{bits[0]}]"
        for i in range(1, n_in):
            act = self.combine(act, f"m[{i}][{bits[i]}]", True)
        if self.per_cell:
            code += [f"    int cell = {cell};", f"    {t} act = {act};",
                     f"    {t} a = {self.p}fired({self.weighted('act', 'cell')});"]
            code += ["    " + s for s in self.accumulate("a", "cell", "r", "CELL_CONSEQUENTS")]
            return code + ["}"]
        code += [f"    int cell = {cell_row_c(self.cells, self.p, cell)};",
                 f"    {t} act = {act};", "    int d;",
                 f"    for (d = 0; d < {depth}; ++d) {{",
                 f"        int rule = {P}CELLS[cell][d];",
                 f"        {t} a = {self.p}fired({self.weighted('act', 'rule')});"]
        code += ["        " + s for s in self.accumulate("a", "rule", f"r * {depth} + d")]
        code += ["    }", "}"]
        return code

    def defuzzify(self, o: int, var) -> list[str]:
        lit, t = self.real.lit, self.real.name
        method = self.rb.inference.defuzzifier
        alpha = f"alpha{o}"
        if self.by_items(var):
            return self.items.defuzzify(o, var)
        if _uses_peaks(var, method):
            peaks = var.peaks()
            num = " + ".join(f"{alpha}[{j}] * {lit(v)}" for j, v in enumerate(peaks))
            den = " + ".join(f"{alpha}[{j}]" for j in range(var.n_terms))
            code = [f"{{ {t} num = {num};", f"  {t} den = {den};"]
            # the registry's text; a centroid of singletons is their ratio too
            value = DEFUZZIFIERS[method].c_float if method in PEAK_BASED else "num / den"
            return code + [f"  y[{o}] = den > 0 ? {value} : {lit(var.default)}; }}"]
        if self.walks(var):
            return self.area.defuzzify(o, var, alpha)
        emitter = CentroidEmitter(self.real, self.p, self.rb.inference)
        code = [f"{{ {t} area = {lit(0)}, moment = {lit(0)};"]
        code += ["  " + s for s in emitter.emit(area_segments(var), alpha)]
        return code + [f"  y[{o}] = area > 0 ? moment / area : {lit(var.default)}; }}"]

    def walks(self, var) -> bool:
        """Whether this output is defuzzified by walking M's points (c_area): every area-based
        case but the straight-line exact centroid of piecewise-linear terms."""
        method = self.rb.inference.defuzzifier
        return not _uses_peaks(var, method) and \
            (method != Defuzzifier.CENTROID or is_sampled(var))

    def area_support(self) -> None:
        """The walk's functions and the grid tables, where an output needs them."""
        walked = [o for o, var in enumerate(self.rb.outputs) if self.walks(var)]
        if walked:
            self.out(*self.area.helpers(polygon=any(not is_sampled(self.rb.outputs[o])
                                                    for o in walked)))
        for o in walked:
            if is_sampled(self.rb.outputs[o]):
                n_items = self.items.n_items if self.by_items(self.rb.outputs[o]) else 0
                self.out(*self.area.grid_getter(o, self.rb.outputs[o], n_items))
        if self.items is not None:
            self.item_support()

    def item_support(self) -> None:
        """c_items' functions and per-output tables (outputs kept rule by rule)."""
        outputs = [(o, var) for o, var in enumerate(self.rb.outputs) if self.by_items(var)]
        exact = [not is_sampled(var) for _, var in outputs]
        centroid = self.rb.inference.defuzzifier == Defuzzifier.CENTROID
        self.out(*self.items.helpers(centroid=centroid and any(exact),
                                     polygon=not centroid and any(exact)))
        for o, var in outputs:
            self.out(*self.items.tables(o, var, self.term_rows(var)))

    def rulebase_function(self) -> None:
        rb, t, p, lit = self.rb, self.real.name, self.p, self.real.lit
        if self.sparse:
            self.sparse_tables()
        else:
            if np.any(rb.hedges != Hedge.NONE) or np.any(rb.negated) or \
                    np.any(rb.connective != Connective.AND):
                self.clause_helper()
            self.membership_functions()
        self.consequent_table(extra_row=self.sparse)
        self.area_support()
        body = self.sparse_rules() if self.sparse else self.dense_rules()
        self.out("",
                 "/* The bare rule base: x[N_RB_INPUTS] (scaled inputs) -> y[N_RB_OUTPUTS]. "
                 "*/",
                 f"static inline void {p}rulebase(const {t} x[{self.P}N_RB_INPUTS], "
                 f"{t} y[{self.P}N_RB_OUTPUTS]) {{",
                 "    int r;")
        for o, var in enumerate(rb.outputs):
            if not self.by_items(var):
                self.out(f"    {t} alpha{o}[{var.n_terms + 1}] = {{{lit(0)}}};")
        if self.items is not None:
            self.out(*("    " + s for s in self.items.declarations()))
        self.out(*("    " + s for s in body))
        for o, var in enumerate(rb.outputs):
            self.out(*("    " + s for s in self.defuzzify(o, var)))
        self.out("}", "")

    # -- signal chain -------------------------------------------------------------------------

    def symbol(self, name: str) -> str:
        if name in self.model.params:
            return f"{self.P}PARAM_{c_identifier(name)}"
        return f"v_{c_identifier(name)}"

    def chain(self) -> CChain:
        """The chain walk's C domain for this header (fuzzyc.backends.c.chain)."""
        blocks = [(w.rb, w.p, w.P) for w in self.block_writers] or [(self.rb, self.p, self.P)]
        return CChain(self.model, self.real, self.p, self.P, self.symbol, blocks)

    def state_struct(self) -> None:
        self.out("typedef struct {", *self.chain().state_fields(), f"}} {self.p}state;", "")

    def init_function(self) -> None:
        self.out(f"static inline void {self.p}init({self.p}state *s) {{",
                 *self.chain().init_lines(), "}", "")

    def step_function(self) -> None:
        t, P, m = self.real.name, self.P, self.model
        body = [f"const {t} {self.symbol(sig.name)} = in[{k}];"
                for k, sig in enumerate(m.signals)]
        body += self.chain().statements()
        # A file may leave signals unused (or have no output at all): no warnings.
        body += [f"(void){self.symbol(name)};" for name in
                 [*(g.name for g in m.signals), *(g.name for g in m.steps),
                  *(v.name for rb in m.blocks for v in rb.outputs), *(o.name for o in m.outputs)]]
        if not m.outputs:
            body += ["(void)s;", "(void)out;"]
        self.out("/* One sample of the whole chain: raw inputs in[N_SIGNALS] -> out[N_OUTPUTS]. "
                 "*/",
                 f"static inline void {self.p}step({self.p}state *s, "
                 f"const {t} in[{P}N_SIGNALS], {t} out[{P}N_OUTPUTS]) {{",
                 *("    " + line for line in body), "}", "")

    # -- the whole header ---------------------------------------------------------------------

    def rules_comment(self) -> list[str]:
        """The header comment's lines on the rule base, or on each rule block."""
        def rules(w) -> str:
            return f"rules: {w.rb.n_rules}; activations: " + (
                "at most 2**I rules of the active term tuples (cell table)" if w.sparse
                else "all rules per call")
        if not self.block_writers:
            return [f" * inference: {self.rb.inference.describe()}", f" * {rules(self)}"]
        lines = [f" * {len(self.block_writers)} rule blocks, evaluated in this order:"]
        for k, w in enumerate(self.block_writers):
            lines += [f" *   {k}: {c_comment(w.rb.name)} ({w.p}rulebase), inference: "
                      f"{w.rb.inference.describe()}", f" *      {rules(w)}"]
        return lines

    def comment(self, numeric: str) -> None:
        m = self.model
        src = c_comment(m.source_path or "(built in memory)")
        self.out("/*",
                 f" * {self.name}.h - generated by fuzzyc from {src}",
                 f" * source hash (sha256, first 16 hex): {m.source_hash}",
                 f" * {c_comment(m.title)}" if m.title else " *",
                 f" * numeric: {numeric} ({self.real.name} arithmetic)",
                 *self.rules_comment(),
                 " * inputs of the chain: " + ", ".join(f"{c_comment(s.name)} [{s.lo:g}, {s.hi:g}]"
                                                        for s in m.signals),
                 " * outputs of the chain: " + ", ".join(f"{c_comment(o.name)} [{o.lo:g}, {o.hi:g}]"
                                                         for o in m.outputs),
                 " *",
                 " * Functions are static inline in this one header so it is self-contained",
                 " * (no .c file to add to a firmware build), the compiler can specialise and",
                 " * inline them into the control loop, and two controllers never clash at link",
                 " * time. No heap, no recursion, no writable globals, loop bounds are constants.",
                 " * Link with -lm only if the terms use exp/pow/sqrt (gaussian, bell, sigmoid,",
                 " * somewhat), the defuzzifier is the bisector, or the expressions do.",
                 " *",
                 " * Defined for every input: a NaN input gives every term of its variable",
                 " * membership 0, so rules needing it do not fire and an output where nothing",
                 " * fires gives its declared default; +-inf gives the shapes' limits. In the",
                 " * chain, memories keep their last finite value and an output whose value is",
                 " * not finite holds its state (an increment counts as 0), so out[] is finite.",
                 " */")

    def size_defines(self) -> list[str]:
        P, rb = self.P, self.rb
        return [f"#define {P}N_RB_INPUTS {len(rb.inputs)}",
                f"#define {P}N_RB_OUTPUTS {len(rb.outputs)}",
                f"#define {P}N_RULES {rb.n_rules}"]

    def block_section(self, k: int, real_type: str) -> list[str]:
        """Rule block k's part of a header of several: its sizes, its own copy of the helpers
        (under its prefix, so its code is the one-block header's), its tables and rulebase."""
        self.out(f"/* Rule block {k}: {c_comment(self.rb.name)}. */",
                 *self.size_defines(),
                 f"typedef {real_type} {self.p}real;", "")
        self.helpers()
        self.rulebase_function()
        return self.lines

    def header(self, numeric: str) -> str:
        m, P = self.model, self.P
        guard = f"FUZZYC_{self.name.upper()}_H"
        self.comment(numeric)
        self.out(f"#ifndef {guard}", f"#define {guard}", "", "#include <math.h>", "",
                 f"#define {P}N_SIGNALS {max(1, len(m.signals))}",
                 f"#define {P}N_OUTPUTS {max(1, len(m.outputs))}",
                 *([] if self.block_writers else self.size_defines()), "",
                 f"typedef {self.real.name} {self.p}real;   /* the type of in[], out[], x[], y[] */",
                 "")
        for k, s in enumerate(m.signals):
            self.out(f"#define {P}IN_{c_identifier(s.name).upper()} {k}")
        for k, o in enumerate(m.outputs):
            self.out(f"#define {P}OUT_{c_identifier(o.name).upper()} {k}")
        self.out("")
        for prm in m.params.values():
            self.out(f"static const {self.real.name} {P}PARAM_{c_identifier(prm.name)} = "
                     f"{self.real.lit(prm.value)};")
        self.out("")
        self.helpers()
        if self.block_writers:
            for k, w in enumerate(self.block_writers):
                self.out(*w.block_section(k, f"{self.p}real"))
        else:
            self.rulebase_function()
        self.state_struct()
        self.init_function()
        self.step_function()
        self.out(f"#endif /* {guard} */", "")
        return "\n".join(self.lines)


def generate_header(model: Model, numeric: str = "float") -> str:
    """The text of the C99 header for `model` (numeric: float | double)."""
    if numeric not in REAL_TYPES:
        raise _fail(f"numeric `{numeric}` is not emitted; choose one of "
                    + ", ".join(REAL_TYPES))
    if not all(rb.inputs and rb.outputs for rb in model.blocks):
        raise _fail("the C back end needs rule blocks with inputs and outputs")
    return checked_header(HeaderWriter(model, REAL_TYPES[numeric]).header(numeric), model)
