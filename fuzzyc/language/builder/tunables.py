"""The `tune { ... }` section: which written numbers `fuzzyc tune` may move, and within what.

Each line names targets and one bound: `e.NB.b in [-1.2, -0.8]` (one number),
`e.NB in +/- 0.2` (every number of a term, each within 0.2 of its written value), `e.*.center`
(that number of every term), `e` (every number of every term), `r1.weight` (a named rule's
weight), `GE` (a param).  What the semantics needs is checked on the whole box the bounds
allow, so no point the tuner may reach is an invalid file: a term's break points stay ordered,
its widths and slopes positive, its peak in its variable's range, and a variable whose terms
peak in increasing order (a partition) keeps that order.
"""
from __future__ import annotations

import math
from dataclasses import replace

from ...semantics.model import RuleBase, SourceLoc, TermKind, Variable
from ...semantics.tunable import ORDERED, POSITIVE, TunedNumber, parameter_names, slots
from ..syntax import Name, Num, Stmt, TermDef
from .terms import term_core


class TunablesBuilder:
    """The `tune` statements (a part of `Builder`): recorded as they come, resolved once the
    rule blocks are built (`_tunables`)."""

    def _stmt_tune(self, s: Stmt) -> None:
        if getattr(self, "tune_statements", None) is None:
            self.tune_statements = []
        self.tune_statements.append(s)

    def _tunables(self, statements: list[Stmt], blocks: list[RuleBase]) -> list[TunedNumber]:
        tunes = getattr(self, "tune_statements", None) or []
        if not tunes:
            return []
        written = _WrittenNumbers(statements)
        found: dict[tuple, TunedNumber] = {}
        for s in tunes:
            for item in s.data["items"]:
                bound = self._tune_bound(item["bound"])
                for path in item["paths"]:
                    for number in self._tune_target(path, bound, written, blocks):
                        number = replace(number, section=(s.loc, s.end),
                                         spread=bound is not None and bound[0] == "spread")
                        key = (number.kind, number.var, number.term, number.index,
                               number.rule, number.param)
                        if key in found:
                            first = found[key].loc
                            self.error(number.loc, f"`{number.target}` is already tuned at line "
                                                   f"{first.line}; give each number one bound")
                            continue
                        found[key] = number
        numbers = list(found.values())
        if not self.rep.diagnostics:
            self._check_tune_box(numbers, blocks)
        return numbers

    # ---- bounds
    def _tune_bound(self, bound) -> tuple[str, float, float, SourceLoc] | None:
        """("abs", lo, hi) or ("spread", d, d); None when reported as empty."""
        if bound[0] == "spread":
            d: Num = bound[1]
            if not d.value > 0:
                self.error(d.loc, f"the spread +/- {d.value:g} is empty: write a number above 0")
                return None
            return ("spread", d.value, d.value, d.loc)
        lo, hi = bound
        if not lo.value < hi.value:
            fix = ("write the lower bound first" if lo.value > hi.value
                   else "the upper bound must be above the lower")
            self.error(lo.loc, f"the bounds [{lo.value:g}, {hi.value:g}] are empty; {fix}")
            return None
        return ("abs", lo.value, hi.value, lo.loc)

    # ---- names
    def _tune_target(self, path: list[Name], bound, written: "_WrittenNumbers",
                 blocks: list[RuleBase]) -> list[TunedNumber]:
        head = path[0]
        if head.text in self.broken:
            return []
        if head.text in self.vars:
            return self._tuned_term_numbers(path, bound, written)
        if head.text in self.params:
            if len(path) > 1:
                self.error(path[1].loc, f"`{head.text}` is a param, one number: "
                                        f"write `{head.text}`")
                return []
            num = written.params.get(head.text)
            return self._tuned_numbers(bound, [TunedNumber(
                "param", head.text, num.value, 0.0, 0.0, loc=head.loc, token=num.loc,
                param=head.text)])
        if head.text in written.rules:
            return self._tuned_weight(path, bound, written.rules[head.text], blocks)
        self.error(head.loc, f"`{head.text}` is no variable, param or named rule of this file; "
                             "`tune` names what it moves as VAR.TERM.PARAMETER, RULE.weight or "
                             "PARAM")
        return []

    def _tuned_term_numbers(self, path: list[Name], bound, written: "_WrittenNumbers"):
        var = self.vars[path[0].text]
        if len(path) > 3:
            self.error(path[3].loc, "a tuned term number is VAR.TERM.PARAMETER: one dot too many")
            return []
        names = var.term_names()
        if len(path) == 1 or path[1].text == "*":
            terms = names
        elif path[1].text in names:
            terms = [path[1].text]
        else:
            self.error(path[1].loc, f"`{var.name}` has no term `{path[1].text}`: known: "
                                    f"{' '.join(names) or 'none'}")
            return []
        where = path[0].loc
        out = []
        for term in terms:
            defn = written.terms.get((var.name, term))
            if defn is None or isinstance(defn, str):
                why = defn or ("it is made by a numeric conclusion; declare it in `terms` to "
                               "tune it")
                self.error(where, f"term `{term}` of `{var.name}` has no numbers of its own to "
                                  f"tune: {why}")
                return []
            term_def, shared = defn
            if shared:
                self.error(where, f"the terms of `{var.name}` are written together with those "
                                  f"of {shared} (one `terms` statement): tuning them would move "
                                  "both; give each variable its own `terms` statement")
                return []
            spellings = parameter_names(term_def.shape, len(term_def.args))
            if len(path) == 3 and path[2].text != "*":
                wanted = path[2].text
                picked = [i for i, s in enumerate(spellings) if wanted in s]
                if not picked:
                    said = " ".join(s[0] for s in spellings)
                    self.error(path[2].loc, f"{term_def.shape} `{term}` has no parameter "
                                            f"`{wanted}`: known: {said}")
                    return []
            else:
                picked = list(range(len(term_def.args)))
            for i in picked:
                num = term_def.args[i]
                out.append(TunedNumber(
                    "term", f"{var.name}.{term}.{spellings[i][0]}", num.value, 0.0, 0.0,
                    loc=where, token=num.loc, var=var.name, term=term, shape=term_def.shape,
                    index=i, slots=() if term_def.shape in ("linear", "discrete")
                    else slots(term_def.shape, i)))
        return self._tuned_numbers(bound, out)

    def _tuned_weight(self, path: list[Name], bound, stmt: Stmt, blocks: list[RuleBase]):
        name = path[0].text
        if len(path) != 2 or path[1].text != "weight":
            self.error(path[-1].loc, f"`{name}` is a rule: tune its weight as `{name}.weight`")
            return []
        label = f"rule {name}"
        places = [(b, r) for b, rb in enumerate(blocks) for r, origin in enumerate(rb.origins)
                  if label in origin.split("; ")]
        if len(places) != 1 or blocks[places[0][0]].origins[places[0][1]] != label:
            self.error(path[0].loc, f"rule `{name}` shares its place in the rule matrix with "
                                    "another rule (same condition and weight, other outputs): "
                                    "tuning its weight would move both; give it its own weight")
            return []
        b, r = places[0]
        num: Num | None = stmt.data["weight"]
        numbers = self._tuned_numbers(bound, [TunedNumber(
            "weight", f"{name}.weight", num.value if num else 1.0, 0.0, 0.0, loc=path[0].loc,
            token=num.loc if num else None, insert_at=None if num else stmt.end, rule=name,
            block=b, rule_index=r)])
        for n in numbers:
            if not (0 <= n.lo and n.hi <= 1):
                self.error(n.loc, f"a rule weight must lie in [0, 1]: the bounds of "
                                  f"`{n.target}` [{n.lo:g}, {n.hi:g}] leave it")
                return []
        return numbers

    def _tuned_numbers(self, bound, numbers: list[TunedNumber]) -> list[TunedNumber]:
        """The numbers with their bounds; a written value outside its bound is an error."""
        if bound is None:
            return []
        how, a, b, where = bound
        out = []
        for n in numbers:
            lo, hi = (n.value - a, n.value + b) if how == "spread" else (a, b)
            if not lo <= n.value <= hi:
                self.error(where, f"`{n.target}` is {n.value:g} as written, outside its bounds "
                                  f"[{lo:g}, {hi:g}]")
                continue
            out.append(replace(n, lo=lo, hi=hi))
        return out

    # ---- what the semantics needs, on the whole box
    def _check_tune_box(self, numbers: list[TunedNumber], blocks: list[RuleBase]) -> None:
        by_term: dict[tuple[str, str], list[TunedNumber]] = {}
        for n in numbers:
            if n.kind == "term":
                by_term.setdefault((n.var, n.term), []).append(n)
        corners: dict[str, dict[str, tuple]] = {}
        for (var_name, term), tuned in by_term.items():
            var = _model_variable(blocks, var_name)
            if var is None:
                continue
            t = var.index(term)
            shape = tuned[0].shape
            written = list(var.term_numbers(t)) if shape in ("linear", "discrete") else \
                _written(shape, var.params[t])
            lo, hi = list(written), list(written)
            for n in tuned:
                lo[n.index], hi[n.index] = n.lo, n.hi
            problem = _box_problem(shape, lo, hi)
            if problem:
                self.error(tuned[0].loc, f"the bounds of `{var_name}.{term}` let {problem}; "
                                         "narrow them")
                continue
            if shape not in ("linear", "discrete"):
                kind = TermKind(int(var.kinds[t]))
                low, high = _params(shape, var.params[t], lo), _params(shape, var.params[t], hi)
                if term_core(kind, low)[1] < var.lo or term_core(kind, high)[0] > var.hi:
                    self.error(tuned[0].loc, f"the bounds of `{var_name}.{term}` let its peak "
                                             f"leave the range [{var.lo:g}, {var.hi:g}] of "
                                             f"`{var_name}`; narrow them")
                    continue
                corners.setdefault(var_name, {})[term] = (low, high, tuned[0].loc)
        for var_name, moved in corners.items():
            self._check_tuned_partition(_model_variable(blocks, var_name), moved)

    def _check_tuned_partition(self, var: Variable, moved: dict[str, tuple]) -> None:
        """Terms whose peaks are in increasing order as written stay in that order."""
        peaks = var.peaks()
        if len(peaks) < 2 or not all(math.isfinite(p) for p in peaks) or \
                not all(p < q for p, q in zip(peaks, peaks[1:])):
            return
        low, high = _peaks_at(var, moved, 0), _peaks_at(var, moved, 1)
        for t in range(len(peaks) - 1):
            if high[t] >= low[t + 1] and (var.names[t] in moved or var.names[t + 1] in moved):
                name = var.names[t] if var.names[t] in moved else var.names[t + 1]
                self.error(moved[name][2], f"the bounds let `{var.name}.{var.names[t]}` peak at "
                                           f"{high[t]:g}, at or past `{var.names[t + 1]}` "
                                           f"({low[t + 1]:g}): the terms of `{var.name}` stay "
                                           "in their order; narrow the bounds")
                return


class _WrittenNumbers:
    """Where the file writes each number the tune section may name: term definitions by
    (variable, term) -> (TermDef, the other variables of its `terms` statement) or the reason
    it has none; params by name; named rule statements by name."""

    def __init__(self, statements: list[Stmt]):
        self.terms: dict[tuple[str, str], tuple[TermDef, str] | str] = {}
        self.params: dict[str, Num] = {}
        self.rules: dict[str, Stmt] = {}
        for s in statements:
            self._read(s)

    def _read(self, s: Stmt) -> None:
        if s.kind == "block":
            for inner in s.data["statements"]:
                self._read(inner)
        elif s.kind == "param":
            self.params[s.data["name"].text] = s.data["value"]
        elif s.kind == "rule" and s.data["name"] is not None:
            self.rules[s.data["name"].text] = s
        elif s.kind == "terms":
            names = [n.text for n in s.data["names"]]
            kind, *rest = s.data["terms"]
            for var in names:
                others = ", ".join(f"`{n}`" for n in names if n != var)
                if kind == "uniform":
                    for term in rest[0]:
                        self.terms[(var, term.text)] = (
                            "it belongs to a `uniform` partition, whose numbers are not "
                            "written; write the terms out to tune them")
                    continue
                for term in rest[0]:
                    self.terms[(var, term.name.text)] = (term, others)


def _model_variable(blocks: list[RuleBase], name: str) -> Variable | None:
    for rb in blocks:
        for v in rb.inputs + rb.outputs:
            if v.name == name:
                return v
    return None


def _written(shape: str, params) -> list[float]:
    """A term's numbers as written, from its model params."""
    count = len(parameter_names(shape, 4))
    return [float(params[slots(shape, i)[0]]) for i in range(count)]


def _params(shape: str, params, numbers: list[float]) -> list[float]:
    """The model params of a term written as `numbers`."""
    out = [float(p) for p in params]
    for i, value in enumerate(numbers):
        for slot in slots(shape, i):
            out[slot] = value
    return out


def _box_problem(shape: str, lo: list[float], hi: list[float]) -> str:
    names = parameter_names(shape, len(lo))
    for i in POSITIVE.get(shape, ()):
        if not lo[i] > 0:
            return f"its {names[i][0]} reach {lo[i]:g}; it must stay above 0"
    for i, j, strict in ORDERED.get(shape, ()):
        if hi[i] > lo[j] or (strict and hi[i] == lo[j]):
            return (f"{names[i][0]} (up to {hi[i]:g}) pass {names[j][0]} (down to {lo[j]:g}); "
                    f"a {shape}'s numbers stay in order")
    if shape == "sigmoid" and lo[1] <= 0 <= hi[1]:
        return "its slope reach 0"
    return ""


def _peaks_at(var: Variable, moved: dict[str, tuple], corner: int):
    params = var.params.copy()
    for term, corners in moved.items():
        params[var.index(term)] = corners[corner]
    return replace(var, params=params).peaks()
