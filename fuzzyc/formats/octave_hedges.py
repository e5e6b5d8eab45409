"""The Octave toolkit's hedges on Mamdani consequents, for `--semantics octave`.

A FIS rule index `t.h` on an output is a hedge said on a conclusion; the model keeps it as
said (CondOp.CONCLUDED steps closing the rule's clause program), and its own semantics read it
as eval_rules_sugeno.m does: the strength raised to 1/p.  For a Mamdani output the toolkit does
something else: eval_rules_mamdani.m evaluates the consequent's membership function with the
hedge (evalmf_private.m: y = mu(u) ^ p) and applies the implication to the rule's plain
strength, so the rule concludes the set mu^p.  `octave_mamdani_hedges` gives the rule base that
computes that: each rule's trailing CONCLUDED steps dropped (a carried one is no step of the
toolkit's at all) and each of its conclusions moved to a further term of the output, mu^p as a
Function term (`formats.complement.membership_formula`, or the term's own formula)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..engine.formula import parse_formula
from ..engine.membership import HEDGE_EXPONENT
from ..semantics.model import CondOp, RuleBase, TermKind, Variable
from .complement import membership_formula


def _power_text(var: Variable, t: int, power: float) -> str | None:
    kind = TermKind(int(var.kinds[t]))
    if kind == TermKind.FUNCTION:
        formula = (var.formulas or {}).get(t)
        mu = None if formula is None or not formula.names() <= {"x"} else formula.infix()
    else:
        mu = membership_formula(kind, np.asarray(var.params[t], dtype=float))
    return None if mu is None else f"({mu}) ^ ({power!r})"


def octave_mamdani_hedges(rb: RuleBase) -> RuleBase:
    """rb with its Mamdani rules' consequent hedges as the Octave toolkit applies them (see
    the module docstring); rb itself when no rule has one (or a term has no formula here)."""
    outputs = [replace(v, names=list(v.names), kinds=np.array(v.kinds),
                       params=np.array(v.params, dtype=float), formulas=dict(v.formulas or {}),
                       term_locs=list(v.term_locs)) for v in rb.outputs]
    consequents = rb.consequents.copy()
    conditions = dict(rb.conditions)
    added: dict[tuple[int, int, float], int] = {}
    changed = False
    for r, program in rb.conditions.items():
        k = len(program)
        while k > 1 and program[k - 1, 0] == CondOp.CONCLUDED:
            k -= 1
        if k == len(program):
            continue
        power = float(np.prod([HEDGE_EXPONENT[int(h)] for _, _, t, h in program[k:] if t]))
        moved = {}
        for o in np.flatnonzero(consequents[r] >= 0):
            t = int(consequents[r, o])
            if power == 1.0:
                continue
            if (o, t, power) not in added:
                text = _power_text(rb.outputs[o], t, power)
                if text is None:
                    break
                var = outputs[o]
                var.formulas[var.n_terms] = parse_formula(text)
                var.names.append(f"{var.names[t]}^{power:g}")
                var.kinds = np.append(var.kinds, int(TermKind.FUNCTION))
                var.params = np.vstack([var.params, np.zeros((1, var.params.shape[1]))])
                if var.term_locs:
                    var.term_locs.append(var.term_locs[t])
                if var.learnable is not None:
                    var.learnable = np.append(var.learnable, False)
                added[o, t, power] = var.n_terms - 1
            moved[o] = added[o, t, power]
        else:
            conditions[r] = program[:k]
            for o, t in moved.items():
                consequents[r, o] = t
            changed = True
    if not changed:
        return rb
    return replace(rb, outputs=outputs, consequents=consequents, conditions=conditions)
