"""A System as the text of its tool's format: FLL (fuzzylite 6 and pyfuzzylite 8), fuzzylite
6's FCL (as its FclExporter writes it: FLL term words, `DEFAULT := nan`, `LOCK : RANGE`), and the
Octave toolkit's .fis (readfis.m: `MFk='name':'type',[params]`, rule rows `i1 i2, o1 (w) : c`
with negative indices for not and the fraction for a hedge)."""
from __future__ import annotations

import math

from .spec import Clause, Node, System, Var

SUFFIX = {"fll": ".fll", "fll6": ".fll", "fcl": ".fcl", "fis": ".fis"}
FCL_TNORMS = {"Minimum": "MIN", "AlgebraicProduct": "PROD", "BoundedDifference": "BDIF",
              "DrasticProduct": "DPROD", "EinsteinProduct": "EPROD", "HamacherProduct": "HPROD",
              "NilpotentMinimum": "NMIN"}
FCL_SNORMS = {"Maximum": "MAX", "AlgebraicSum": "ASUM", "BoundedSum": "BSUM",
              "DrasticSum": "DSUM", "EinsteinSum": "ESUM", "HamacherSum": "HSUM",
              "NilpotentMaximum": "NMAX", "NormalizedSum": "NSUM",
              # fuzzylite 6's FclExporter writes the class name (it has no FCL word for it),
              # and its importer reads no `SUM` (measured: `fuzzylite -i x.fll -of fcl`)
              "UnboundedSum": "UnboundedSum"}
FCL_METHODS = {"Centroid": "COG", "Bisector": "COA", "MeanOfMaximum": "MM",
               "SmallestOfMaximum": "LM", "LargestOfMaximum": "RM", "WeightedAverage": "COGS",
               "WeightedSum": "COGSS"}
FIS_EXPONENT = {"somewhat": ".05", "very": ".2", "extremely": ".3", "very very": ".4"}


def num(value: float) -> str:
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return repr(float(value))


def render(system: System) -> str:
    return {"fll": fll, "fll6": fll, "fcl": fcl, "fis": fis}[system.fmt](system)


def condition(cond: Clause | Node, top: bool = True) -> str:
    if isinstance(cond, Clause):
        words = cond.hedges if "any" in cond.hedges else cond.hedges + [cond.term]
        return f"{cond.var} is {' '.join(words)}"
    text = f"{condition(cond.left, False)} {cond.op} {condition(cond.right, False)}"
    return f"({text})" if cond.brackets and not top else text


def rule_text(rule) -> str:
    then = " and ".join(f"{c.var} is {' '.join(c.hedges + [c.term])}" for c in rule.then)
    weight = "" if rule.weight is None else f" with {num(rule.weight)}"
    return f"if {condition(rule.cond)} then {then}{weight}"


def _term_params(term) -> str:
    return " ".join(num(p) for p in term.params)


# ---------------------------------------------------------------------- FLL
def fll(system: System) -> str:
    lines = [f"Engine: {system.name}"]
    for var in system.inputs:
        lines += [f"InputVariable: {var.name}", "  enabled: true",
                  f"  range: {num(var.lo)} {num(var.hi)}",
                  f"  lock-range: {str(var.lock_range).lower()}"]
        lines += [f"  term: {t.name} {t.shape} {_term_params(t)}" for t in var.terms]
    for var in system.outputs:
        defuzzifier = var.defuzzifier + ("" if var.resolution is None else
                                         f" {var.resolution}")
        lines += [f"OutputVariable: {var.name}", "  enabled: true",
                  f"  range: {num(var.lo)} {num(var.hi)}",
                  f"  lock-range: {str(var.lock_range).lower()}",
                  f"  aggregation: {var.aggregation or 'none'}",
                  f"  defuzzifier: {defuzzifier}", f"  default: {num(var.default)}",
                  "  lock-previous: false"]
        lines += [f"  term: {t.name} {t.shape} {_term_params(t)}" for t in var.terms]
    lines += ["RuleBlock: rules", "  enabled: true", f"  conjunction: {system.conjunction}",
              f"  disjunction: {system.disjunction}",
              f"  implication: {system.implication or 'none'}", "  activation: General"]
    lines += [f"  rule: {rule_text(rule)}" for rule in system.rules]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- FCL
def _fcl_term(term) -> str:
    if term.shape == "Constant":
        return num(term.params[0])
    if term.shape == "Discrete":
        pairs = zip(term.params[::2], term.params[1::2])
        return " ".join(f"({num(x)}, {num(y)})" for x, y in pairs)
    return f"{term.shape} {_term_params(term)}"


def _fcl_terms(var: Var) -> list[str]:
    return [f"  TERM {t.name} := {_fcl_term(t)};" for t in var.terms]


def fcl(system: System) -> str:
    lines = [f"FUNCTION_BLOCK {system.name}", "", "VAR_INPUT"]
    lines += [f"  {v.name}: REAL;" for v in system.inputs] + ["END_VAR", "", "VAR_OUTPUT"]
    lines += [f"  {v.name}: REAL;" for v in system.outputs] + ["END_VAR", ""]
    for var in system.inputs:
        lines += [f"FUZZIFY {var.name}", f"  RANGE := ({num(var.lo)} .. {num(var.hi)});"]
        lines += _fcl_terms(var) + ["END_FUZZIFY", ""]   # fuzzylite 6 locks outputs only
    for var in system.outputs:
        lines += [f"DEFUZZIFY {var.name}", f"  RANGE := ({num(var.lo)} .. {num(var.hi)});"]
        lines += _fcl_terms(var) + [f"  METHOD : {FCL_METHODS[var.defuzzifier]};"]
        if var.aggregation:
            lines.append(f"  ACCU : {FCL_SNORMS[var.aggregation]};")
        lines.append(f"  DEFAULT := {num(var.default)};")
        lines += (["  LOCK : RANGE;"] if var.lock_range else []) + ["END_DEFUZZIFY", ""]
    lines += ["RULEBLOCK rules", f"  AND : {FCL_TNORMS[system.conjunction]};",
              f"  OR : {FCL_SNORMS[system.disjunction]};"]
    if system.implication:
        lines.append(f"  ACT : {FCL_TNORMS[system.implication]};")
    lines += [f"  RULE {k + 1} : {rule_text(rule)};" for k, rule in enumerate(system.rules)]
    return "\n".join(lines + ["END_RULEBLOCK", "", "END_FUNCTION_BLOCK"]) + "\n"


# ---------------------------------------------------------------------- FIS
def _fis_index(clause: Clause | None, var: Var) -> str:
    if clause is None:
        return "0"
    index = str(1 + [t.name for t in var.terms].index(clause.term))
    hedges = [h for h in clause.hedges if h != "not"]
    text = index + (FIS_EXPONENT[hedges[0]] if hedges else "")
    return ("-" if "not" in clause.hedges else "") + text


def _fis_rule(system: System, rule) -> str:
    said = {c.var: c for c in _flat(rule.cond)}
    concluded = {c.var: c for c in rule.then}
    ins = " ".join(_fis_index(said.get(v.name), v) for v in system.inputs)
    outs = " ".join(_fis_index(concluded.get(v.name), v) for v in system.outputs)
    op = rule.cond.op if isinstance(rule.cond, Node) else "and"
    weight = 1.0 if rule.weight is None else rule.weight
    return f"{ins}, {outs} ({num(weight)}) : {1 if op == 'and' else 2}"


def _flat(cond):
    return [cond] if isinstance(cond, Clause) else _flat(cond.left) + _flat(cond.right)


def _fis_variable(section: str, var: Var) -> list[str]:
    lines = [f"[{section}]", f"Name='{var.name}'", f"Range=[{num(var.lo)} {num(var.hi)}]",
             f"NumMFs={len(var.terms)}"]
    lines += [f"MF{k + 1}='{t.name}':'{t.shape}',[{' '.join(num(p) for p in t.params)}]"
              for k, t in enumerate(var.terms)]
    return lines + [""]


def fis(system: System) -> str:
    out = system.outputs[0]
    lines = ["[System]", f"Name='{system.name}'",
             f"Type='{'sugeno' if system.sugeno else 'mamdani'}'", "Version=2.0",
             f"NumInputs={len(system.inputs)}", f"NumOutputs={len(system.outputs)}",
             f"NumRules={len(system.rules)}", f"AndMethod='{system.conjunction}'",
             f"OrMethod='{system.disjunction}'", f"ImpMethod='{system.implication}'",
             f"AggMethod='{out.aggregation or 'sum'}'", f"DefuzzMethod='{out.defuzzifier}'", ""]
    for k, var in enumerate(system.inputs):
        lines += _fis_variable(f"Input{k + 1}", var)
    for k, var in enumerate(system.outputs):
        lines += _fis_variable(f"Output{k + 1}", var)
    lines += ["[Rules]"] + [_fis_rule(system, rule) for rule in system.rules]
    return "\n".join(lines) + "\n"
