"""The model's rule base as .fz text that `fuzzyc.language.parser.parse` reads back to the same rule base.

Inputs become `input` declarations with their terms, outputs `var` + `terms` and a plain
`output NAME_out = NAME` each; rules are written one per `rule` statement (tables are a
reading aid of the source, not part of the model).  A model with a signal chain is written as
its bare rule base, with warnings naming what was left out.  A model of several rule blocks is
written as `block NAME { ... }`s (each with its full inference), chained blocks included: the
file evaluates as the model.  A name spelled like a .fz keyword, or no plain identifier, is
written in backticks (`rule`, `Food-Quality`); one with a backtick, a dot or a control
character, or starting with __, is refused (`unsayable_names`).
"""
from __future__ import annotations

import math

import numpy as np

from ..semantics.model import Hedge, Model, TermKind, Variable, chain_output_names
from ..semantics.shapes import SHAPES
from ..escape import one_line
from ..semantics.tunable import parameter_names, shape_word, slots
from ..engine.membership import linear_coefficients
from ..semantics import operators as ops
from ..language.parser import fz_name, keywords
from .blocks import block_names, block_view, file_variables, linear_on, read_inputs
from .export import (left_out, model_identifier, num, refuse, rule_sentence,
                     unsayable_functions, unsayable_names)

# the .fz words: the operator registry's
FZ_HEDGES = {h: rec.word for h, rec in ops.HEDGES.items() if h != Hedge.NONE}
FZ_INFERENCE = tuple((key, field, {k: rec.word for k, rec in ops.REGISTRIES[key].items()})
                     for key, field in (("and", "and_"), ("or", "or_"),
                                        ("implication", "implication"),
                                        ("aggregation", "aggregation"),
                                        ("defuzzify", "defuzzifier")))


def write_fz(model: Model, warnings: list[str] | None = None) -> str:
    inputs, outputs = file_variables(model)
    several = len(model.blocks) > 1
    names = _tuned_rule_names(model)      # rules whose weight the tune section names
    problems = unsayable_names(model, ".fz") + unsayable_functions(model, ".fz", True, True)
    lines = [f"controller {fz_name(model_identifier(model))} {_string(model.title)} {{"
             .replace("  ", " ")]
    lines += [f"  note {_string(n)}" for n in model.notes]
    for var in inputs:
        lines.append(f"  input {fz_name(var.name)}{_unit(var)} in [{num(var.lo)}, {num(var.hi)}]")
    for var in inputs:
        lines.append(f"  terms {fz_name(var.name)} : {_terms(var, problems)}".rstrip())
    for rb in model.blocks:
        # a block of a .fz file reads the variables its rules name, in declaration order
        read = read_inputs(rb, inputs + outputs) if several else rb.inputs
        for var in rb.outputs:
            var = linear_on(var, rb.inputs, read, problems)
            lines.append(f"  var {fz_name(var.name)}{_unit(var)} "
                         f"in [{num(var.lo)}, {num(var.hi)}] default {num(var.default)}"
                         + (" hold_last" if var.lock_previous else ""))
            lines.append(f"  terms {fz_name(var.name)} : {_terms(var, problems, len(read))}")
    lines += _fuzzylite_lines(model)
    if several:
        for b, (name, rb) in enumerate(zip(block_names(model, keywords()), model.blocks)):
            lines += [f"  block {name} {{",
                      *("  " + line for line in _block_lines(block_view(model, rb), problems,
                                                              names.get(b, {}))),
                      "  }"]
    else:
        lines += _block_lines(model, problems, names.get(0, {}))
    # `y_out`, or `y_out2` when the file has a `y_out` of its own: as the importers name it
    chain = chain_output_names([v.name for v in outputs], [v.name for v in inputs + outputs])
    problems += [f"the controller output `{out}` made from `{var.name}` starts with __, which "
                 f"fuzzyc reserves for the names it generates; rename `{var.name}`"
                 for var, out in zip(outputs, chain) if out.startswith("__")]
    for var, out in zip(outputs, chain):
        lines.append(f"  output {fz_name(out)}{_unit(var)} "
                     f"in [{num(var.lo)}, {num(var.hi)}] = {fz_name(var.name)}")
    lines += _tune_lines(model, warnings)
    lines.append("}")
    refuse(model, ".fz", problems)
    if warnings is not None:
        warnings.extend(left_out(model))
    return "\n".join(lines) + "\n"


def _fuzzylite_lines(model: Model) -> list[str]:
    """The `fuzzylite` statements: what an imported fuzzylite file said that only the fuzzylite
    semantics read (tool_semantics.FileSettings), so that the .fz file gives its numbers."""
    from .tool_semantics import file_settings      # it imports the engine, which imports us
    said = file_settings(model)
    lines = ["  fuzzylite replace_nan"] if said.known else []
    if said.locked:
        lines.append("  fuzzylite lock_range " + " ".join(map(fz_name, sorted(said.locked))))
    lines += [f"  fuzzylite resolution {fz_name(name)} {points}"
              for name, points in sorted(said.resolution.items())]
    if said.nan_default:
        lines.append("  fuzzylite nan_default " + " ".join(map(fz_name,
                                                                 sorted(said.nan_default))))
    if said.flat:
        lines.append("  fuzzylite flat " + " ".join(map(fz_name, sorted(said.flat))))
    return lines


def _block_lines(model: Model, problems: list[str], rule_names: dict[int, str]) -> list[str]:
    """The inference and rules of the model's one rule block (rule r named rule_names[r])."""
    rb = model.rulebase
    inf = rb.inference
    lines = ["  inference " + ", ".join(f"{key} = {words[getattr(inf, field)]}"
                                        for key, field, words in FZ_INFERENCE)]
    for o, var in enumerate(rb.outputs):
        if var.name in rb.output_choices:
            own = rb.inference_of(o)
            lines.append(f"  inference {fz_name(var.name)}: " + ", ".join(
                f"{key} = {words[getattr(own, field)]}"
                for key, field, words in FZ_INFERENCE[3:]))    # aggregation, defuzzify
    for r in range(rb.n_rules):
        label = f"{fz_name(rule_names[r])}: " if r in rule_names else ""
        lines.append("  rule " + label
                     + rule_sentence(model, r, FZ_HEDGES, ", ", problems, says_any=True,
                                       say=fz_name, hedged_conditions=True))
    return lines


def _string(text: str) -> str:
    """A .fz string literal on one line (the language has no escapes: quotes and backslashes
    are replaced)."""
    return '"' + one_line(text).replace("\\", "/").replace('"', "'") + '"'


def _unit(var: Variable) -> str:
    return f" : {var.unit}" if var.unit else ""


def _terms(var: Variable, problems: list[str], n_inputs: int = 0) -> str:
    linear = linear_coefficients(var, n_inputs) if np.any(var.kinds == TermKind.LINEAR) else None
    return ", ".join(f"{fz_name(name)} = linear({', '.join(num(c) for c in linear[t])})"
                     if kind == TermKind.LINEAR else
                     f"{fz_name(name)} = discrete({', '.join(map(num, var.term_numbers(t)))})"
                     if kind == TermKind.DISCRETE else
                     f'{fz_name(name)} = formula("{var.formulas[t].infix()}")'
                     if kind == TermKind.FUNCTION else
                     f"{fz_name(name)} = "
                     f"{_shape(TermKind(int(kind)), p, var.name, name, problems)}"
                     for t, (name, kind, p) in enumerate(zip(var.names, var.kinds, var.params)))


def _shape(kind: TermKind, p, var: str, term: str, problems: list[str]) -> str:
    a, b, c, d = (float(x) for x in p)
    if kind == TermKind.TRAPEZOID:
        if a == b == -math.inf and c < d < math.inf:
            return f"lshoulder({num(c)}, {num(d)})"
        if c == d == math.inf and -math.inf < a < b:
            return f"rshoulder({num(a)}, {num(b)})"
        if not all(math.isfinite(x) for x in (a, b, c, d)):
            problems.append(f"term `{term}` of `{var}` ({', '.join(map(num, (a, b, c, d)))}) "
                            "has no .fz shape")
        if b == c:
            return f"tri({num(a)}, {num(b)}, {num(d)})"
        return f"trap({num(a)}, {num(b)}, {num(c)}, {num(d)})"
    word = SHAPES[kind].words[0]        # the shape's one .fz word: its numbers are the params
    return f"{word.word}({', '.join(num(x) for x in (a, b, c, d)[:word.arity])})"


def _tuned_rule_names(model: Model) -> dict[int, dict[int, str]]:
    """block -> rule -> the name the tune section gives it (its weight is tuned)."""
    names: dict[int, dict[int, str]] = {}
    for n in model.tunables:
        if n.kind == "weight":
            names.setdefault(n.block, {})[n.rule_index] = n.rule
    return names


def _tune_lines(model: Model, warnings: list[str] | None) -> list[str]:
    """The tune section, one line per tuned number, named as this writer writes the term."""
    lines = []
    for n in model.tunables:
        if n.kind == "param":          # the writer writes the bare rule base, no params
            if warnings is not None:
                warnings.append(f"tune: `{n.target}` is a param, which the .fz writer leaves "
                                "out with the signal chain")
            continue
        target = f"{fz_name(n.rule)}.weight"
        if n.kind == "term":
            var = next(v for rb in model.blocks for v in rb.inputs + rb.outputs
                       if v.name == n.var)
            t = var.index(n.term)
            word = shape_word(var.kinds[t], var.params[t])
            count = len(var.term_numbers(t))
            index = n.index if word in ("linear", "discrete") else next(
                i for i in range(count) if n.slots[0] in slots(word, i))
            spelled = parameter_names(word, max(count, index + 1))[index][0]
            target = f"{fz_name(n.var)}.{fz_name(n.term)}.{spelled}"
        line = f"    {target} in "
        if any(kept.startswith(line) for kept in lines):    # a trap(a, b, b, d) written as tri
            if warnings is not None:
                warnings.append(f"tune: `{n.target}` is written as `{target}`, tuned once")
            continue
        lines.append(f"{line}[{num(n.lo)}, {num(n.hi)}]")
    return ["  tune {", *lines, "  }"] if lines else []
