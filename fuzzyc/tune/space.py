"""The search space of a tune: the model's tuned numbers as one vector with its bounds, and a
working copy of the model that takes any vector of the box.

The engine caches a rule base's tables by the identity of its arrays (`set_entries`), so a
candidate assigns new arrays: the next evaluation sees it, nothing is written in place."""
from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np

from ..semantics.model import Model, Variable, set_entries
from ..semantics.tunable import TunedNumber


class Space:
    """x0 (as written), lo, hi: one entry per TunedNumber of `model.tunables`, in order."""

    def __init__(self, model: Model, numbers: list[TunedNumber] | None = None):
        self.numbers = list(model.tunables if numbers is None else numbers)
        if not self.numbers:
            raise ValueError(f"`{model.name}` has no `tune` section: nothing may move; "
                             "add one naming what may")
        self.x0 = np.array([n.value for n in self.numbers], dtype=float)
        self.lo = np.array([n.lo for n in self.numbers], dtype=float)
        self.hi = np.array([n.hi for n in self.numbers], dtype=float)
        self.model = copy.deepcopy(model)        # the working copy every candidate goes to
        self._variables = {}                      # name -> every Variable object of that name
        for rb in self.model.blocks:
            for v in rb.inputs + rb.outputs:
                self._variables.setdefault(v.name, [])
                if all(v is not w for w in self._variables[v.name]):
                    self._variables[v.name].append(v)

    @property
    def size(self) -> int:
        return len(self.numbers)

    def indices(self, kind: str) -> np.ndarray:
        return np.array([i for i, n in enumerate(self.numbers) if n.kind == kind], dtype=int)

    def apply(self, x: np.ndarray) -> Model:
        """The working copy with the tuned numbers set to x (and every other number as
        written)."""
        x = np.asarray(x, dtype=float)
        by_var: dict[str, list[tuple[TunedNumber, float]]] = {}
        weights: dict[int, list[tuple[int, float]]] = {}
        for n, value in zip(self.numbers, x):
            if n.kind == "term":
                by_var.setdefault(n.var, []).append((n, float(value)))
            elif n.kind == "weight":
                weights.setdefault(n.block, []).append((n.rule_index, float(value)))
            else:
                self.model.params[n.param] = replace(self.model.params[n.param],
                                                     value=float(value))
        for name, moved in by_var.items():
            for var in self._variables.get(name, []):
                _set_terms(var, moved)
        for b, changes in weights.items():
            rb = self.model.blocks[b]
            rules = [r for r, _ in changes]
            set_entries(rb, "weights", rules, [w for _, w in changes])
        return self.model

    def values(self, model: Model) -> np.ndarray:
        """The tuned numbers as they are in `model` (the inverse of apply)."""
        out = []
        for n in self.numbers:
            if n.kind == "param":
                out.append(model.params[n.param].value)
            elif n.kind == "weight":
                out.append(float(model.blocks[n.block].weights[n.rule_index]))
            else:
                var = next(v for rb in model.blocks for v in rb.inputs + rb.outputs
                           if v.name == n.var)
                out.append(float(np.asarray(_numbers_of(var, var.index(n.term), n))[n.index]))
        return np.array(out)


def _numbers_of(var: Variable, t: int, n: TunedNumber):
    if n.shape in ("linear", "discrete"):
        return var.term_numbers(t)
    return [var.params[t][s[0]] if s else 0.0 for s in
            [n.slots if i == n.index else () for i in range(n.index + 1)]]


def _set_terms(var: Variable, moved: list[tuple[TunedNumber, float]]) -> None:
    params = np.array(var.params, dtype=float)
    coefficients = dict(var.coefficients) if var.coefficients else None
    points = dict(var.points) if var.points else None
    for n, value in moved:
        t = var.index(n.term)
        if n.shape == "discrete":
            row = np.array(points[t], dtype=float)
            row.ravel()[n.index] = value
            points[t] = row
        elif n.shape == "linear" and coefficients and t in coefficients:
            row = np.array(coefficients[t], dtype=float)
            row[n.index] = value
            coefficients[t] = row
        elif n.shape == "linear":
            params[t, n.index] = value
        else:
            params[t, list(n.slots)] = value
    var.params = params
    if coefficients is not None:
        var.coefficients = coefficients
    if points is not None:
        var.points = points
