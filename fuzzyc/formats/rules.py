"""Rules of FCL and FLL (the same `if ... then ... with w` shape): lark tree -> builder `RuleSpec`.

A flat conjunction or disjunction stays a matrix row; mixed and/or, `not` around a compound
condition and an input named twice make a clause program (`fuzzyc.language.conditions`).  A hedge the
model lacks is reported.
fuzzylite's `x is any` (truth 1) is said exactly with wildcards: every norm has 1 as the
absorbing element of s-norms and the neutral one of t-norms, and 0 the other way round, so
`any` drops out of an and-rule and makes an or-rule fire 1; `not any` (truth 0) the reverse
(language.conditions.resolve_any, shared with .fz, where `x is any` means the same).
"""
from __future__ import annotations

import functools
import math
from collections.abc import Callable
from importlib import resources

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from ..language.builder import RuleSpec
from ..language.conditions import ANY, Cond, premise, resolve_any
from ..errors import Reporter, shown_char, suggest
from ..language.limits import MAX_HEDGES, MAX_NESTING
from ..semantics.model import Hedge, SourceLoc
from ..semantics.operators import HEDGES as HEDGE_RECORDS
from .common import Collected

LocOf = Callable[[Token], SourceLoc]


@functools.lru_cache(maxsize=1)
def fcl_lark() -> Lark:
    grammar = resources.files("fuzzyc").joinpath("language/grammar/fcl.lark").read_text()
    return Lark(grammar, parser="lalr", start=["start", "rule_text"], propagate_positions=True)


def syntax_error(exc: UnexpectedInput, rep: Reporter, loc: SourceLoc) -> None:
    """One readable diagnostic for a lark error at `loc`."""
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken)
                                          and exc.token.type == "$END"):
        rep.error(loc, "the text ends too early: " + _expected(exc.expected))
    elif isinstance(exc, UnexpectedToken):
        rep.error(loc, f"unexpected `{exc.token}`: " + _expected(exc.expected))
    elif isinstance(exc, UnexpectedCharacters):
        rep.error(loc, f"unexpected character {shown_char(exc.char)}")
    else:  # pragma: no cover - lark has no other kinds
        rep.error(loc, str(exc))


READABLE = {"NAME": "a name", "SIGNED_NUMBER": "a number", "INT": "a rule number",
            "LPAR": "`(`", "RPAR": "`)`", "SEMICOLON": "`;`", "COLON": "`:`", "COMMA": "`,`",
            "NOT": "`NOT`", "FUNCTION": "a function term", "NC": "`NC`", "$END": "the end"}


def _expected(names) -> str:
    shown = sorted(READABLE.get(n, f"`{n.strip('_')}`") for n in names)[:10]
    return "expected " + ", ".join(shown)


def rule_from_tree(tree: Tree, got: Collected, loc_of: LocOf, hedges: dict[str, Hedge],
                   origin: str, loc: SourceLoc) -> list[RuleSpec]:
    """A `rule_text` tree as rules of the model (none after reporting why it cannot be).

    Hedged conclusions as fuzzylite computes them (fuzzylite 6 and pyfuzzylite 8 alike): a
    conclusion's hedges act on the rule's activation, and what they make of it carries on to
    the conclusions after it; so each run of conclusions under the same hedges becomes a rule
    of its own whose condition is hedged so."""
    rep = got.rep
    condition, *rest = tree.children
    weight_tree = rest.pop() if rest and rest[-1].data == "weight" else None
    too_deep = _first_too_deep(condition)
    if too_deep is not None:
        rep.error(loc_of(too_deep), f"a rule condition nested more than {MAX_NESTING} "
                                    "parentheses deep (fuzzyc.language.limits.MAX_NESTING); write it "
                                    "with fewer, or as several rules")
        return []
    cond = _condition(condition, got, loc_of, hedges)
    ok = cond is not None
    conclusions: dict[str, int] = {}
    carried: list[Hedge] = []
    chains: dict[str, tuple[Hedge, ...]] = {}     # output -> the hedges its activation takes
    for concl in rest:
        name, *words = concl.children
        term = _conclusion(name, words, got, loc_of)
        said = _hedges(words[:-1], hedges, loc_of, rep)
        if term is None or said is None:
            ok = False
        elif name.value in conclusions:
            rep.error(loc_of(name), f"`{name}` is concluded twice in one rule; write one "
                                    "conclusion on it")
            ok = False
        elif len(carried) + len(said) > MAX_HEDGES:     # each carried hedge nests the condition
            rep.error(loc_of(words[0]), f"the conclusions of a rule carry more than {MAX_HEDGES} "
                                        "hedges in all (fuzzyc.language.limits.MAX_HEDGES)")
            ok = False
        else:
            conclusions[name.value] = term
            carried += said
            chains[name.value] = tuple(carried)
    weight = 1.0
    if weight_tree is not None:
        token = weight_tree.children[0].children[0]
        weight = float(token)
        if not 0.0 <= weight <= 1.0:
            rep.error(loc_of(token), f"a rule weight must lie in [0, 1], got {weight:g}")
            ok = False
    if not ok:
        return []
    rules = []
    for chain in dict.fromkeys(chains.values()):
        # fuzzylite hedges the weighted activation, h(w a); for powers h(w a) = w^p h(a), so
        # the model's rule weighs its hedged condition by w^p (p the chain's exponents'
        # product); under seldom or extremely (fuzzylite's S-curve, no power) the weight
        # stays inside the hedges, a CondOp.WEIGHT step, and the rule's own weight is 1
        powers = all(HEDGE_RECORDS[h].exponent is not None for h in chain)
        hedged = cond if powers or weight == 1.0 else Cond("weight", [cond], weight=weight)
        for hedge in chain:
            hedged = Cond("hedge", [hedged], hedge=hedge)
        mine = {out: conclusions[out] for out, c in chains.items() if c == chain}
        if weight != 1.0 and powers:
            hedged_weight = weight ** math.prod(HEDGE_RECORDS[h].exponent for h in chain)
        else:
            hedged_weight = weight if powers else 1.0
        rules.append(_rule(hedged, mine, hedged_weight, loc, origin))
    return rules


def _rule(cond: Cond, conclusions: dict[str, int], weight: float, loc: SourceLoc,
          origin: str) -> RuleSpec:
    rule_clauses, connective, program = premise(cond)
    if program is None:
        rule_clauses, connective, weight = resolve_any(rule_clauses, connective, weight)
    return RuleSpec(rule_clauses, connective, conclusions, weight, loc, origin, program)


def _hedges(words: list[Token], hedges: dict[str, Hedge], loc_of: LocOf,
            rep: Reporter) -> list[Hedge] | None:
    """Hedge words in the order they apply (the one nearest the term first), or None after
    reporting one the model lacks or more than MAX_HEDGES (each one nests the condition)."""
    if len(words) > MAX_HEDGES:
        rep.error(loc_of(words[MAX_HEDGES]), f"{len(words)} hedges on one clause: at most "
                                             f"{MAX_HEDGES} (fuzzyc.language.limits.MAX_HEDGES)")
        return None
    for word in words:
        if word.value.lower() not in hedges:
            rep.error(loc_of(word), f"hedge `{' '.join(w.value for w in words)}` is not "
                                    f"supported: {hedge_message(word.value.lower(), hedges)}")
            return None
    return [hedges[w.value.lower()] for w in reversed(words)]


def _first_too_deep(condition: Tree) -> Token | None:
    """A token where the first group nested more than MAX_NESTING parentheses deep starts
    (inside its `(`), found without recursing: what follows recurses through the condition."""
    stack = [(condition, 0)]        # the whole condition is an or_cond too: depth 0
    while stack:
        node, depth = stack.pop()
        if depth > MAX_NESTING:
            return Token("NAME", "", line=node.meta.line, column=node.meta.column)
        stack.extend((child, depth + (child.data == "or_cond")) for child in node.children
                     if isinstance(child, Tree))
    return None


def _condition(node: Tree, got: Collected, loc_of: LocOf, hedges: dict[str, Hedge]) -> Cond | None:
    """The condition tree by names, or None after reporting every clause that cannot be."""
    while node.data in ("or_cond", "and_cond") and len(node.children) == 1:
        node = node.children[0]     # `(...)` without a connective: no level of recursion
    if node.data == "is_clause":
        name, *words = node.children
        negated = bool(words) and words[0].type == "NOT"
        said = _hedges(words[negated:-1], hedges, loc_of, got.rep)
        clause = _clause(name, words[-1], said, got, loc_of)
        if clause is None:
            return None
        # the hedge nearest the term is the clause's own, the others apply after it, then `not`
        cond = Cond("is", leaf=(name.value, clause))
        for hedge in said[1:]:
            cond = Cond("hedge", [cond], hedge=hedge)
        return Cond("not", [cond]) if negated else cond
    parts = [_condition(child, got, loc_of, hedges) for child in node.children]
    if None in parts:
        return None
    op = {"and_cond": "and", "or_cond": "or", "not_cond": "not"}[node.data]
    return Cond(op, parts)


def _clause(name: Token, term: Token, said: list[Hedge] | None, got: Collected,
            loc_of: LocOf):
    """(term index, not negated, the hedge nearest the term) of `name is ... term`."""
    rep = got.rep
    # an output read by a rule chains the blocks (Collected.model puts the rule after them)
    var = got.inputs.get(name.value) or got.outputs.get(name.value)
    if var is None:
        rep.error(loc_of(name), f"no variable `{name}`: "
                                f"{suggest(name.value, [*got.inputs, *got.outputs])}")
        return None
    if said is None:
        return None
    if not said and term.value.lower() == "any" and "any" not in var.term_names():
        return ANY, False, Hedge.NONE
    index = var.term_index(term.value, loc_of(term), rep)
    return None if index is None else (index, False, said[0] if said else Hedge.NONE)


def hedge_message(word: str, hedges: dict[str, Hedge]) -> str:
    if not hedges:
        return "this format carries no hedge"
    return (f"the model carries one of {', '.join(hedges)} (one hedge per clause, applied "
            "before `not`)")


def _conclusion(name: Token, words: list[Token], got: Collected, loc_of: LocOf) -> int | None:
    """The term index of `name is [hedges] term` (the hedges are the caller's)."""
    rep = got.rep
    var = got.outputs.get(name.value)
    if var is None:
        rep.error(loc_of(name), f"no output variable `{name}`: "
                                f"{suggest(name.value, list(got.outputs))}")
        return None
    return var.term_index(words[-1].value, loc_of(words[-1]), rep)
