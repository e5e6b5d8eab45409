"""A model of several rule blocks as the exporters see it: the variables of the whole file, one
single-block view per block (so the one-rule-base helpers of `export` apply block by block),
the chained reads, and the blocks merged into one rule base where that is exact (FIS).

A file's inputs are the blocks' inputs that no block concludes (the raw signals' order first,
then the blocks' order); its outputs every block's outputs in block order.  A LINEAR term's
coefficients follow the inputs of whatever reads it (a block, the merged rule base, fuzzylite's
engine), so they are moved to the new input order, zero on inputs the block does not read.
"""
from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

from ..engine.membership import linear_coefficients
from ..semantics.model import CondOp, Model, RuleBase, TermKind, Variable


def file_variables(model: Model) -> tuple[list[Variable], list[Variable]]:
    """(inputs, outputs) of the whole model, each variable once."""
    if len(model.blocks) == 1:
        return list(model.blocks[0].inputs), list(model.blocks[0].outputs)
    outputs = [v for rb in model.blocks for v in rb.outputs]
    concluded = {v.name for v in outputs}
    signals = [s.name for s in model.signals]
    seen: dict[str, Variable] = {}
    for rb in model.blocks:
        for v in rb.inputs:
            if v.name not in concluded:
                seen.setdefault(v.name, v)
    order = [n for n in signals if n in seen] + [n for n in seen if n not in signals]
    return [seen[n] for n in order], outputs


def block_names(model: Model, keywords: frozenset[str] = frozenset()) -> list[str]:
    """Each block's name as the formats can say it (letters, digits, _; unique; none of the
    format's `keywords`, in lower case)."""
    names: list[str] = []
    for k, rb in enumerate(model.blocks):
        ok = re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", rb.name) and rb.name not in names \
            and rb.name.lower() not in keywords
        names.append(rb.name if ok else "rules" if k == 0 else f"rules_{k + 1}")
    return names


def read_inputs(rb: RuleBase, declared: list[Variable]) -> list[Variable]:
    """The inputs a block's rules read, in `declared` order: the inputs of the block a `.fz`
    file gives it back (its `block` reads what its rules name)."""
    used = {int(i) for i in np.flatnonzero(np.any(rb.antecedents >= 0, axis=0))}
    used |= {int(i) for p in rb.conditions.values() for op, i, *_ in p.tolist()
             if op == CondOp.CLAUSE}
    names = {rb.inputs[i].name for i in used}
    return [v for v in declared if v.name in names]


def block_view(model: Model, rb: RuleBase) -> Model:
    """The model with `rb` as its one rule block (for the helpers that read `model.rulebase`)."""
    return replace(model, blocks=[rb])


def one_output(rb: RuleBase, o: int) -> RuleBase:
    """Block `rb` concluding its output o only, with that output's own inference (a writer
    that says the aggregation and defuzzifier per output writes each from this)."""
    return replace(rb, outputs=[rb.outputs[o]], consequents=rb.consequents[:, [o]],
                   inference=rb.inference_of(o), output_choices={})


def chained_reads(model: Model) -> list[str]:
    """`block `B` reads `y`, an output of block `A`` for every output a later block reads."""
    owner = {v.name: rb.name for rb in model.blocks for v in rb.outputs}
    return [f"block `{rb.name}` reads `{v.name}`, an output of block `{owner[v.name]}`"
            for rb in model.blocks for v in rb.inputs if v.name in owner]


def chain_warning(model: Model, fmt: str) -> list[str]:
    """The warning a chained model written as FLL or FCL carries (docs/formats.md)."""
    reads = chained_reads(model)
    if not reads:
        return []
    return [f"{'; '.join(reads)}: fuzzyc reads the output's value through its terms, fuzzylite "
            f"reading this {fmt} reads each term's activation in the output's fuzzy set, so "
            "its numbers differ (`fuzzyc eval --semantics fuzzylite` reproduces them)"]


def linear_on(var: Variable, block_inputs: list[Variable], inputs: list[Variable],
              problems: list[str]) -> Variable:
    """`var` with its LINEAR terms' coefficients moved from `block_inputs` to `inputs` (0 on an
    input the block does not read); a coefficient on an input not in `inputs` is a problem."""
    if not np.any(var.kinds == TermKind.LINEAR) or \
            [v.name for v in block_inputs] == [v.name for v in inputs]:
        return var
    rows = linear_coefficients(var, len(block_inputs))
    names = [v.name for v in inputs]
    moved = np.zeros((var.n_terms, 1 + len(inputs)))
    moved[:, 0] = rows[:, 0]
    for i, v in enumerate(block_inputs):
        if v.name in names:
            moved[:, 1 + names.index(v.name)] = rows[:, 1 + i]
        elif np.any(rows[:, 1 + i] != 0):
            problems.append(f"a linear term of `{var.name}` has a coefficient on `{v.name}`, "
                            "which is no input of the rule list that reads it there")
    linear = np.flatnonzero(var.kinds == TermKind.LINEAR)
    params = var.params.copy()
    params[linear] = 0.0
    if len(inputs) <= 3:
        params[linear, :1 + len(inputs)] = moved[linear]
        coefficients = None
    else:
        coefficients = {int(t): moved[t] for t in linear}
    return replace(var, params=params, coefficients=coefficients)


def one_rule_base(model: Model, fmt: str) -> Model:
    """The model with its blocks merged into one rule base, for a format of one rule list:
    exact when no block reads another's output and the blocks' and/or/implication agree (each
    output keeps its block's aggregation and defuzzifier as its own choice, which the writer
    then says or refuses).  Else refused by name."""
    from .export import refuse     # export reads this module's file_variables
    if len(model.blocks) == 1:
        return model
    first = model.blocks[0]
    problems = [f"{read}: {fmt} has no chained rules" for read in chained_reads(model)]
    for rb in model.blocks[1:]:
        mine, theirs = (_operators(b) for b in (first, rb))
        if mine != theirs:
            problems.append(f"rule blocks `{first.name}` ({mine}) and `{rb.name}` ({theirs}) "
                            f"differ in operators: {fmt} has one rule list with one AND, OR "
                            "and implication method")
    refuse(model, fmt, problems)
    inputs, _ = file_variables(model)
    merged = replace(first, inputs=inputs, name="", **_stacked(model.blocks, inputs, problems))
    refuse(model, fmt, problems)
    choice = first.inference_of(0)
    merged.inference = replace(first.inference, aggregation=choice.aggregation,
                               defuzzifier=choice.defuzzifier)
    merged.output_choices = {
        v.name: (own.aggregation, own.defuzzifier)
        for rb in model.blocks for o, v in enumerate(rb.outputs)
        for own in [rb.inference_of(o)]
        if (own.aggregation, own.defuzzifier) != (choice.aggregation, choice.defuzzifier)}
    return replace(model, blocks=[merged])


def _operators(rb: RuleBase) -> str:
    inf = rb.inference
    return (f"and={inf.and_.name.lower()} or={inf.or_.name.lower()} "
            f"implication={inf.implication.name.lower()}")


def _stacked(blocks: list[RuleBase], inputs: list[Variable], problems: list[str]) -> dict:
    """The rule matrices of every block over `inputs` and every block's outputs: a block's rules
    leave the other inputs out (wildcards) and conclude nothing on the other blocks' outputs."""
    names = [v.name for v in inputs]
    parts: dict[str, list] = {k: [] for k in ("antecedents", "negated", "hedges", "consequents")}
    conditions, offset, n_out = {}, 0, sum(len(rb.outputs) for rb in blocks)
    column = 0
    for rb in blocks:
        where = [names.index(v.name) for v in rb.inputs]
        for key, fill in (("antecedents", -1), ("negated", False), ("hedges", 0)):
            block = getattr(rb, key)
            wide = np.full((rb.n_rules, len(inputs)), fill, dtype=block.dtype)
            wide[:, where] = block
            parts[key].append(wide)
        cons = np.full((rb.n_rules, n_out), -1, dtype=rb.consequents.dtype)
        cons[:, column:column + len(rb.outputs)] = rb.consequents
        parts["consequents"].append(cons)
        for r, program in rb.conditions.items():
            program = program.copy()
            clause = program[:, 0] == CondOp.CLAUSE
            program[clause, 1] = np.array(where)[program[clause, 1]]
            conditions[offset + r] = program
        offset += rb.n_rules
        column += len(rb.outputs)
    return dict(
        {key: np.concatenate(arrays) for key, arrays in parts.items()},
        outputs=[linear_on(v, rb.inputs, inputs, problems) for rb in blocks for v in rb.outputs],
        weights=np.concatenate([rb.weights for rb in blocks]),
        connective=np.concatenate([rb.connective for rb in blocks]),
        rule_locs=[loc for rb in blocks for loc in (rb.rule_locs or [None] * rb.n_rules)],
        origins=[o for rb in blocks for o in (rb.origins or [""] * rb.n_rules)],
        conditions=conditions)
