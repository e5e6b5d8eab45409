"""The file's table and grid properties (monotone, covers, bounded) during and after a tune.

During the search each property is a penalty over a grid of the input space (residuals that
are 0 where it holds, so least squares pushes them to 0); after it, the verifier decides the
candidate, and one that loses a property that held before is rejected with the reason and its
counterexample: the points the verifier found (and a few around them) join that property's
penalty set for the next round of the search (counterexample-guided)."""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..engine import inference as engine
from ..semantics.model import Model, Property
from ..verifier.result import Evidence, Result, Status
from ..verifier.runner import Options, check_property
from ..verifier.space import dense_grid, tensor_points
from .sugeno import SugenoForm, sugeno_problem

KINDS = ("monotone", "covers", "bounded")
KEPT = (Status.PROVED, Status.HELD)
PENALTY_POINTS = 400          # grid points per property during the search
MARGIN = 1e-4       # of the output's range (a level for covers): the penalty aims this far in
SEGMENT_PARTS = 4             # a monotone counterexample's segment, cut in this many pairs


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
    verdict, why, _ = check(model, prop, seed)
    return verdict, why


def check(model: Model, prop: Property, seed: int) -> tuple[Status, str, Evidence | None]:
    """The verifier's verdict, why it failed and the failing evidence (its counterexample)."""
    evidence = check_property(model, prop, Options(seed=seed, max_examples=50))
    result = Result(prop, prop.text, evidence)
    worst = result.violation
    return result.status, worst.detail if worst else "", worst


@dataclass
class Item:
    """One property's penalty set: grid points, and the counterexamples added to them."""
    prop: Property
    points: np.ndarray                 # (M, I): bounded, covers (covers: its inputs only)
    shape: list[int] | None = None     # monotone: the tensor grid's shape
    keep: list[int] | None = None      # covers: the inputs it reads
    pairs: list = field(default_factory=list)    # monotone: (a, b) with b after a along x_k
    added: int = 0                     # counterexample points added
    form: object = None                # bounded: its Takagi-Sugeno form, when it has one


class Penalties:
    """Residuals that are 0 where the properties hold, on grids fixed at the start and the
    verifier's counterexamples added as they come."""

    def __init__(self, model: Model, props: list[Property]):
        rb = model.rulebase
        self.items: list[Item] = []
        self.step = [np.ptp(ax) / max(len(ax) - 1, 1)
                     for ax in dense_grid(rb, [], PENALTY_POINTS)]
        for p in props:
            a = p.args
            if p.kind == "monotone":
                axes = dense_grid(rb, a["where"], PENALTY_POINTS)
                if all(len(ax) > 1 for ax in axes[rb.input_index(a["input"]):][:1]):
                    self.items.append(Item(p, tensor_points(axes), [len(ax) for ax in axes]))
            elif p.kind == "bounded":
                self.items.append(Item(p, tensor_points(dense_grid(rb, [], PENALTY_POINTS))))
            elif p.kind == "covers":
                keep = [rb.input_index(n) for n in a["inputs"]]
                if not rb.conditions:
                    axes = dense_grid(rb, [], PENALTY_POINTS)
                    self.items.append(Item(p, tensor_points([axes[i] for i in keep]),
                                           keep=keep))

    def __bool__(self) -> bool:
        return bool(self.items)

    def size(self, prop: Property) -> int:
        """The points in a property's penalty set (a monotone pair counts its two)."""
        item = self._item(prop)
        return 0 if item is None else len(item.points) + 2 * len(item.pairs)

    def _item(self, prop: Property) -> Item | None:
        return next((i for i in self.items if i.prop is prop), None)

    def add(self, model: Model, prop: Property, evidence: Evidence | None) -> int:
        """Add a counterexample of `prop` (the verifier's failing evidence) to its penalty set:
        bounded and covers the point and its neighbours half a penalty-grid step away along
        each input (the worst point is rarely the only one out); monotone the segment from
        `point` to `to_point`, cut in SEGMENT_PARTS pairs. Returns the points added (0 when
        the evidence has no point, or no penalty stands for the property)."""
        item = self._item(prop)
        if item is None or evidence is None or evidence.point is None:
            return 0
        rb = model.rulebase
        x = np.array([evidence.point.get(v.name, 0.5 * (v.lo + v.hi)) for v in rb.inputs])
        if prop.kind == "monotone":
            if evidence.to_point is None:
                return 0
            b = np.array([evidence.to_point[v.name] for v in rb.inputs])
            cuts = np.linspace(0.0, 1.0, SEGMENT_PARTS + 1)[:, None]
            path = x + cuts * (b - x)
            item.pairs += list(zip(path[:-1], path[1:]))
            new = 2 * SEGMENT_PARTS
        else:
            lo = np.array([v.lo for v in rb.inputs])
            hi = np.array([v.hi for v in rb.inputs])
            near = [x]
            for i, h in enumerate(self.step):
                for s in (-0.5, 0.5):
                    moved = x.copy()
                    moved[i] = np.clip(x[i] + s * h, lo[i], hi[i])
                    near.append(moved)
            near = np.unique(np.array(near), axis=0)
            if item.keep is not None:
                near = np.unique(near[:, item.keep], axis=0)
            item.points = np.vstack([item.points, near])
            new = len(near)
        item.added += new
        return new

    def residuals(self, model: Model) -> np.ndarray:
        out = [self._residual(item, model) for item in self.items]
        return np.concatenate(out) if out else np.zeros(0)

    def jacobian(self, space, theta: np.ndarray, differences) -> np.ndarray:
        """d residuals / d theta: analytic for `bounded` on a Takagi-Sugeno output (the
        form's own derivatives at the penalty points), else differences(fun, theta)."""
        rows = []
        for item in self.items:
            form = self._form(space, item)
            if form is None:
                rows.append(differences(lambda t: self._residual(item, space.apply(t)), theta))
                continue
            a = item.prop.args
            o = space.model.blocks[0].output_index(a["signal"])
            y = form.predict(theta)[:, o]
            J = form.jacobian(theta)[o::form_outputs(space)]
            margin = MARGIN * (a["hi"] - a["lo"])
            sign = np.where(y > a["hi"] - margin, 1.0, np.where(y < a["lo"] + margin, -1.0, 0.0))
            rows.append(sign[:, None] * J)
        return np.vstack(rows) if rows else np.zeros((0, len(theta)))

    def _form(self, space, item: Item):
        """A Takagi-Sugeno form over a bounded item's points, rebuilt when points are added."""
        if item.prop.kind != "bounded" or sugeno_problem(space.model):
            return None
        if item.form is None or len(item.form.x) != len(item.points):
            item.form = SugenoForm(space, item.points)
        return item.form if item.form.analytic else None

    def _residual(self, item: Item, model: Model) -> np.ndarray:
        rb = model.rulebase
        p, a = item.prop, item.prop.args
        if p.kind == "monotone":
            # slopes, not steps (per the input's range), aiming MARGIN above 0: a short
            # counterexample segment weighs as much as a grid step
            o, k = rb.output_index(a["output"]), rb.input_index(a["input"])
            sign = 1.0 if a["direction"] == "increasing" else -1.0
            span = rb.inputs[k].hi - rb.inputs[k].lo
            margin = MARGIN * (rb.outputs[o].hi - rb.outputs[o].lo)
            grid = item.points[:int(np.prod(item.shape))]
            y = engine.evaluate(rb, grid)[:, o].reshape(item.shape)
            dx = np.diff(grid[:, k].reshape(item.shape), axis=k) / span
            out = [np.minimum(0.0, np.diff(y, axis=k) * sign / dx - margin).ravel()]
            if item.pairs:
                ab = np.vstack([np.array(pair) for pair in item.pairs])
                ends = engine.evaluate(rb, ab)
                dx = np.maximum(np.abs(ab[1::2, k] - ab[0::2, k]) / span, 1e-12)
                out.append(np.minimum(0.0, (ends[1::2, o] - ends[0::2, o]) * sign / dx
                                      - margin))
            return np.concatenate(out)
        if p.kind == "bounded":
            y = engine.evaluate(rb, item.points)[:, rb.output_index(a["signal"])]
            margin = MARGIN * (a["hi"] - a["lo"])
            return np.maximum(0.0, np.maximum(y - (a["hi"] - margin), (a["lo"] + margin) - y))
        keep = item.keep
        projected = replace(rb, inputs=[rb.inputs[i] for i in keep],
                            antecedents=rb.antecedents[:, keep],
                            negated=rb.negated[:, keep], hedges=rb.hedges[:, keep])
        best = engine.activations(projected, item.points).max(axis=1)
        return np.maximum(0.0, a["level"] + MARGIN - best)


def form_outputs(space) -> int:
    return len(space.model.blocks[0].outputs)
