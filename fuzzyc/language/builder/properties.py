"""The `verify { ... }` section: properties as written, checked against the declared
names, for fuzzyc.verify to give meaning."""

from __future__ import annotations

import sympy

from .. import units
from ...errors import source_lines, suggest
from ...semantics.model import Property
from ..syntax import Expr, Num, Stmt
from .chain import fold_left


class PropertiesBuilder:
    """The `verify` statement and its properties (a part of `Builder`)."""

    def _stmt_verify(self, s: Stmt) -> None:
        for prop in s.data["properties"]:
            built = getattr(self, f"_prop_{prop.kind}")(prop)
            if built is not None:
                self.properties.append(Property(prop.kind, built, prop.loc,
                                                self._source_text(prop)))

    def _source_text(self, s: Stmt) -> str:
        lines = source_lines(self.rep.text)
        if s.end is None or s.loc.line > len(lines):
            return ""
        if s.loc.line == s.end.line:
            return lines[s.loc.line - 1][s.loc.col - 1:s.end.col - 1].strip()
        return lines[s.loc.line - 1][s.loc.col - 1:].strip() + " ..."

    def _property_input(self, name):
        """A variable a property reads as an input: a rule-base input, or, in a file of rule
        blocks, a variable one block concludes and a later one reads, which is known only once
        the blocks are (check_property_inputs)."""
        var = self.vars.get(name.text)
        if var is not None and not var.is_input:
            self.property_reads.append(name)
            return var
        return self._input_var(name)

    def check_property_inputs(self, blocks) -> None:
        """The error _input_var gives for a rule-base output, unless a block reads it."""
        read = {v.name for rb in blocks for v in rb.inputs} if len(blocks) > 1 else set()
        inputs = ", ".join(v for v, lv in self.vars.items() if lv.is_input)
        for name in self.property_reads:
            if name.text not in read:
                self.error(name.loc, f"`{name.text}` is a rule-base output; conditions name "
                                     "inputs (or, inside a `block`, outputs of earlier blocks) "
                                     f"({inputs})")

    def _prop_covers(self, p: Stmt):
        names = [self._property_input(n) for n in p.data["inputs"]]
        if None in names:
            return None
        return {"inputs": [v.name for v in names], "level": p.data["level"].value}

    def _prop_consistent(self, p: Stmt):
        return {}

    def _optional_output(self, p: Stmt):
        name = p.data["output"]
        if name is None:
            return {"output": None}
        var = self._output_var(name)
        return None if var is None else {"output": var.name}

    _prop_complete = _optional_output

    _prop_continuous = _optional_output

    def _prop_monotone(self, p: Stmt):
        out, inp = self._output_var(p.data["output"]), self._property_input(p.data["input"])
        where: dict = {}
        ok = all([self._clause(c, where, "a `where` guard") for c in p.data["where"]])
        if out is None or inp is None or not ok:
            return None
        return {"output": out.name, "input": inp.name, "direction": p.data["direction"],
                "where": [(v, t, neg) for v, (t, neg, _h) in where.items()]}

    def _prop_bounded(self, p: Stmt):
        name = p.data["signal"]
        known = [*self.signals, *self.step_by_name, *(o.name for o in self.outputs),
                 *(v for v, lv in self.vars.items() if not lv.is_input)]
        if name.text not in known:
            self.error(name.loc, f"unknown signal `{name.text}` in `bounded`: "
                                 f"{suggest(name.text, known)}")
            return None
        rng = self._range(p.data["range"], f"`bounded {name.text}`")
        return None if rng is None else {"signal": name.text, "lo": rng[0], "hi": rng[1]}

    def _seconds(self, num: Num, unit, what: str) -> float | None:
        if unit is None:
            return num.value
        u = units.make(unit)
        scale = units.SECONDS.get(u[0][0]) if len(u) == 1 and u[0][1] == 1 else None
        if scale is None:
            self.error(num.loc, f"{what} needs a time unit (s, ms, min)")
            return None
        return num.value * scale

    def _prop_closed_loop(self, p: Stmt):
        d = p.data
        duration = self._seconds(d["duration"], d["unit"], "the loop duration")
        settings, ranges, before, faults, checks = {}, {}, {}, [], []
        for item in d["items"]:
            if item.kind == "set":
                settings[item.data["key"].text] = item.data["value"].value
            elif item.kind == "vary":
                key = item.data["key"].text
                rng = self._range(item.data["range"], f"`vary {key}`")
                if rng and self._varied_key(item.data["key"]):
                    ranges[key] = rng
                if item.data["before"]:
                    seconds = self._seconds(*item.data["before"], "`steps before`")
                    if seconds is not None:
                        before[key] = seconds
            elif item.kind == "fault":
                seconds = self._seconds(item.data["seconds"], item.data["unit"], "a fault")
                if seconds is not None and seconds <= 0:
                    self.error(item.data["seconds"].loc, "a fault must last a positive time")
                elif seconds is not None:
                    faults.append((item.data["signal"].text, item.data["kind"], seconds))
            else:
                check = self._temporal(item)
                if check is not None:
                    checks.append(Property(item.kind, check, item.loc, self._source_text(item)))
        if duration is None:
            return None
        return {"scenario": d["scenario"].text, "duration": duration, "set": settings,
                "vary": ranges, "steps_before": before, "faults": faults, "checks": checks}

    def _varied_key(self, key) -> bool:
        """`vary plant.NAME` (a plant parameter, resolved with the scenario) or
        `vary controller.NAME` (a param of this file: a set point)."""
        kind, _, name = key.text.partition(".")
        if kind == "controller" and name in self.params:
            return True
        if kind == "controller":
            self.error(key.loc, f"`{key.text}`: this file has no param `{name}`"
                       + (f"; known: {', '.join(self.params)}" if self.params else ""))
        elif kind != "plant" or not name:
            self.error(key.loc, f"`vary {key.text}`: vary a plant parameter (plant.NAME) or a "
                       f"param of this file (controller.NAME)")
        return kind == "plant" and bool(name)

    def _predicate(self, node: Expr):
        """Comparisons over plant and controller signals; names are resolved at run time."""
        if node.op in ("and", "or"):
            parts = [self._predicate(a) for a in node.args]
            if any(p is None for p in parts):
                return None
            return (sympy.And if node.op == "and" else sympy.Or)(*parts)
        left, right = self._free_expr(node.args[0]), self._free_expr(node.args[1])
        if left is None or right is None:
            return None
        relation = {"<": sympy.Lt, "<=": sympy.Le, ">": sympy.Gt, ">=": sympy.Ge}[node.name]
        return relation(left, right, evaluate=False)

    def _free_expr(self, node: Expr):
        """An expression in a loop property: any name (a plant signal) is allowed."""
        if node.op == "symbol":
            return sympy.Symbol(node.args[0])
        if node.op == "constant":
            return sympy.Float(node.args[0])
        if node.op == "call" and node.name in ("abs", "min", "max"):
            args = [self._free_expr(a) for a in node.args]
            if None in args:
                return None
            return {"abs": sympy.Abs, "min": sympy.Min, "max": sympy.Max}[node.name](*args)
        if node.op == "call":
            self.error(node.loc, f"`{node.name}` is not allowed in a loop property: abs, min, max")
            return None
        if node.op == "neg":
            arg = self._free_expr(node.args[0])
            return None if arg is None else -arg
        ops = {"add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
               "div": lambda a, b: a / b, "pow": lambda a, b: a ** b}
        return fold_left(node, self._free_expr, lambda n, a, b: None if a is None or b is None
                         else ops[n.op](a, b))

    def _temporal(self, item: Stmt):
        d = item.data
        if item.kind == "always":
            pred = self._predicate(d["predicate"])
            return None if pred is None else {"predicate": pred}
        if item.kind == "eventually":
            pred = self._predicate(d["predicate"])
            within = self._seconds(d["within"], d["unit"], "`within`")
            return None if pred is None or within is None else {"predicate": pred, "within": within}
        if item.kind == "settles":
            target = self._free_expr(d["target"])
            by = self._seconds(d["by"], d["unit"], "`by`")
            if target is None or by is None:
                return None
            return {"signal": d["signal"].text, "target": target,
                    "tolerance": d["tolerance"].value, "by": by}
        return {"signal": d["signal"].text, "limit": d["limit"].value}
