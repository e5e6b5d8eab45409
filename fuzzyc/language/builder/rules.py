"""Rules, tables and rule blocks: clauses resolved to term indices, `rule`, 2-D and list
tables, `inference` and `block`, and the rule matrices the model stores (shared with the
importers: RuleSpec, assemble_rulebase, merge_rules)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..conditions import ANY, Cond, Program, premise, program_array, resolve_any
from ...display import plural
from ...errors import suggest
from ...engine.membership import monotonic
from ...semantics.model import (CondOp, Connective, Defuzzifier, Hedge, Inference,
                     RuleBase, SourceLoc, TermKind, Variable)
from ...semantics import operators
from ..syntax import Clause, Condition, Name, Num, Stmt
from .terms import LinguisticVar, to_variable

# the words of `inference` settings and of hedges: the operator registry's
INFERENCE_VALUES = {key: operators.format_words(operators.REGISTRIES[key], "fz")
                    for key in ("and", "or", "implication", "aggregation", "defuzzify")}

INFERENCE_FIELD = {"and": "and_", "or": "or_", "implication": "implication",
                   "aggregation": "aggregation", "defuzzify": "defuzzifier"}

# the peak-based defuzzifiers (the registry's "peaks" family) read a linear term's value
LINEAR_DEFUZZIFIERS = operators.members(operators.DEFUZZIFIERS, lambda rec: rec.family == "peaks")

HEDGES = {None: Hedge.NONE, **{rec.word: h for h, rec in operators.HEDGES.items()
                               if h != Hedge.NONE}}


@dataclass
class RuleSpec:
    """One rule by names, as a front end collects it, before it becomes rows of the matrices."""
    clauses: dict[str, tuple[int, bool, Hedge]]   # input name -> (term, negated, hedge)
    connective: Connective
    conclusions: dict[str, int]                   # output name -> term index
    weight: float
    loc: SourceLoc
    origin: str
    program: Program | None = None                # a nested condition (clauses is then {})

    def connectives(self) -> set[Connective]:
        """The connectives the rule needs a norm for (those joining two or more parts)."""
        if self.program is not None:
            return {Connective.AND if step[0] == CondOp.AND else Connective.OR
                    for step in self.program if step[0] in (CondOp.AND, CondOp.OR)}
        return {self.connective} if len(self.clauses) > 1 else set()


@dataclass
class BlockSpec:
    """A rule block being assembled: the file's top level, or a `block NAME { ... }`."""
    name: str
    loc: SourceLoc | None
    inference: Inference = field(default_factory=Inference)
    rules: list[RuleSpec] = field(default_factory=list)
    # output name -> its own aggregation and/or defuzzifier, by Inference field
    choices: dict[str, dict[str, Any]] = field(default_factory=dict)

    def reads(self) -> set[str]:
        return {name for r in self.rules
                for name in (r.clauses if r.program is None else [p[1] for p in r.program])
                if name}

    def writes(self) -> set[str]:
        return {name for r in self.rules for name in r.conclusions}

    def inference_of(self, output: str) -> Inference:
        return replace(self.inference, **self.choices.get(output, {}))


def assemble_rulebase(inputs: list[Variable], outputs: list[Variable], rules: list[RuleSpec],
                      inference: Inference) -> RuleBase:
    """The rule matrices of the IR from rules written by name (shared by every front end)."""
    in_index = {v.name: i for i, v in enumerate(inputs)}
    out_index = {v.name: i for i, v in enumerate(outputs)}
    n = len(rules)
    ante = np.full((n, len(inputs)), -1, dtype=np.int64)
    negated = np.zeros((n, len(inputs)), dtype=bool)
    hedges = np.zeros((n, len(inputs)), dtype=np.int64)
    cons = np.full((n, len(outputs)), -1, dtype=np.int64)
    conditions = {r: program_array(rule.program, in_index)
                  for r, rule in enumerate(rules) if rule.program is not None}
    for r, rule in enumerate(rules):
        for name, (term, neg, hedge) in rule.clauses.items():
            ante[r, in_index[name]] = term
            negated[r, in_index[name]] = neg
            hedges[r, in_index[name]] = int(hedge)
        for name, term in rule.conclusions.items():
            cons[r, out_index[name]] = term
    return RuleBase(
        inputs=inputs, outputs=outputs, antecedents=ante, consequents=cons,
        weights=np.array([r.weight for r in rules], dtype=float), negated=negated, hedges=hedges,
        connective=np.array([int(r.connective) for r in rules], dtype=np.int64),
        inference=inference, rule_locs=[r.loc for r in rules], origins=[r.origin for r in rules],
        conditions=conditions)


def merge_rules(rules: list[RuleSpec]) -> list[RuleSpec]:
    """Rules with the same premise and weight concluding on different outputs become one rule
    with several conclusions (the papers print one table per output for one set of premises).
    A premise that concludes twice on the same output stays two rules: that is a consistency
    question for the verifier, not something to hide here."""
    merged: list[RuleSpec] = []
    by_premise: dict = {}
    for rule in rules:
        key = (tuple(sorted(rule.clauses.items())), rule.connective, rule.program, rule.weight)
        target = by_premise.get(key)
        if target is not None and not set(target.conclusions) & set(rule.conclusions):
            target.conclusions.update(rule.conclusions)
            target.origin += "; " + rule.origin
            continue
        copy = RuleSpec(dict(rule.clauses), rule.connective, dict(rule.conclusions), rule.weight,
                        rule.loc, rule.origin, rule.program)
        merged.append(copy)
        by_premise.setdefault(key, copy)
    return merged


class RulesBuilder:
    """The rule, table, inference and block statements (a part of `Builder`)."""

    def _stmt_inference(self, s: Stmt) -> None:
        output = s.data["output"]
        var = output and self._output_var(output)
        for key, value in s.data["settings"]:
            options = INFERENCE_VALUES[key]
            if value.text not in options:
                self.error(value.loc, f"unknown {key} `{value.text}`: "
                                      f"{suggest(value.text, list(options))}")
            elif output is None:
                setattr(self.block.inference, INFERENCE_FIELD[key], options[value.text])
            elif key not in ("aggregation", "defuzzify"):
                self.error(value.loc, f"`{key}` belongs to the whole rule base (or block); an "
                                      f"output has its own aggregation and defuzzify only")
            elif var is not None:
                self.block.choices.setdefault(var.name, {})[INFERENCE_FIELD[key]] = \
                    options[value.text]

    def _stmt_block(self, s: Stmt) -> None:
        name = s.data["name"]
        if any(b.name == name.text for b in self.blocks):
            self.error(name.loc, f"there is already a block `{name.text}`")
        # a block starts from the inference given outside blocks (its defaults)
        self.block = BlockSpec(name.text, name.loc, replace(self.top.inference),
                            choices={k: dict(v) for k, v in self.top.choices.items()})
        for stmt in s.data["statements"]:
            getattr(self, f"_stmt_{stmt.kind}")(stmt)
        self.blocks.append(self.block)
        self.block = self.top

    def _input_var(self, name: Name) -> LinguisticVar | None:
        var = self.vars.get(name.text)
        if var is None and name.text in self.broken:
            return None
        if var is None and (name.text in self.signals or name.text in self.step_by_name):
            kind = "input" if name.text in self.signals else "signal"
            self.error(name.loc, f"{kind} `{name.text}` has no terms; declare them with "
                                 f"`terms {name.text} : ...` (`terms {name.text} : uniform "
                                 "N Z P`, or `N = tri(a, b, c), ...`)")
            return None
        if var is None:
            known = [v for v, lv in self.vars.items() if lv.is_input]
            self.error(name.loc, f"unknown input `{name.text}` in a condition: "
                                 f"{suggest(name.text, known)}")
            return None
        if not var.is_input and self.block is self.top:
            self.error(name.loc, f"`{name.text}` is a rule-base output; conditions must name "
                                 "inputs (or, inside a `block`, outputs of earlier blocks) "
                                 f"({', '.join(v for v, lv in self.vars.items() if lv.is_input)})")
            return None
        return var

    def _output_var(self, name: Name) -> LinguisticVar | None:
        var = self.vars.get(name.text)
        if var is None and name.text in self.broken:
            return None
        if var is None:
            known = [v for v, lv in self.vars.items() if not lv.is_input]
            self.error(name.loc, f"unknown output `{name.text}`: {suggest(name.text, known)}")
            return None
        if var.is_input:
            outs = [v for v, lv in self.vars.items() if not lv.is_input]
            self.error(name.loc, f"`{name.text}` is an input of the rule base; a conclusion must "
                                 f"name an output ({', '.join(outs) or 'declare one with `var`'})")
            return None
        return var

    def _term(self, var: LinguisticVar, term: Name, context: str) -> int | None:
        names = var.term_names()
        if term.text not in names and f"{var.name}.{term.text}" in self.broken:
            return None     # its definition is reported
        if term.text not in names:
            hint = suggest(term.text, names)
            known = f" (known terms are {' '.join(names)})" if hint.startswith("did") else ""
            self.error(term.loc, f"unknown term `{term.text}` of `{var.name}` in {context}: "
                                 f"{hint}{known}")
            return None
        return names.index(term.text)

    def _leaf(self, clause: Clause, context: str) -> Cond | None:
        var = self._input_var(clause.var)
        term = None if var is None else self._term(var, clause.term, context)
        if term is None:
            return None
        return Cond("is", leaf=(var.name, (term, clause.negated, HEDGES[clause.hedge])))

    def _clause(self, clause: Clause, rule_clauses: dict, context: str) -> bool:
        """One clause of a flat conjunction (a table's guard, a `where`)."""
        leaf = self._leaf(clause, context)
        if leaf is None:
            return False
        name, value = leaf.leaf
        if name in rule_clauses:
            self.error(clause.var.loc, f"`{name}` appears twice in one guard; write it once")
            return False
        rule_clauses[name] = value
        return True

    def _condition(self, cond: Clause | Condition, context: str) -> Cond | None:
        if isinstance(cond, Clause) and cond.term.text == "any":
            var = self._input_var(cond.var)     # `x is any`: truth 1 (fuzzylite's), unless
            if var is None:                     # x has a term of that name
                return None
            if "any" not in var.term_names():
                return Cond("is", leaf=(var.name, (ANY, cond.negated, HEDGES[cond.hedge])))
        if isinstance(cond, Clause):
            return self._leaf(cond, context)
        parts = [self._condition(p, context) for p in cond.parts]
        if None in parts:
            return None
        if cond.connective == "weight":     # `0.5 * (...)`: fuzzylite's weight under a hedge
            weight = self._weight(cond.weight)
            return None if weight is None else Cond("weight", parts, weight=weight)
        return Cond(cond.connective, parts, hedge=HEDGES[cond.hedge])

    def _conclusion(self, var: LinguisticVar, term, context: str,
                    learnable: bool = False, label: str = "") -> int | None:
        """A term name, or a number: a singleton consequent of its own."""
        if isinstance(term, Num):
            name = Name(label or _fresh_term(var), term.loc)
            if not (var.lo <= term.value <= var.hi):
                self.error(term.loc, f"value {term.value:g} is outside `{var.name}`'s range "
                                     f"[{var.lo:g}, {var.hi:g}]")
                return None
            return self._append_term(var, name, TermKind.SINGLETON, (term.value, 0, 0, 0), learnable)
        return self._term(var, term, context)

    def _stmt_rule(self, s: Stmt) -> None:
        label = f"rule {s.data['name'].text}" if s.data["name"] else f"rule at line {s.loc.line}"
        condition = self._condition(s.data["condition"], label)
        ok = condition is not None
        conclusions = {}
        for concl in s.data["conclusions"]:
            var = self._output_var(concl.var)
            if var is None:
                ok = False
                continue
            term = self._conclusion(var, concl.term, label)
            if term is None:
                ok = False
            elif var.name in conclusions:
                self.error(concl.var.loc, f"`{var.name}` is concluded twice in one rule; "
                                            "write one conclusion on it")
                ok = False
            else:
                conclusions[var.name] = term
        weight = self._weight(s.data["weight"])
        if ok and weight is not None:
            clauses, connective, program = premise(condition)
            if program is None:
                clauses, connective, weight = resolve_any(clauses, connective, weight)
            self.block.rules.append(RuleSpec(clauses, connective, conclusions, weight, s.loc, label,
                                       program))

    def _weight(self, num: Num | None) -> float | None:
        if num is None:
            return 1.0
        if not 0.0 <= num.value <= 1.0:
            self.error(num.loc, f"a rule weight must lie in [0, 1], got {num.value:g}")
            return None
        return num.value

    def _stmt_table2d(self, s: Stmt) -> None:
        d = s.data
        out = self._output_var(d["output"])
        guard: dict = {}
        guard_ok = all([self._clause(c, guard, f"the guard of table {d['output'].text}")
                        for c in d["guard"]])
        axes = {}
        for kind, var_name, terms in d["axes"]:
            if kind in axes:
                self.error(var_name.loc, f"table has two `{kind}` axes; give one `rows` and one `cols`")
                return
            var = self._input_var(var_name)
            if var is None:
                return
            if var.name in guard:
                self.error(var_name.loc, f"`{var.name}` is both a table axis and in the guard")
                return
            idx = [self._term(var, t, f"the {kind} of table {d['output'].text}") for t in terms]
            axes[kind] = (var, idx, terms)
        if out is None or not guard_ok or len(axes) != 2 or any(None in a[1] for a in axes.values()):
            return
        (row_var, row_idx, row_terms), (col_var, col_idx, col_terms) = axes["rows"], axes["cols"]
        cells = d["cells"]
        if not self._table_shape(s, cells, len(row_idx), len(col_idx)):
            return
        guard_text = ("when " + " and ".join(f"{c.var.text} is {c.term.text}" for c in d["guard"])
                      + ", ") if d["guard"] else ""
        for r, (ri, rt) in enumerate(zip(row_idx, row_terms)):
            for c, (ci, ct) in enumerate(zip(col_idx, col_terms)):
                cell = cells[r * len(col_idx) + c]
                if isinstance(cell, Name) and cell.text == "-":
                    continue
                origin = (f"table {out.name} {guard_text}row {row_var.name}={rt.text}, "
                          f"col {col_var.name}={ct.text}")
                if d["learnable"] and not isinstance(cell, Num):
                    self.error(cell.loc, "cells of a learnable table are numbers (the initial "
                                         f"weights), not `{cell.text}`")
                    continue
                term = self._conclusion(out, cell, f"table `{out.name}`", d["learnable"],
                                        label=f"w_{rt.text}_{ct.text}" if d["learnable"] else "")
                if term is None:
                    continue
                clauses = dict(guard)
                clauses[row_var.name] = (ri, False, Hedge.NONE)
                clauses[col_var.name] = (ci, False, Hedge.NONE)
                self.block.rules.append(RuleSpec(clauses, Connective.AND, {out.name: term}, 1.0,
                                        cell.loc, origin))

    def _table_shape(self, s: Stmt, cells, n_rows: int, n_cols: int) -> bool:
        """Each printed line of the table is one row of the declared width."""
        lines: dict[int, list] = {}
        for cell in cells:
            lines.setdefault(cell.loc.line, []).append(cell)
        rows = list(lines.values())
        for row in rows:
            if len(row) != n_cols:
                self.error(row[0].loc, f"this table row has {plural(len(row), 'cell')}; the "
                                       f"table declares {plural(n_cols, 'column')}; give it "
                                       "one cell per column")
                return False
        if len(rows) != n_rows:
            self.error(s.loc, f"table `{s.data['output'].text}` has {plural(len(rows), 'row')}; "
                              f"its `rows` axis declares {n_rows}")
            return False
        return True

    def _stmt_list_table(self, s: Stmt) -> None:
        d = s.data
        premises = [self._input_var(n) for n in d["premises"]]
        outputs = [self._output_var(n) for n in d["outputs"]]
        if None in premises or None in outputs:
            return
        labels: dict[int, SourceLoc] = {}
        for row in d["rows"]:
            label = int(row["label"].value)
            if label in labels:
                self.error(row["label"].loc, f"rule {label} is numbered twice in this table")
            labels[label] = row["label"].loc
            context = f"table rule {label}"
            if len(row["premises"]) != len(premises) or len(row["conclusions"]) != len(outputs):
                self.error(row["label"].loc,
                           f"rule {label} has {len(row['premises'])} premise and "
                           f"{len(row['conclusions'])} conclusion cells; the table header "
                           f"declares {len(premises)} and {len(outputs)}")
                continue
            clauses: dict = {}
            ok = True
            for var, cell in zip(premises, row["premises"]):
                if cell.text == "*":
                    continue
                term = self._term(var, cell, context)
                ok = ok and term is not None
                clauses[var.name] = (term, False, Hedge.NONE)
            conclusions = {}
            for var, cell in zip(outputs, row["conclusions"]):
                term = self._term(var, cell, context)
                ok = ok and term is not None
                conclusions[var.name] = term
            weight = self._weight(row["weight"])
            if ok and weight is not None:
                self.block.rules.append(RuleSpec(clauses, Connective.AND, conclusions, weight,
                                        row["label"].loc, context))

    def _rulebases(self) -> list[RuleBase]:
        blocks = self.blocks or [self.top]
        if self.blocks and self.top.rules:
            self.error(self.top.rules[0].loc, "a rule outside the blocks: when a file has "
                                              "`block`s, every rule belongs to one; move it "
                                              "into a block")
        written = {name for b in blocks for name in b.writes()}
        for v in self.vars.values():
            concluded = not v.is_input and v.name in written
            if not v.terms and not v.stated and not concluded:
                self.error(v.loc, f"`{v.name}` has no terms: add `terms {v.name} : ...`")
            if not v.is_input and v.lo is not None and not v.lo <= v.default <= v.hi:
                self.error(v.loc, f"the default {v.default:g} of `{v.name}` is outside its range "
                                  f"[{v.lo:g}, {v.hi:g}]")
        if not self.blocks:     # one rule base: every input and every output variable
            inputs = [v for v in self.vars.values() if v.is_input]
            outputs = [v for v in self.vars.values() if not v.is_input]
        made = {name: to_variable(v) for name, v in self.vars.items() if v.lo is not None}
        rulebases, done = [], set()
        for b in blocks:
            if self.blocks:     # a block: the variables its rules read and write
                inputs = [v for n, v in self.vars.items() if n in b.reads()]
                outputs = [v for n, v in self.vars.items() if n in b.writes()]
                self._check_chain(b, inputs, outputs, done)
            for v in outputs:
                self._check_linear_terms(v, len(inputs), b.inference_of(v.name))
            if any(v.name not in made for v in inputs + outputs):
                continue        # reported where the variable was declared
            rb = assemble_rulebase([made[v.name] for v in inputs],
                                   [made[v.name] for v in outputs], merge_rules(b.rules),
                                   b.inference)
            rb.name = b.name
            rb.output_choices = {v.name: (b.inference_of(v.name).aggregation,
                                          b.inference_of(v.name).defuzzifier)
                                 for v in outputs if v.name in b.choices}
            rulebases.append(rb)
        return rulebases

    def _check_chain(self, b: BlockSpec, inputs, outputs, done: set[str]) -> None:
        """A block reads signals and outputs of earlier blocks; it writes outputs no other
        block writes."""
        for v in inputs:
            if not v.is_input and v.name not in done:
                maker = next((o for o in self.blocks if v.name in o.writes()), None)
                later = "" if maker is None else \
                    f"; move block `{maker.name}`, which computes it, before it"
                self.error(b.loc, f"block `{b.name}` reads `{v.name}` before any block "
                                  f"computes it{later}")
        for v in outputs:
            if v.name in done:
                self.error(b.loc, f"block `{b.name}` concludes on `{v.name}`, which an earlier "
                                  "block computes: an output belongs to one block")
            done.add(v.name)

    def _check_linear_terms(self, v: LinguisticVar, n_inputs: int, inference: Inference) -> None:
        for name, kind, params, loc in v.terms:
            if inference.defuzzifier in (Defuzzifier.TSUKAMOTO, Defuzzifier.TSUKAMOTO_SUM) \
                    and not monotonic(kind, params):
                self.error(loc, f"{inference.defuzzifier.name.lower()} needs monotonic output terms (shoulders, sigmoid, "
                                f"sshape, zshape, concave) or singletons; `{name}` is neither")
            if kind != TermKind.LINEAR:
                continue
            if inference.defuzzifier not in LINEAR_DEFUZZIFIERS:
                self.error(loc, f"linear term `{name}` needs defuzzify = " + " or ".join(
                    operators.DEFUZZIFIERS[d].word for d in sorted(   # the usual one first
                        LINEAR_DEFUZZIFIERS, key=lambda d: d != Defuzzifier.WEIGHTED_AVERAGE)))
            if any(params[n_inputs + 1:]):     # zeros are the (T, 4) padding
                self.error(loc, f"linear `{name}` has more coefficients than c0 and one per "
                                f"rule-base input ({n_inputs})")


def _fresh_term(var: LinguisticVar) -> str:
    """A name for a numeric conclusion's own term: `_vN` (N its index), or `_vN_2`, ... when
    the file already gave that name to a term of `var` (no user term is taken over)."""
    name, n = f"_v{len(var.terms)}", 2
    while name in var.term_index:
        name, n = f"_v{len(var.terms)}_{n}", n + 1
    return name
