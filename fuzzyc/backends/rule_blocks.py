"""The rule bases a C header emits for a model: its rule blocks in order, each split into one
rule base per distinct (aggregation, defuzzifier) of its outputs where outputs have their own
(fuzzylite's per-variable defuzzifier, a hybrid FIS).  The split keeps every rule with its
conclusions on that group's outputs only; a rule's activation does not depend on the output,
and each output aggregates and defuzzifies its own conclusions, so the split rule bases give
each output what the block gives it (fuzzyc.semantics.model, RuleBase.inference_of)."""
from __future__ import annotations

from dataclasses import replace

from ..semantics.model import Model, RuleBase


def split_by_output_choices(rb: RuleBase) -> list[RuleBase]:
    """rb as rule bases of one inference each, in the order of their first output; rb itself
    where every output follows the block's inference."""
    if not rb.output_choices:
        return [rb]
    groups: dict[tuple, list[int]] = {}
    for o in range(len(rb.outputs)):
        inf = rb.inference_of(o)
        groups.setdefault((inf.aggregation, inf.defuzzifier), []).append(o)
    if len(groups) == 1:
        o = next(iter(groups.values()))[0]
        return [replace(rb, inference=rb.inference_of(o), output_choices={})]
    # the part's name is data (the C writers escape it where they print it), not C text
    return [replace(rb, outputs=[rb.outputs[o] for o in outs],
                    consequents=rb.consequents[:, outs], inference=rb.inference_of(outs[0]),
                    output_choices={},
                    name=(rb.name or "rules") + " (" + ", ".join(rb.outputs[o].name
                                                                 for o in outs) + ")")
            for outs in groups.values()]


def emitted_blocks(model: Model) -> list[RuleBase]:
    """The rule bases the C headers emit, in evaluation order."""
    return [part for rb in model.blocks for part in split_by_output_choices(rb)]
