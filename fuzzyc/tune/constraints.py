"""The file's table and grid properties (monotone, covers, bounded) during and after a tune.

During the search each property is a penalty over a fixed grid of the input space (residuals
that are 0 where it holds, so least squares pushes them to 0); after it, the verifier decides
the candidate, and one that loses a property that held before is rejected with the reason."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..engine import inference as engine
from ..semantics.model import Model, Property
from ..verifier.result import Result, Status
from ..verifier.runner import Options, check_property
from ..verifier.space import dense_grid, tensor_points

KINDS = ("monotone", "covers", "bounded")
KEPT = (Status.PROVED, Status.HELD)
PENALTY_POINTS = 400          # grid points per property during the search


@dataclass
class PropertyCheck:
    text: str
    before: str          # the verifier's status before tuning
    after: str = ""      # and on the result
    detail: str = ""     # why it failed, when it did


def kept_properties(model: Model) -> list[Property]:
    """The properties the tuner keeps: the file's monotone, covers and bounded (on a rule-base
    output)."""
    outputs = {v.name for rb in model.blocks for v in rb.outputs}
    return [p for p in model.properties if p.kind in KINDS
            and (p.kind != "bounded" or p.args["signal"] in outputs)]


def status(model: Model, prop: Property, seed: int) -> tuple[Status, str]:
    evidence = check_property(model, prop, Options(seed=seed, max_examples=50))
    result = Result(prop, prop.text, evidence)
    worst = next((e.detail for e in evidence if e.status == Status.VIOLATED), "")
    return result.status, worst


class Penalties:
    """Residuals that are 0 where the properties hold, on grids fixed at the start."""

    def __init__(self, model: Model, props: list[Property]):
        rb = model.rulebase
        self.items = []
        for p in props:
            a = p.args
            if p.kind == "monotone":
                axes = dense_grid(rb, a["where"], PENALTY_POINTS)
                if all(len(ax) > 1 for ax in axes[rb.input_index(a["input"]):][:1]):
                    self.items.append((p, tensor_points(axes), [len(ax) for ax in axes]))
            elif p.kind == "bounded":
                self.items.append((p, tensor_points(dense_grid(rb, [], PENALTY_POINTS)), None))
            elif p.kind == "covers":
                keep = [rb.input_index(n) for n in a["inputs"]]
                if not rb.conditions:
                    axes = dense_grid(rb, [], PENALTY_POINTS)
                    self.items.append((p, tensor_points([axes[i] for i in keep]), keep))

    def __bool__(self) -> bool:
        return bool(self.items)

    def residuals(self, model: Model) -> np.ndarray:
        rb = model.rulebase
        out = []
        for p, points, extra in self.items:
            a = p.args
            if p.kind == "monotone":
                o, k = rb.output_index(a["output"]), rb.input_index(a["input"])
                y = engine.evaluate(rb, points)[:, o].reshape(extra)
                sign = 1.0 if a["direction"] == "increasing" else -1.0
                out.append(np.minimum(0.0, np.diff(y, axis=k) * sign).ravel())
            elif p.kind == "bounded":
                y = engine.evaluate(rb, points)[:, rb.output_index(a["signal"])]
                out.append(np.maximum(0.0, np.maximum(y - a["hi"], a["lo"] - y)))
            else:
                keep = extra
                projected = replace(rb, inputs=[rb.inputs[i] for i in keep],
                                    antecedents=rb.antecedents[:, keep],
                                    negated=rb.negated[:, keep], hedges=rb.hedges[:, keep])
                best = engine.activations(projected, points).max(axis=1)
                out.append(np.maximum(0.0, a["level"] - best))
        return np.concatenate(out) if out else np.zeros(0)
