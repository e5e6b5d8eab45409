"""What the exporters share: what of a model lies outside its rule base (and so is left out of
an exported file), numbers written so they read back bit for bit, and how rules read as text.

Policy: an export writes the bare rule base and returns warnings naming everything it left out
(the signal chain, learnable flags, properties, ...); it refuses (FuzzycError) only when the
rule base itself cannot be said in the target format.
"""
from __future__ import annotations

import math
import re
from typing import Callable

import numpy as np
import sympy

from ..errors import Diagnostic, FuzzycError
from ..display import plural
from ..escape import FZ_QUOTED_NAME, SAFE_NAME, name_problems
from ..semantics.model import (CondOp, Hedge, Model, OutputKind, TermKind, Variable,
                               chain_output_names)
from .blocks import file_variables


def num(value: float) -> str:
    """Shortest text that reads back as the same float (`repr`), integers without `.0`."""
    value = float(value)
    if math.isfinite(value) and value == int(value) and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def model_identifier(model: Model) -> str:
    """The model's name as .fz, FLL and FCL can say it: [A-Za-z_][A-Za-z0-9_]*."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", model.name) or "imported"
    return name if re.match(r"[A-Za-z_]", name) else "_" + name


# `__` starts the names fuzzyc generates (language.builder.chain.RESERVED_PREFIX)
FZ_NAME = re.compile(f"(?!__)(?:{SAFE_NAME.pattern}|{FZ_QUOTED_NAME.pattern})")


def unsayable_names(model: Model, fmt: str) -> list[str]:
    """The variable and term names of the rule base that the format cannot say: not letters,
    digits and _ (FLL and FCL), or, in .fz, which writes other names in backticks, a name
    with a backtick, a dot or a control character: written as they are they would read back
    as something else."""
    inputs, outputs = file_variables(model)
    names = [n for v in inputs + outputs for n in (v.name, *v.names)]
    return fz_name_problems(names) if fmt == ".fz" else name_problems(names, fmt)


def fz_name_problems(names) -> list[str]:
    return name_problems(names, ".fz", FZ_NAME, "in backticks any character but a backtick, a "
                                                "dot or a control character, not starting "
                                                "with __")


def refuse(model: Model, fmt: str, problems: list[str]) -> None:
    if problems:     # a problem found per block or output is said once
        raise FuzzycError([Diagnostic(None, f"cannot export `{model.name}` to {fmt}: {p}")
                           for p in dict.fromkeys(problems)])


def finish(model: Model, fmt: str, lines: list[str], problems: list[str], notes: list[str],
           warnings: list[str] | None) -> str:
    """Every writer's last step: refuse what the format cannot say, else hand the notes to
    the caller's warnings and return the file's text."""
    refuse(model, fmt, problems)
    if warnings is not None:
        warnings.extend(dict.fromkeys(notes))     # a note said per block or output once
    return "\n".join(lines) + "\n"


def left_out(model: Model) -> list[str]:
    """Everything of the model that a bare rule-base export does not carry, as sentences."""
    inputs, outputs = file_variables(model)
    lost = []
    signals = {s.name for s in model.signals}
    derived = [v.name for v in inputs if v.name not in signals]
    if model.steps:
        shown = ", ".join(s.name for s in model.steps if not s.hidden)
        lost.append(f"the input signal chain ({shown}): the rule base's inputs "
                    f"{', '.join(v.name for v in inputs)} become the exported inputs")
    elif derived:
        lost.append(f"inputs {', '.join(derived)} are not raw signals")
    unused = sorted(signals - {v.name for v in inputs})
    if unused:
        lost.append(f"raw inputs not read by the rule base: {', '.join(unused)}")
    # a plain output read back is named by the importers' convention (y -> y_out)
    read_back = dict(zip([v.name for v in outputs], chain_output_names(
        [v.name for v in outputs], [v.name for v in (*inputs, *outputs)])))
    for out in model.outputs:
        if _is_plain_output(out, outputs) and out.name != read_back[out.expr.name]:
            lost.append(f"output {out.name} is the rule-base output {out.expr.name} under "
                        f"another name: the file names it {out.expr.name} (read back, "
                        f"{read_back[out.expr.name]})")
        if not _is_plain_output(out, outputs):
            kind = {OutputKind.INCREMENT: "integrate", OutputKind.RECIPROCAL_INCREMENT:
                    "1/integrate"}.get(out.kind, "")
            lost.append(f"output {out.name} = {kind}({out.expr}) in [{out.lo:g}, {out.hi:g}]: "
                        "the rule-base outputs are exported instead")
    if model.params:
        lost.append("params " + ", ".join(model.params))
    for v in outputs:
        if v.learnable is not None and np.any(v.learnable):
            lost.append(f"the learnable flags of `{v.name}`'s terms")
    if model.properties:
        lost.append(f"{plural(len(model.properties), 'verify property', 'verify properties')}"
                    " dropped: the format has no place for them (verify the .fz)")
    if model.period is not None:
        lost.append(f"the sample period {model.period:g} s")
    return lost


def _is_plain_output(out, variables: list[Variable]) -> bool:
    """An output that just passes a rule-base output through, saturated to its range."""
    if out.kind != OutputKind.DIRECT or not isinstance(out.expr, sympy.Symbol):
        return False
    var = next((v for v in variables if v.name == out.expr.name), None)
    return var is not None and (out.lo, out.hi) == (var.lo, var.hi)


def all_singletons(var: Variable) -> bool:
    return bool(np.all(var.kinds == TermKind.SINGLETON))


def rule_sentence(model: Model, r: int, hedge_words: dict[Hedge, str], also: str,
                  problems: list[str], says_any: bool = False,
                  say: Callable[[str], str] = str, hedged_conditions: bool = False) -> str:
    """Rule r as `if x is not very A and ... then y is B<also>z is C with w` (FLL, FCL, .fz
    share this shape; `also` joins conclusions).  Lower-case keywords: FCL's are
    case-insensitive, and fuzzylite 6 reads FCL rules only in lower case (measured).
    `says_any`: a rule without clauses (it always fires) is `if x is any` (fuzzylite's).
    `say` writes a variable or term name (.fz quotes its keywords); `hedged_conditions`: the
    format says a hedge on a compound or hedged condition as `very (...)`, a weight under
    it as `0.5 * (...)` and a FIS row's hedge on a conclusion as `concluded very (...)` or
    `carried very (...)` (.fz)."""
    rb = model.rulebase

    def clause(i: int, t: int, negated: bool, hedge: Hedge) -> str:
        v = rb.inputs[i]
        words = ["not"] if negated else []
        if hedge != Hedge.NONE:
            words.append(hedge_words.get(hedge, hedge.name.lower()))  # else refused already
        return " ".join([say(v.name), "is", *words, say(v.names[t]) if t >= 0 else "any"])

    condition = rb.describe_condition(r, clause, ("and", "or", "not", "concluded", "carried")
                                      if hedged_conditions else ("and", "or", "not"))
    if r in rb.conditions and np.any(rb.conditions[r][:, 0] == CondOp.HEDGE) \
            and not hedged_conditions:
        problems.append(f"rule {r + 1} hedges a compound condition or a hedged clause (read "
                        "from fuzzylite's `very very x` or a hedged conclusion), which the "
                        "format cannot say")
    if r in rb.conditions and np.any(rb.conditions[r][:, 0] == CondOp.WEIGHT) \
            and not hedged_conditions:
        problems.append(f"rule {r + 1} weighs its activation before a hedge said on its "
                        "conclusion acts on it (fuzzylite's `then y is seldom z with w`: "
                        "seldom(w a)), which the format cannot say")
    if r in rb.conditions and np.any(rb.conditions[r][:, 0] == CondOp.CONCLUDED) \
            and not hedged_conditions:
        problems.append(f"rule {r + 1} comes from a FIS row with a hedge on a consequent (the "
                        "Octave toolkit's strength^(1/p), fuzzylite's hedge carried on to the "
                        "later conclusions), which the format cannot say")
    if not condition and says_any and rb.inputs and "any" not in rb.inputs[0].names:
        condition = f"{rb.inputs[0].name} is any"
    elif not condition:
        problems.append(f"rule {r + 1} has no clause, which the format cannot say")
    conclusions = [f"{say(v.name)} is {say(v.names[int(rb.consequents[r, o])])}"
                   for o, v in enumerate(rb.outputs) if rb.consequents[r, o] >= 0]
    text = f"if {condition} then {also.join(conclusions)}"
    if rb.weights[r] != 1.0:
        text += f" with {num(rb.weights[r])}"
    return text


def unsayable_hedges(model: Model, hedge_words: dict[Hedge, str], fmt: str) -> list[str]:
    rb = model.rulebase
    used = {Hedge(int(h)) for h in np.unique(rb.hedges)} - {Hedge.NONE}
    used |= {Hedge(int(h)) for p in rb.conditions.values() for h in p[:, 3]} - {Hedge.NONE}
    return [f"hedge `{h.name.lower()}` has no equivalent in {fmt}"
            for h in sorted(used) if h not in hedge_words]


def peaks_instead(model: Model, fmt: str) -> tuple[list[Variable], list[str]]:
    """The outputs as singletons at their peaks, for peak-based defuzzifiers in formats whose
    peak-based defuzzifier needs singleton (or linear) terms (the numbers it gives do not
    change)."""
    changed, notes = [], []
    for v in model.rulebase.outputs:
        kept = np.isin(v.kinds, (TermKind.SINGLETON, TermKind.LINEAR, TermKind.FUNCTION))
        if np.all(kept):
            changed.append(v)
            continue
        peaks = np.where(kept, v.params[:, 0], v.peaks())
        params = np.where(kept[:, None], v.params, 0.0)
        params[:, 0] = peaks
        changed.append(Variable(v.name, v.lo, v.hi, list(v.names),
                                np.where(kept, v.kinds, int(TermKind.SINGLETON)), params,
                                default=v.default, coefficients=v.coefficients,
                                formulas=v.formulas, lock_previous=v.lock_previous))
        notes.append(f"`{v.name}`'s terms are written as singletons at their peaks "
                     f"({', '.join(num(p) for p in peaks)}): {fmt}'s peak-based defuzzifier "
                     "needs singletons; the outputs are the same, the term shapes are not kept")
    return changed, notes


def unsayable_functions(model: Model, fmt: str, formulas: bool, lock: bool) -> list[str]:
    """Problems for a format that cannot write Function terms (`formulas` False) or an output
    that holds its value (`lock` False): fuzzylite's FLL, FCL and FIS can say the first."""
    problems = []
    for rb in model.blocks:
        for v in rb.inputs + rb.outputs:
            for t in (v.formulas or {}) if not formulas else ():
                problems.append(f"{fmt} has no formula terms: `{v.names[t]}` of `{v.name}` is "
                                f"Function {v.formulas[t].infix()}; write FLL instead")
            if v.lock_previous and not lock:
                problems.append(f"{fmt} cannot say that `{v.name}` holds its last value where "
                                "no rule fires (lock-previous: write FLL or FCL)")
    return problems


def compound_negations(model: Model, fmt: str) -> list[str]:
    """Problems for a format without `not` around a compound condition (fuzzylite's `not` is a
    hedge on one clause)."""
    rb = model.rulebase
    return [f"rule {r + 1} negates a compound condition, which {fmt} cannot say"
            for r, p in sorted(rb.conditions.items())
            if any(op == CondOp.NOT and p[k - 1, 0] != CondOp.CLAUSE
                   for k, op in enumerate(p[:, 0]))]


def own_output_choices(model: Model, fmt: str) -> list[str]:
    """Problems for a format writer that says one aggregation and defuzzifier for the rule
    base: the outputs that have their own."""
    rb = model.rulebase
    return [f"output `{name}` has its own {agg.name.lower()} aggregation and "
            f"{defuzz.name.lower()} defuzzifier; the {fmt} writer says one for the rule base"
            for name, (agg, defuzz) in rb.output_choices.items()
            if (agg, defuzz) != (rb.inference.aggregation, rb.inference.defuzzifier)]
