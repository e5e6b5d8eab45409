"""Rule conditions as front ends read them (and/or/not trees over clauses) -> the model's form.

Every front end (the .fz builder, the FCL/FLL rule text) resolves its clauses to names and term
indices and hands the tree to `premise`, which keeps the plain matrix row wherever the rule is a
flat conjunction or disjunction (the engine's and the C back end's fast path) and compiles
anything else to the postfix clause program of `RuleBase.conditions` (semantics in
`fuzzyc.semantics.model`).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..semantics.model import CondOp, Connective, Hedge, weight_bits

Leaf = tuple[str, tuple[int, bool, Hedge]]     # input name, (term, negated, hedge)
Program = tuple[tuple[CondOp, str, int, Hedge], ...]   # postfix steps by input name
CONCLUDED = {"concluded": 1, "carried": 0}     # Cond op -> CondOp.CONCLUDED's term column
ANY = -1   # the clause `x is any` (truth 1), a wildcard term index (in a program too)


@dataclass
class Cond:
    """A condition: op "is" (a clause, in `leaf`), "and"/"or" (over `parts`), "not" (one part),
    "hedge" (`hedge` on one part), "concluded"/"carried" (`hedge` said on the rule's own
    conclusion / an earlier conclusion of its FIS row: CondOp.CONCLUDED), "weight" (the part
    times `weight`: fuzzylite's rule weight under the hedges of a conclusion, CondOp.WEIGHT)."""
    op: str
    parts: list[Cond] = field(default_factory=list)
    leaf: Leaf | None = None
    hedge: Hedge = Hedge.NONE
    weight: float = 1.0          # op "weight": the part times this (CondOp.WEIGHT)


def premise(cond: Cond) -> tuple[dict, Connective, Program | None]:
    """(clauses by input, connective, None) when the condition is flat: one connective, `not`
    only on single clauses, each input at most once; else ({}, AND, its clause program)."""
    cond = _simplified(cond)
    if cond.op in ("hedge", "weight", *CONCLUDED):
        return {}, Connective.AND, tuple(_postfix(cond))
    leaves = [cond] if cond.op == "is" else cond.parts
    names = [p.leaf[0] for p in leaves if p.op == "is"]
    if len(names) == len(leaves) and len(set(names)) == len(names):
        connective = Connective.OR if cond.op == "or" else Connective.AND
        return dict(p.leaf for p in leaves), connective, None
    return {}, Connective.AND, tuple(_postfix(cond))


def _simplified(cond: Cond) -> Cond:
    """Single-part and/or dropped, a connective inside the same one merged into it (both fold
    left to right), `not` moved onto a single clause and double `not` cancelled."""
    if cond.op == "is":
        return cond
    if cond.op in CONCLUDED:
        return Cond(cond.op, [_simplified(cond.parts[0])], hedge=cond.hedge)
    if cond.op == "weight":
        return Cond("weight", [_simplified(cond.parts[0])], weight=cond.weight)
    if cond.op == "hedge":      # onto a plain clause, where it is the clause's own hedge
        inner = _simplified(cond.parts[0])
        if inner.op == "is" and inner.leaf[1][2] == Hedge.NONE and not inner.leaf[1][1]:
            name, (term, _, _) = inner.leaf
            return Cond("is", leaf=(name, (term, False, cond.hedge)))
        return Cond("hedge", [inner], hedge=cond.hedge)
    if cond.op == "not":
        inner = _simplified(cond.parts[0])
        if inner.op == "is":
            name, (term, negated, hedge) = inner.leaf
            return Cond("is", leaf=(name, (term, not negated, hedge)))
        return inner.parts[0] if inner.op == "not" else Cond("not", [inner])
    parts = [_simplified(p) for p in cond.parts]
    if len(parts) == 1:
        return parts[0]
    merged = parts[:1] if parts[0].op != cond.op else list(parts[0].parts)
    return Cond(cond.op, merged + parts[1:])


def _postfix(cond: Cond):
    if cond.op == "is":
        name, (term, negated, hedge) = cond.leaf
        yield CondOp.CLAUSE, name, term, hedge
        if negated:
            yield CondOp.NOT, "", 0, Hedge.NONE
    elif cond.op == "not":
        yield from _postfix(cond.parts[0])
        yield CondOp.NOT, "", 0, Hedge.NONE
    elif cond.op == "hedge":
        yield from _postfix(cond.parts[0])
        yield CondOp.HEDGE, "", 0, cond.hedge
    elif cond.op == "weight":
        yield from _postfix(cond.parts[0])
        yield CondOp.WEIGHT, "", weight_bits(cond.weight), Hedge.NONE
    elif cond.op in CONCLUDED:
        yield from _postfix(cond.parts[0])
        yield CondOp.CONCLUDED, "", CONCLUDED[cond.op], cond.hedge
    else:
        op = CondOp.AND if cond.op == "and" else CondOp.OR
        yield from _postfix(cond.parts[0])
        for part in cond.parts[1:]:
            yield from _postfix(part)
            yield op, "", 0, Hedge.NONE


def program_array(program: Program, in_index: dict[str, int]) -> np.ndarray:
    """The program with inputs by index: the (K, 4) int array of `RuleBase.conditions`."""
    return np.array([(int(op), in_index[name] if op == CondOp.CLAUSE else 0, term, int(hedge))
                     for op, name, term, hedge in program], dtype=np.int64).reshape(-1, 4)


def resolve_any(clauses: dict, connective: Connective,
                weight: float) -> tuple[dict, Connective, float]:
    """A flat rule's clauses, connective and weight with `x is any` (fuzzylite's truth 1) said
    exactly by wildcards: every norm has 1 as the absorbing element of s-norms and the neutral
    one of t-norms, and 0 the other way round, so `any` drops out of an and-rule and makes an
    or-rule fire 1; `not any` (truth 0) the reverse.  One clause or none: `and`, as every
    front end reads it."""
    truths = {not negated for term, negated, _ in clauses.values() if term == ANY}
    wildcard = (ANY, False, Hedge.NONE)
    if connective == Connective.AND and False in truths:    # and `not any`: never fires
        clauses, weight = {name: wildcard for name in clauses}, 0.0
    elif connective == Connective.OR and True in truths:    # or `any`: always fires
        clauses = {name: wildcard for name in clauses}
    else:
        clauses = {name: wildcard if c[0] == ANY else c for name, c in clauses.items()}
    if sum(term != ANY for term, _, _ in clauses.values()) < 2:
        connective = Connective.AND
    return clauses, connective, weight
