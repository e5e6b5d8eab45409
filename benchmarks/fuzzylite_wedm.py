"""The same rule base as a pyfuzzylite 8 engine, for the benchmark's comparison.

Two engines from one fuzzyc rule base (inputs: Triangle/Trapezoid terms, shoulders as Ramp):
- tsk=True: Constant output terms at the fuzzyc terms' peaks, Minimum conjunction,
  WeightedAverage = sum_r act_r z_r / sum_r act_r over the rules.  This is fuzzyc's
  WEIGHTED_AVERAGE, not the paper's eq. 2 (center of area takes the max over the rules that
  conclude the same term); the two agree only where each term is concluded by one firing rule.
- tsk=False: Mamdani, Minimum implication, Maximum aggregation, Centroid (sampled at
  fuzzylite's default resolution of 1000 points), against fuzzyc's exact centroid.
"""
from __future__ import annotations

import fuzzylite as fl
import numpy as np


def _term(name: str, a: float, b: float, c: float, d: float) -> fl.Term:
    if np.isneginf(a):
        return fl.Ramp(name, d, c)
    if np.isposinf(d):
        return fl.Ramp(name, a, b)
    return fl.Triangle(name, a, b, d) if b == c else fl.Trapezoid(name, a, b, c, d)


def _terms(v) -> list[fl.Term]:
    return [_term(n, *p) for n, p in zip(v.names, v.params)]


def build(rb, tsk: bool) -> fl.Engine:
    inputs = [fl.InputVariable(v.name, minimum=v.lo, maximum=v.hi, terms=_terms(v))
              for v in rb.inputs]
    if tsk:
        outputs = [fl.OutputVariable(v.name, minimum=v.lo, maximum=v.hi, default_value=v.default,
                                     defuzzifier=fl.WeightedAverage(),
                                     terms=[fl.Constant(n, p) for n, p in zip(v.names, v.peaks())])
                   for v in rb.outputs]
    else:
        outputs = [fl.OutputVariable(v.name, minimum=v.lo, maximum=v.hi, default_value=v.default,
                                     aggregation=fl.Maximum(), defuzzifier=fl.Centroid(),
                                     terms=_terms(v)) for v in rb.outputs]
    engine = fl.Engine("wedm", input_variables=inputs, output_variables=outputs)
    block = fl.RuleBlock(conjunction=fl.Minimum(), implication=None if tsk else fl.Minimum(),
                         activation=fl.General())
    for r in range(rb.n_rules):
        when = " and ".join(f"{v.name} is {v.names[t]}"
                            for v, t in zip(rb.inputs, rb.antecedents[r]) if t >= 0)
        then = " and ".join(f"{v.name} is {v.names[t]}"
                            for v, t in zip(rb.outputs, rb.consequents[r]) if t >= 0)
        block.rules.append(fl.Rule.create(f"if {when} then {then}", engine))
    engine.rule_blocks = [block]
    return engine


def evaluate(engine: fl.Engine, x: np.ndarray) -> np.ndarray:
    """x (N, I) -> (N, O), through pyfuzzylite's vectorized process()."""
    for i, v in enumerate(engine.input_variables):
        v.value = x[:, i]
    engine.process()
    return np.stack([np.atleast_1d(v.value) for v in engine.output_variables], axis=1)
