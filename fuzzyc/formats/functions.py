"""fuzzylite's Function terms as the importers read them (FLL `term: f Function sin(x)/x`, its
FCL `TERM f := Function ...;`, its FIS `'function',[...]`): the formula parsed at once (a syntax
error or an unknown function at its own column), the names it reads checked once the model's
rule blocks are known (see fuzzyc.semantics.model, FUNCTION, and fuzzyc.engine.held_outputs)."""
from __future__ import annotations

from dataclasses import replace

from ..errors import Reporter
from ..engine.formula import FormulaError, name_offset, parse_formula
from ..semantics.model import RuleBase, SourceLoc, TermKind
from ..engine.held_outputs import TAKAGI_SUGENO
from .common import TermSpec


def function_term(name: str, text: str, name_loc: SourceLoc, formula_loc: SourceLoc,
                  rep: Reporter) -> TermSpec | None:
    """The term `name` whose formula `text` starts at formula_loc, or None after reporting."""
    if not text.strip():
        rep.error(formula_loc, "a Function term needs a formula, e.g. `Function sin(x) / x`")
        return None
    lead = len(text) - len(text.lstrip())
    try:
        formula = parse_formula(text)
    except FormulaError as exc:
        rep.error(_at(formula_loc, exc.offset), str(exc))
        return None
    return TermSpec(name, TermKind.FUNCTION, (0.0,) * 4, name_loc, formula=formula,
                    formula_loc=_at(formula_loc, lead))


def _at(loc: SourceLoc, offset: int) -> SourceLoc:
    return replace(loc, col=loc.col + offset)


def check_reads(rb: RuleBase, specs: dict, rep: Reporter, inputs) -> None:
    """Report every name a function term reads that the model cannot give it: an input's
    term and an output's membership read x only; a Takagi-Sugeno value reads the rule base's
    inputs and the outputs before it (their values now; a later output or itself would be the
    previous evaluation's value in fuzzylite: state), never x (fuzzylite's rule activation).
    `specs`: the importers' VarSpecs by name (the formulas' places), or a function
    (variable, term, name) -> the place of that name in the term's formula (the .fz
    builder); `inputs`: the names of the file's inputs (a chained block's input is an
    earlier block's output, checked there)."""
    for var in rb.inputs:
        if var.name in inputs:
            for t, formula in (var.formulas or {}).items():
                _only(formula, {"x"}, specs, var, t, rep, "an input's Function term reads x "
                      "(the input's value) only")
    for o, var in enumerate(rb.outputs):
        if rb.inference_of(o).defuzzifier not in TAKAGI_SUGENO:
            for t, formula in (var.formulas or {}).items():
                _only(formula, {"x"}, specs, var, t, rep, f"a Function term under "
                      f"{rb.inference_of(o).defuzzifier.name.lower()} is a membership of x: "
                      "it reads x only")
            continue
        known = [v.name for v in rb.inputs] + [v.name for v in rb.outputs[:o]]
        later = {v.name for v in rb.outputs[o:]}
        for t, formula in (var.formulas or {}).items():
            for name in sorted(formula.names() - set(known)):
                why = ("x in a Takagi-Sugeno Function term is the rule's activation in "
                       "fuzzylite; fuzzyc does not carry that" if name == "x" else
                       f"`{name}` is defuzzified after `{var.name}` (or is it): fuzzylite reads "
                       "its previous value, state fuzzyc does not carry; declare it before"
                       if name in later else
                       f"unknown name `{name}`: known: " + ", ".join(known))
                rep.error(_name_loc(specs, var, t, name), why)


def _only(formula, allowed: set[str], specs, var, t: int, rep: Reporter, why: str) -> None:
    for name in sorted(formula.names() - allowed):
        rep.error(_name_loc(specs, var, t, name), f"`{name}`: {why}")


def _name_loc(specs, var, t: int, name: str) -> SourceLoc | None:
    if callable(specs):
        return specs(var, t, name)
    term = specs[var.name].terms[t]
    return _at(term.formula_loc, name_offset(term.formula.text, name)) if term.formula_loc \
        else term.loc
