"""The numpy engine: what a rule base means (the reference semantics of `fuzzyc.semantics.model`).

Two ways to find the rule activations, with identical results:
- dense: every rule for every sample (any rule base: OR, NOT, hedges, wildcards, any terms);
- sparse: when every input is a partition where at most two terms are positive at a time (see
  `LocalPartition`) and the rules are plain AND conjunctions of one term per input, a sample can
  fire at most 2**I rules.  Per sample the engine takes the two active terms of each input, forms
  the 2**I term-index tuples, and looks their rules up in a table built once from the rules (a
  direct table of every term tuple, or the rules' sorted tuple codes where that table would be
  too big).  Wide rule bases stay on this path while 2**I is at most the number of rules, so
  the cost grows with 2**I, not with the rules (3**I in a full grid of three terms).
Defuzzification (`fuzzyc.engine.defuzz`) takes either form.  Where every output can be defuzzified
from its terms' strengths alpha_j (peak-based methods; area-based ones with MAX aggregation, or
SUM with PRODUCT implication; not PROBSUM or BOUNDED_SUM, whose area methods need every rule's
own shape), the sparse case goes one step further: `fuzzyc.engine.strength_grid` scatters the 2**I
activations straight into alpha, with tables per cell of the input grid (per term tuple for
wide rule bases, where the cells' tables would be too big), and the exact centroid has a closed
form in alpha (`fuzzyc.engine.centroid`) where the output terms allow it.  Batches are
processed in chunks so memory stays flat in the batch size.
"""
from __future__ import annotations

from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from typing import Callable, Sequence

import numpy as np

from .defuzz import SCATTERS, OutputDefuzzifier, safe_ratio
from .strength_grid import GridStrengths, lookup_rows, place_values
from .membership import HEDGE_EXPONENT, LocalPartition, apply_hedges, memberships
from ..semantics.model import (CondOp, Connective, Defuzzifier, Hedge, RuleBase, TNorm,
                               weight_of)
from .norms import combine, firing, row_sum
from .scalar import ScalarGrid
from .workspace import Workspace, WorkspacePool
from .held_outputs import EXACT, Held, Policy, finish_output, locked, reads_values, refuse_stateless

MAX_LOOKUP_CELLS = 1 << 21     # a direct cell table up to here, sorted cell codes beyond
MAX_SPARSE_INPUTS = 6          # past this many inputs the grid path is taken only while a
                               # sample's 2**I candidates are fewer than the rules (the
                               # fixed-point C cell tables stop here)
MAX_CELL_CODE = float(1 << 62)  # cell codes are int64
# assumption: the working set one chunk may use, in float64 values (16 MB).  Measured on a 2-core
# EPYC (2 MB L2), 100,000-200,000 samples, the paper rule bases: in a fresh process 1 << 22
# (32 MB) chunks get their temporaries as fresh pages every chunk (page faults dominate), and
# 1 << 21 ran the grid path 3.3-4.6x and the dense path 1.2-2x faster; where the allocator keeps
# its memory (no faults) the two sizes are within 5 % of each other.  1 << 20 gained a little
# more cold but lost 24 % on the closed-form centroid warm (more chunks, each with fixed cost).
CHUNK_FLOATS = 1 << 21
DEFAULT_CHUNK = 65536          # samples per chunk at most, whatever the work per sample
FAST_TNORMS = (TNorm.MIN, TNorm.PRODUCT)   # the t-norms the sparse and grid paths (and
                                          # the back ends built on them) know


def activations(rb: RuleBase, x: np.ndarray) -> np.ndarray:
    """x (N, I) -> act (N, R): every rule's activation, after weights (the dense reference)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    mus = [memberships(var, x[:, i]) for i, var in enumerate(rb.inputs)]
    act = flat_activations(rb, mus, mus, x.shape[0])
    for r, program in rb.conditions.items():
        act[:, r] = run_condition(rb, program, x)
    return firing(act * rb.weights)


def flat_activations(rb: RuleBase, mus: list[np.ndarray], negated_mus: list[np.ndarray],
                     n: int, tables: tuple[dict, dict] | None = None) -> np.ndarray:
    """The matrix rules' truth (N, R) before weights, from each input's memberships mus[i]
    (N, T_i); a negated clause reads negated_mus instead (1 - hedge of it). Every norm and
    hedge is monotone, so the set-valued proofs get bounds of the truth by passing (lower,
    upper) and (upper, lower) membership bounds.  `tables`: the norms' functions in place of
    the model's (norms.combine)."""
    conj = rb.connective == Connective.AND
    clauses = []
    for i, var in enumerate(rb.inputs):
        cols = rb.antecedents[:, i]
        picked = np.where(cols >= 0, cols, var.n_terms)
        gathered = []
        for source in (mus[i],) if negated_mus is mus else (mus[i], negated_mus[i]):
            mu = np.concatenate([source, np.zeros((n, 1))], axis=1)
            g = mu[:, picked]
            if np.any(rb.hedges[:, i] != Hedge.NONE):
                g = apply_hedges(g, rb.hedges[:, i])
            gathered.append(g)
        g = np.where(rb.negated[:, i], 1.0 - gathered[-1], gathered[0])
        # An absent clause is the neutral element of the rule's connective.
        clauses.append(np.where(cols >= 0, g, np.where(conj, 1.0, 0.0)))
    if not clauses:
        return np.ones((n, rb.n_rules))
    act = np.where(conj, combine(clauses, rb.inference.and_, True, tables),
                   combine(clauses, rb.inference.or_, False, tables))
    return np.where(np.all(rb.antecedents < 0, axis=1), 1.0, act)


def run_condition(rb: RuleBase, program: np.ndarray, x: np.ndarray,
                  tables: tuple[dict, dict] | None = None) -> np.ndarray:
    """x (N, I) -> the truth (N,) of one rule's clause program (see `fuzzyc.semantics.model`);
    `tables` as for flat_activations."""
    stack: list[np.ndarray] = []
    for op, i, t, h in program.tolist():
        if op == CondOp.CLAUSE:
            if t < 0:
                stack.append(np.ones(x.shape[0]))
                continue
            mu = memberships(rb.inputs[i], x[:, i])[:, t:t + 1]
            stack.append((apply_hedges(mu, np.array([h])) if h else mu)[:, 0])
        elif op == CondOp.NOT:
            stack.append(1.0 - stack.pop())
        elif op == CondOp.HEDGE:
            stack.append(apply_hedges(stack.pop()[:, None], np.array([h]))[:, 0])
        elif op == CondOp.WEIGHT:       # fuzzylite's weight under a conclusion's hedges
            stack.append(stack.pop() * weight_of(t))
        elif op == CondOp.CONCLUDED:    # the Octave toolkit's: its own hedge inverted
            v = stack.pop()
            stack.append(v ** (1.0 / HEDGE_EXPONENT[h]) if t else v)
        else:
            b, a = stack.pop(), stack.pop()
            norm = rb.inference.and_ if op == CondOp.AND else rb.inference.or_
            stack.append(combine([a, b], norm, op == CondOp.AND, tables))
    return stack.pop()


def _key(rb: RuleBase, arrays: list[np.ndarray]) -> tuple:
    """What rb's compiled tables depend on, in O(variables + nested rules) whatever the number
    of rules: each numpy array by its identity (compiling makes it read-only, so a change is an
    assignment of a new array, which changes the key; `arrays` collects them so that their ids
    are not reused while the key is kept), everything else by value (params given as a list)."""
    def ref(a) -> int | tuple:
        if isinstance(a, np.ndarray):
            arrays.append(a)
            return id(a)
        a = np.asarray(a, dtype=float)
        return a.shape, a.tobytes()

    def items(d: dict | None) -> tuple:
        return tuple((k, ref(a)) for k, a in d.items()) if d else ()

    inf = rb.inference
    parts = [inf.and_, inf.or_, inf.implication, inf.aggregation, inf.defuzzifier,
             tuple(sorted(rb.output_choices.items())), ref(rb.antecedents), ref(rb.consequents),
             ref(rb.weights), ref(rb.negated), ref(rb.hedges), ref(rb.connective),
             items(rb.conditions)]
    for v in rb.inputs + rb.outputs:
        parts += [v.name, tuple(v.names), v.lo, v.hi, v.default, v.lock_previous, ref(v.kinds),
                  ref(v.params), items(v.coefficients), items(v.points),
                  tuple((t, f.text) for t, f in v.formulas.items()) if v.formulas else ()]
    return tuple(parts)


def _freeze(a: np.ndarray) -> None:
    """a read-only, and the arrays it is a view of: an in-place write to a compiled rule base
    raises instead of leaving its tables stale.  (A writeable view of the same memory taken
    before compiling stays writeable: numpy cannot reach it.  fuzzyc keeps none.)"""
    while isinstance(a, np.ndarray):
        a.flags.writeable = False
        a = a.base


class CompiledRuleBase:
    """The per-rule-base tables of the engine, built once (see `compiled`)."""

    def __init__(self, rb: RuleBase, allow_sparse: bool = True):
        self.rb = rb
        self.arrays: list[np.ndarray] = []
        self.key = _key(rb, self.arrays)
        for a in self.arrays:
            _freeze(a)
        self.defuzzifiers = [OutputDefuzzifier(v, rb.inference_of(o), rb.inputs)
                             for o, v in enumerate(rb.outputs)]
        self.linear_terms = any(d.linear is not None for d in self.defuzzifiers)
        # every output a ratio of its peaks weighted by the strengths (COA, weighted average)
        self.peak_ratio = not self.linear_terms and all(
            d.use_peaks and d.inference.defuzzifier not in (Defuzzifier.WEIGHTED_SUM,
                                                            Defuzzifier.GROUPED_SUM)
            for d in self.defuzzifiers)
        self.defaults = np.array([[float(v.default)] for v in rb.outputs])
        # outputs read by function terms or holding their value: in order, NaN where nothing
        # with a value fired, finished by fuzzyc.engine.held_outputs
        self.ordered = [OutputDefuzzifier(replace(v, default=np.nan), rb.inference_of(o),
                                          rb.inputs)
                        for o, v in enumerate(rb.outputs)] if reads_values(rb) else None
        self.partitions = self.sparse_partitions(rb) if allow_sparse else None
        self.sparse = self.partitions is not None
        n_candidates = rb.n_rules
        self.grid = None
        if self.sparse:
            self._build_lookup(rb)
            n_candidates = self.lookup.shape[1] << len(rb.inputs)
            self.grid = None if self.ordered else self._grid(rb)
        if self.grid is not None:
            work = max([d.work_per_sample(self.grid.width) for d in self.defuzzifiers]
                       + [self.grid.work_per_sample()])
        else:
            work = max([d.work_per_sample(n_candidates) for d in self.defuzzifiers]
                       + [4 * n_candidates * max(1, len(rb.inputs))])
        self.chunk_limit = max(1, CHUNK_FLOATS // max(1, work))   # no rules: no work
        self.pool = WorkspacePool()     # the grid path's buffers, per chunk size
        self._scalar: ScalarGrid | None | bool = False     # built on first use

    @property
    def scalar(self) -> ScalarGrid | None:
        """The one-sample path on Python floats (fuzzyc.engine.scalar), None where it does
        not apply."""
        if self._scalar is False:
            self._scalar = ScalarGrid.build(self)
        return self._scalar

    @staticmethod
    def sparse_partitions(rb: RuleBase) -> list[LocalPartition] | None:
        """The inputs' local partitions where the sparse path applies to rb, else None (the
        C back end takes its cell table from them too)."""
        n_in = len(rb.inputs)
        plain = (rb.n_rules > 0 and 0 < n_in
                 and (n_in <= MAX_SPARSE_INPUTS or 2 ** n_in <= rb.n_rules)
                 and rb.inference.and_ in FAST_TNORMS
                 and np.all(rb.connective == Connective.AND) and not np.any(rb.negated)
                 and np.all(rb.hedges == Hedge.NONE) and np.all(rb.antecedents >= 0)
                 and np.prod([v.n_terms + 1.0 for v in rb.inputs]) <= MAX_CELL_CODE)
        if not plain:
            return None
        parts = [LocalPartition.build(v) for v in rb.inputs]
        return None if any(p is None for p in parts) else parts

    def _grid(self, rb: RuleBase) -> GridStrengths | None:
        """The grid fast path, when every output can be defuzzified from term strengths
        aggregated the same way."""
        aggregations = {d.strength_aggregation() for d in self.defuzzifiers}
        if len(aggregations) != 1 or None in aggregations or aggregations - SCATTERS.keys():
            return None
        return GridStrengths(rb, self.partitions, self.lookup, self.radix, self.codes,
                             aggregations.pop())

    def _build_lookup(self, rb: RuleBase) -> None:
        """lookup[row] = the rules whose antecedent is the term tuple of that row, padded with
        rule R.  The row of a cell code is the code itself (a direct table) while there are at
        most MAX_LOOKUP_CELLS cells; beyond, `codes` holds the rules' codes sorted, the row is
        a code's rank there, and the extra last row (no rule) answers the other codes."""
        radix = np.array([v.n_terms + 1 for v in rb.inputs], dtype=np.int64)
        place = place_values(radix)
        cells = rb.antecedents @ place
        self.codes = None
        if np.prod(radix.astype(float)) > MAX_LOOKUP_CELLS:
            self.codes, cells = np.unique(cells, return_inverse=True)
            cells = cells.ravel()
            n_rows = len(self.codes) + 1
        else:
            n_rows = int(np.prod(radix))
        order = np.argsort(cells, kind="stable")
        counts = np.bincount(cells, minlength=n_rows)
        depth = max(1, int(counts.max()))
        lookup = np.full((n_rows, depth), rb.n_rules)
        rank = np.arange(rb.n_rules) - np.searchsorted(cells[order], cells[order])
        lookup[cells[order], rank] = order
        self.radix, self.lookup = radix, lookup
        self.weights = np.append(rb.weights.astype(float), 0.0)
        self.unit_weights = bool(np.all(rb.weights == 1.0))
        self.consequents = np.vstack([rb.consequents, np.full(len(rb.outputs), -1)])

    def candidates(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """(act (N, C), rule ids (N, C)) of the rules that can fire; ids None = all rules."""
        if not self.sparse:
            return activations(self.rb, x), None
        n = x.shape[0]
        cell = np.zeros((n, 1), dtype=np.intp)
        mu = None    # the first input's memberships as they are: T(1, m) = m only up to rounding
        tnorm = self.rb.inference.and_
        for i, part in enumerate(self.partitions):
            terms, m = part.active(x[:, i])
            cell = (cell[:, :, None] * self.radix[i] + terms[:, None, :]).reshape(n, -1)
            mu = m if mu is None else \
                combine([mu[:, :, None], m[:, None, :]], tnorm, True).reshape(n, -1)
        if self.codes is not None:
            cell = lookup_rows(self.codes, cell)
        rid = self.lookup[cell].reshape(n, -1)
        if self.lookup.shape[1] > 1:
            mu = np.repeat(mu, self.lookup.shape[1], axis=1)
        return firing(mu if self.unit_weights else mu * self.weights[rid]), rid

    def evaluate_chunk(self, x: np.ndarray, held: Held | None = None,
                       policy: Policy = EXACT, work: Workspace | None = None,
                       out: np.ndarray | None = None) -> np.ndarray:
        """x (N, I) -> y (N, O); `held` and `policy` for outputs evaluated in order (see
        fuzzyc.engine.held_outputs; a rule base with outputs that hold their value needs `held`).
        `work`: the buffers the grid path reuses (one caller at a time, see `pool`); `out`: an
        (N, O) array to write y into."""
        y = out if out is not None else np.empty((x.shape[0], len(self.defuzzifiers)))
        if self.ordered:
            y[...] = self._evaluate_ordered(x, held, policy)
            return y
        if self.grid is not None:
            alpha = self.grid.rows(x.T, work)
            if self.peak_ratio:
                return self._peak_ratios(alpha, work, y.T).T
            for o in range(len(self.defuzzifiers)):
                self._from_strengths(o, alpha, x, work, y[:, o])
            return y
        act, rid = self.candidates(x)
        for o, defuzzify in enumerate(self.defuzzifiers):
            J = self.rb.consequents[:, o] if rid is None else self.consequents[rid, o]
            y[:, o] = defuzzify(act, J, x)
        return y

    def _evaluate_ordered(self, x: np.ndarray, held: Held | None, policy: Policy) -> np.ndarray:
        if held is None and locked(self.rb):
            refuse_stateless(self.rb)
        act, rid = self.candidates(x)
        env = {v.name: x[:, i] for i, v in enumerate(self.rb.inputs)}
        y = np.empty((x.shape[0], len(self.ordered)))
        for o, defuzzify in enumerate(self.ordered):
            J = self.rb.consequents[:, o] if rid is None else self.consequents[rid, o]
            value = defuzzify(act, J, x, env, policy.keep_nonfinite)
            fired = ((J >= 0) & (act > 0)).any(axis=1)
            y[:, o] = finish_output(policy, self.rb.outputs[o], value, fired, held, o)
            env[self.rb.outputs[o].name] = y[:, o]
        return y

    def evaluate_rows(self, xt: np.ndarray, held: Held | None = None) -> np.ndarray:
        """xt (I, N), one row per input -> y (O, N): evaluate_chunk for callers that hold
        their signals as rows (the controller), without transposing on the way in or out."""
        if self.grid is None:
            return self.evaluate_chunk(xt.T, held).T
        if xt.shape[1] == 1 and self.scalar is not None:
            y = self.scalar(xt[:, 0].tolist())
            if y is not None:
                return np.array(y)[:, None]
        n = xt.shape[1]
        step = max(1, min(DEFAULT_CHUNK, self.chunk_limit))   # as evaluate: bounded buffers
        y = np.empty((len(self.defuzzifiers), n))
        with self.pool.checkout(max(1, min(n, step))) as work:
            for s in range(0, n, step):
                part, out = xt[:, s:s + step], y[:, s:s + step]
                alpha = self.grid.rows(part, work)
                if self.peak_ratio:
                    self._peak_ratios(alpha, work, out)
                    continue
                # linear terms get x (N, I) laid out as evaluate_chunk's callers pass it
                x = np.ascontiguousarray(part.T) if self.linear_terms else None
                for o in range(len(self.defuzzifiers)):
                    self._from_strengths(o, alpha, x, work, out[o])
        return y

    def _from_strengths(self, o: int, alpha: np.ndarray, x: np.ndarray | None,
                        work: Workspace | None, out: np.ndarray) -> None:
        """Output o from the grid's strengths into out (N,): OutputDefuzzifier.from_strengths,
        with the exact centroid's closed form working in the workspace's buffers."""
        defuzzify, strengths = self.defuzzifiers[o], alpha[self.grid.slices[o]].T
        if not defuzzify.use_peaks and defuzzify.closed_form is not None:
            defuzzify.closed_form(strengths, work, out)
        else:
            out[...] = defuzzify.from_strengths(strengths, x)

    def _peak_ratios(self, alpha: np.ndarray, work: Workspace | None,
                     out: np.ndarray) -> np.ndarray:
        """Every output's sum(alpha z) / sum(alpha) (a peak-based ratio, as
        OutputDefuzzifier.from_strengths) with one check of the denominators for all outputs,
        into out (O, N).  The sums run term by term in a fixed order, not through BLAS, whose
        kernels (FMA, blocking) gave a sample's last bit that depended on the batch size; so a
        sample's result is the same alone or in any batch, and the scalar path
        (fuzzyc.engine.scalar) repeats the same operations."""
        n, n_out = alpha.shape[1], len(self.defuzzifiers)
        work = work if work is not None else Workspace(n)
        num, den = work.array("num", (n_out, n)), work.array("den", (n_out, n))
        for o, (d, rows) in enumerate(zip(self.defuzzifiers, self.grid.slices)):
            strengths = alpha[rows]                                      # (T, N)
            terms = np.multiply(strengths, d.peaks[:, None],
                                out=work.array("terms", strengths.shape))
            row_sum(terms, num[o])
            row_sum(strengths, den[o])
        if den.size and den.min() > 0:      # safe_ratio without a temporary
            return np.divide(num, den, out=out)
        out[...] = safe_ratio(num, den, self.defaults)
        return out


# The most recently used rule bases' tables. An entry holds its rule base (so an id is never
# reused while it is here); the bound frees the tables of rule bases no longer in use.
CACHE_SIZE = 64
_CACHE: OrderedDict[int, CompiledRuleBase] = OrderedDict()


def compiled(rb: RuleBase) -> CompiledRuleBase:
    """The engine's tables for rb, rebuilt whenever rb has changed (e.g. learned values): its
    arrays are read-only from here on, so a change assigns new ones (`rb.weights = w`)."""
    entry = _CACHE.get(id(rb))
    if entry is not None and entry.rb is rb and entry.key == _key(rb, []):
        _CACHE.move_to_end(id(rb))
        return entry
    entry = _CACHE[id(rb)] = CompiledRuleBase(rb)
    _CACHE.move_to_end(id(rb))
    while len(_CACHE) > CACHE_SIZE:
        _CACHE.popitem(last=False)
    return entry


def evaluate(rb: RuleBase, x: np.ndarray, chunk: int = DEFAULT_CHUNK, held: Held | None = None,
             policy: Policy = EXACT, threads: int = 1) -> np.ndarray:
    """x (N, I) -> y (N, O), in chunks so memory is flat in N (`held`, `policy`: see
    CompiledRuleBase.evaluate_chunk).  threads > 1 spreads the chunks over that many threads
    (numpy releases the GIL inside its kernels), each with its own workspace; every chunk is
    computed as with one thread, so the results are the same bits.  Outputs evaluated in
    order (held values, function terms) stay on one thread.  Measured on a shared 2-core
    machine, 2 threads ran the grid path at 0.8-0.93x one thread: its scatter, ufunc.at
    (a third of the time), holds the GIL."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    if x.shape[1] != len(rb.inputs):
        raise ValueError(f"expected {len(rb.inputs)} input columns "
                         f"({', '.join(v.name for v in rb.inputs)}), got {x.shape[1]}")
    engine = compiled(rb)
    n = x.shape[0]
    if n == 1 and engine.scalar is not None:
        row = engine.scalar(x[0].tolist())
        if row is not None:
            return np.array([row])
    step = max(1, min(chunk, engine.chunk_limit))
    y = np.empty((n, len(rb.outputs)))
    starts = range(0, n, step)

    def run(part: range) -> None:
        with engine.pool.checkout(max(1, min(n, step))) as work:
            for s in part:
                engine.evaluate_chunk(x[s:s + step], held, policy, work, y[s:s + step])

    workers = min(threads, len(starts)) if not engine.ordered else 1
    if workers <= 1:
        run(starts)
        return y
    # contiguous runs of chunks, one per thread
    bounds = np.linspace(0, len(starts), workers + 1).astype(int)
    with ThreadPoolExecutor(workers) as executor:
        for done in [executor.submit(run, starts[a:b]) for a, b in zip(bounds, bounds[1:])]:
            done.result()
    return y


def _input_row(rb: RuleBase, values: dict[str, float]) -> np.ndarray:
    missing = [v.name for v in rb.inputs if v.name not in values]
    if missing:
        raise KeyError(f"no value for input(s): {', '.join(missing)}")
    return np.array([[float(values[v.name]) for v in rb.inputs]])


def evaluate_one(rb: RuleBase, values: dict[str, float]) -> dict[str, float]:
    """The outputs at one point given by input name (the scalar path where it applies)."""
    y = evaluate(rb, _input_row(rb, values))[0]
    return dict(zip([v.name for v in rb.outputs], y.tolist()))


def scalar_evaluator(rb: RuleBase) -> Callable[[Sequence[float]], list[float]]:
    """f(values) -> outputs: one point (a float per input, in order) at a time, with rb's
    tables as they are now, so no per-call check that rb has changed (`compiled` costs about
    8 us).  Take a new one after assigning new arrays to rb.  Off the scalar path's reach (see
    fuzzyc.engine.scalar) and at NaN inputs it calls the batch engine."""
    engine = compiled(rb)
    scalar = engine.scalar

    def batch(values: Sequence[float]) -> list[float]:
        return evaluate(rb, np.array([values], dtype=float))[0].tolist()

    if scalar is None:
        return batch

    def one(values: Sequence[float]) -> list[float]:
        y = scalar(values)
        return batch(values) if y is None else y
    return one


@dataclass
class Explanation:
    """Why a rule base gave its outputs at one input point."""
    inputs: dict[str, float]
    memberships: dict[str, dict[str, float]]
    fired: list[tuple[int, float, str, str]] = field(default_factory=list)  # strongest first
    outputs: dict[str, float] = field(default_factory=dict)

    def __str__(self) -> str:
        lines = ["inputs: " + ", ".join(f"{k}={v:g}" for k, v in self.inputs.items())]
        for name, mu in self.memberships.items():
            lines.append(f"  {name}: " + ", ".join(f"{t}={m:.3g}" for t, m in mu.items() if m > 0))
        lines.append(f"fired ({len(self.fired)}):")
        lines += [f"  #{r + 1} {a:.4g}  {text}" + (f"   [{origin}]" if origin else "")
                  for r, a, text, origin in self.fired]
        lines.append("outputs: " + ", ".join(f"{k}={v:.6g}" for k, v in self.outputs.items()))
        return "\n".join(lines)


def explain(rb: RuleBase, x: np.ndarray) -> Explanation:
    """Which rules fired at x (I,) and how strongly, with the memberships and outputs."""
    row = np.asarray(x, dtype=float).reshape(1, -1)
    act = activations(rb, row)[0]
    mu = {v.name: dict(zip(v.names, memberships(v, row[:, i])[0].tolist()))
          for i, v in enumerate(rb.inputs)}
    order = [int(r) for r in np.argsort(-act, kind="stable") if act[r] > 0]
    origins = rb.origins if len(rb.origins) == rb.n_rules else [""] * rb.n_rules
    fired = [(r, float(act[r]), rb.describe_rule(r), origins[r]) for r in order]
    y = evaluate(rb, row, held=Held(sequence=True))[0]    # one step: nothing held yet
    return Explanation({v.name: float(row[0, i]) for i, v in enumerate(rb.inputs)}, mu, fired,
                       {v.name: float(y[o]) for o, v in enumerate(rb.outputs)})
