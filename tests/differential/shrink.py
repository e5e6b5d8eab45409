"""A disagreement or crash made small while it persists (`shrink`), and its cause found by
undoing one construct at a time until fuzzyc and the tool agree (`diagnose_all`).

Each round judges a few simpler variants of every case at once (one tool batch), and keeps the
first variant that fails the same way: rules, outputs, inputs and terms dropped, conditions cut
to one side, hedges and weights dropped, norms made Minimum/Maximum, numbers rounded, rows cut."""
from __future__ import annotations

import copy
import math
import time
from typing import Callable, Iterator

import numpy as np

from .judge import Verdict, judge
from .spec import Clause, Node, System, clauses, rounded

PER_ROUND = 8
MAX_ROUNDS = 40


def _same(before: Verdict, after: Verdict) -> bool:
    if before.status == "crashed":
        return after.status == "crashed" and after.message == before.message
    return after.status == before.status


def shrink(key: str, system: System, x: np.ndarray, verdict: Verdict):
    """(smaller system, its rows, its verdict), failing as `verdict` does."""
    return shrink_all(key, [(system, x, verdict)])[0]


def shrink_all(key: str, found: list[tuple[System, np.ndarray, Verdict]],
               seconds: float = 120.0):
    """Every case shrunk together, one tool batch per round, for at most `seconds`."""
    state = [[s, x, v, 0] for s, x, v in found]
    deadline = time.monotonic() + seconds
    for _ in range(MAX_ROUNDS):
        if time.monotonic() > deadline:
            break
        batch, owners = [], []
        for k, (system, x, verdict, start) in enumerate(state):
            variants = list(_variants(system, x, verdict))[start:start + PER_ROUND]
            batch += variants
            owners += [k] * len(variants)
        if not batch:
            break
        verdicts = judge(key, [s for s, _ in batch], [x for _, x in batch])
        taken = set()
        for k, (s, x), got in zip(owners, batch, verdicts):
            if k not in taken and _same(state[k][2], got):
                state[k][:] = [s, x, got, 0]
                taken.add(k)
        for k in set(owners) - taken:
            state[k][3] += PER_ROUND
    return [(s, x, v) for s, x, v, _ in state]


def _variants(system: System, x: np.ndarray, verdict: Verdict) -> Iterator[tuple]:
    if verdict.status == "disagree" and x.shape[0] > 1:
        yield system, x[verdict.rows()[:1]]
    for edit in (_drop_rules, _drop_outputs, _drop_inputs, _drop_terms, _cut_conditions,
                 _plain, _round_numbers):
        for variant in edit(system):
            if variant.rules:
                yield variant, x if len(variant.inputs) == len(system.inputs) else \
                    x[:, [i for i, v in enumerate(system.inputs)
                          if v.name in {w.name for w in variant.inputs}]]


def _copy(system: System, change: Callable[[System], None]) -> System:
    new = copy.deepcopy(system)
    change(new)
    return new


def _drop_rules(system: System) -> Iterator[System]:
    n = len(system.rules)
    if n > 2:
        yield _copy(system, lambda s: s.rules.__delitem__(slice(n // 2, None)))
        yield _copy(system, lambda s: s.rules.__delitem__(slice(0, n // 2)))
    for r in range(n if n > 1 else 0):
        yield _copy(system, lambda s, r=r: s.rules.pop(r))


def _drop_outputs(system: System) -> Iterator[System]:
    for o in range(len(system.outputs) if len(system.outputs) > 1 else 0):
        def change(s, name=system.outputs[o].name, o=o):
            s.outputs.pop(o)
            for rule in s.rules:
                rule.then = [c for c in rule.then if c.var != name]
            s.rules = [r for r in s.rules if r.then]
        yield _copy(system, change)


def _without(cond, keep: Callable[[Clause], bool]):
    """cond with the clauses `keep` rejects taken out (None when nothing is left)."""
    if isinstance(cond, Clause):
        return cond if keep(cond) else None
    left, right = _without(cond.left, keep), _without(cond.right, keep)
    if left is None or right is None:
        return left or right
    return Node(cond.op, left, right, cond.brackets)


def _drop_inputs(system: System) -> Iterator[System]:
    for i in range(len(system.inputs) if len(system.inputs) > 1 else 0):
        def change(s, name=system.inputs[i].name, i=i):
            s.inputs.pop(i)
            for rule in s.rules:
                rule.cond = _without(rule.cond, lambda c: c.var != name)
            s.rules = [r for r in s.rules if r.cond is not None]
        yield _copy(system, change)


def _drop_terms(system: System) -> Iterator[System]:
    for var in system.inputs + system.outputs:
        for t in range(len(var.terms) if len(var.terms) > 1 else 0):
            def change(s, vname=var.name, t=t):
                v = next(w for w in s.inputs + s.outputs if w.name == vname)
                term = v.terms.pop(t).name
                gone = lambda c: c.var == vname and c.term == term      # noqa: E731
                for rule in s.rules:
                    rule.cond = _without(rule.cond, lambda c: not gone(c))
                    rule.then = [c for c in rule.then if not gone(c)]
                s.rules = [r for r in s.rules if r.cond is not None and r.then]
            yield _copy(system, change)


def _cut_conditions(system: System) -> Iterator[System]:
    for r, rule in enumerate(system.rules):
        if isinstance(rule.cond, Node):
            for side in ("left", "right"):
                yield _copy(system, lambda s, r=r, side=side:
                            setattr(s.rules[r], "cond", getattr(s.rules[r].cond, side)))


def _plain(system: System) -> Iterator[System]:
    """Hedges, weights, brackets and operators made the plainest the format has."""
    fis = system.fmt == "fis"
    plain_and, plain_or = ("min", "max") if fis else ("Minimum", "Maximum")
    if any(c.hedges for rule in system.rules for c in clauses(rule.cond) + rule.then):
        def no_hedges(s):
            for rule in s.rules:
                for c in clauses(rule.cond) + rule.then:
                    c.hedges = [h for h in c.hedges if h == "any"] if "any" in c.hedges else []
        yield _copy(system, no_hedges)
    if any(rule.weight is not None for rule in system.rules):
        yield _copy(system, lambda s: [setattr(r, "weight", None) for r in s.rules])
    for field, plain in (("conjunction", plain_and), ("disjunction", plain_or),
                         ("implication", plain_and)):
        if getattr(system, field) not in (plain, ""):
            yield _copy(system, lambda s, f=field, p=plain: setattr(s, f, p))
    for o, var in enumerate(system.outputs):
        if var.aggregation not in ("", plain_or):
            yield _copy(system, lambda s, o=o: setattr(s.outputs[o], "aggregation", plain_or))
        if var.resolution is not None:
            yield _copy(system, lambda s, o=o: setattr(s.outputs[o], "resolution", None))
        if not math.isnan(var.default):
            yield _copy(system, lambda s, o=o: setattr(s.outputs[o], "default", math.nan))
    for v, var in enumerate(system.inputs + system.outputs):
        if var.lock_range:
            yield _copy(system, lambda s, v=v: setattr((s.inputs + s.outputs)[v],
                                                       "lock_range", False))


def _round_numbers(system: System) -> Iterator[System]:
    for digits in (1, 2):
        def change(s, digits=digits):
            for var in s.inputs + s.outputs:
                var.lo, var.hi = rounded(var.lo, digits), rounded(var.hi, digits)
                for t in var.terms:
                    t.params = [rounded(p, digits) for p in t.params]
        new = _copy(system, change)
        if all(v.lo < v.hi for v in new.inputs + new.outputs) and new != system:
            yield new


# ---------------------------------------------------------------------- causes
def _undo(system: System) -> Iterator[tuple[str, System | None, np.ndarray | None]]:
    """(cause, the system without that construct) in the order causes are told apart."""
    fis = system.fmt == "fis"
    for var in system.outputs:
        if var.resolution is not None:
            yield "the file's defuzzifier resolution", _copy(
                system, lambda s: [setattr(v, "resolution", None) for v in s.outputs]), None
            break
    if any(v.lock_range for v in system.inputs + system.outputs):
        yield "lock-range", _copy(system, lambda s: [setattr(v, "lock_range", False)
                                                     for v in s.inputs + s.outputs]), None
    if any(not math.isnan(v.default) for v in system.outputs):
        yield "a numeric default", _copy(system, lambda s: [setattr(v, "default", math.nan)
                                                            for v in s.outputs]), None
    if any(t.shape.lower() == "linear" for v in system.outputs for t in v.terms):
        def constants(s):
            for v in s.outputs:
                for t in v.terms:
                    if t.shape.lower() == "linear":
                        t.shape, t.params = ("constant" if fis else "Constant"), t.params[-1:]
        yield "a Linear term", _copy(system, constants), None
    for shape in sorted({t.shape for v in system.inputs + system.outputs for t in v.terms}
                        - {"Triangle", "trimf", "Constant", "constant", "Linear", "linear"}):
        yield f"shape {shape}", _copy(system, lambda s, shape=shape: _as_triangles(s, shape)), \
            None
    names = sorted({v.defuzzifier for v in system.outputs})
    yield f"defuzzifier {' '.join(names)}", _copy(system, lambda s: [
        setattr(v, "defuzzifier", ("centroid" if fis else "Centroid") if not s.sugeno else
                ("wtaver" if fis else "WeightedAverage")) for v in s.outputs]), None
    for name, variant in (("a hedge", list(_plain(system))[:1]),):
        if variant and any(c.hedges for r in system.rules for c in clauses(r.cond) + r.then):
            yield name, variant[0], None
    for field in ("conjunction", "disjunction", "implication"):
        plain = ("min" if fis else "Minimum") if field != "disjunction" else \
            ("max" if fis else "Maximum")
        if getattr(system, field) not in (plain, ""):
            yield f"{field} {getattr(system, field)}", _copy(
                system, lambda s, f=field, p=plain: setattr(s, f, p)), None
    for var in system.outputs:
        if var.aggregation not in ("", "max", "Maximum"):
            yield f"aggregation {var.aggregation}", _copy(system, lambda s: [
                setattr(v, "aggregation", "max" if fis else "Maximum") for v in s.outputs]), None
            break
    if any(r.weight is not None for r in system.rules):
        yield "a rule weight", _copy(system, lambda s: [setattr(r, "weight", None)
                                                        for r in s.rules]), None


def _as_triangles(system: System, shape: str) -> None:
    """Every term of `shape` replaced by the triangle over its variable's range."""
    for var in system.inputs + system.outputs:
        for t in var.terms:
            if t.shape == shape:
                t.shape = "trimf" if system.fmt == "fis" else "Triangle"
                t.params = [var.lo, rounded((var.lo + var.hi) / 2), var.hi]


def diagnose_all(key: str, found: list[tuple[System, np.ndarray, Verdict]]) -> list[str]:
    """Per case the first construct whose undoing makes fuzzyc and the tool agree (or the
    crash); every case's variants judged in one tool batch."""
    batch, owners = [], []
    for k, (system, x, verdict) in enumerate(found):
        if verdict.status != "crashed":
            for cause, variant, _ in _undo(system):
                batch.append((cause, variant, x))
                owners.append(k)
    verdicts = judge(key, [v for _, v, _ in batch], [x for _, _, x in batch])
    causes: list[str | None] = [f"crash: {v.message}" if v.status == "crashed" else None
                                for _, _, v in found]
    for k, (cause, _, _), got in zip(owners, batch, verdicts):
        if causes[k] is None and got.status == "agree":
            causes[k] = cause
    for k, (system, _, _) in enumerate(found):
        if causes[k] is None:
            shapes = sorted({t.shape for v in system.inputs + system.outputs for t in v.terms})
            defuzz = sorted({v.defuzzifier for v in system.outputs})
            causes[k] = f"not found by undoing (shapes {' '.join(shapes)}; {' '.join(defuzz)})"
    return causes
