"""The Takagi-Sugeno rule base as ANFIS sees it: outputs linear in the consequents, and
analytic derivatives with respect to the premises (every input shape whose registry record has
a derivative, fuzzyc.semantics.shapes) and the rule weights.

It applies to one rule block of flat AND rules (no `not`, no hedges) under the product t-norm,
every output defuzzified by weighted_average or weighted_sum, every consequent a singleton or
a linear term.  The memberships come from the engine (`memberships`), the rest is the
engine's arithmetic written out (activation floor, linear terms reading clamped inputs, the
default where no rule fires), and the tests hold it to the engine on every rule base they fit.
"""
from __future__ import annotations

import numpy as np

from ..engine.membership import linear_coefficients, memberships
from ..engine.norms import firing
from ..semantics.model import (ACTIVATION_FLOOR, Connective, Defuzzifier, Hedge, Model, TermKind,
                               TNorm)
from ..semantics.shapes import SHAPES
from .space import Space

SUGENO = (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.WEIGHTED_SUM)


def sugeno_problem(model: Model) -> str:
    """'' when the model has the Takagi-Sugeno form this module computes, else why not."""
    if len(model.blocks) != 1:
        return "several rule blocks"
    rb = model.blocks[0]
    if rb.conditions or np.any(rb.connective != Connective.AND) or np.any(rb.negated) \
            or np.any(rb.hedges != Hedge.NONE):
        return "rules other than flat conjunctions"
    if rb.inference.and_ != TNorm.PRODUCT:
        return "an `and` other than product"
    for o, var in enumerate(rb.outputs):
        if rb.inference_of(o).defuzzifier not in SUGENO or var.lock_previous:
            return f"output `{var.name}` is not weighted_average / weighted_sum"
        if np.any((var.kinds != TermKind.SINGLETON) & (var.kinds != TermKind.LINEAR)):
            return f"output `{var.name}` has terms other than singletons and linear"
    return ""


class SugenoForm:
    """y(x; theta) for the working copy of `space`, its design matrix in the consequents and
    its Jacobian in everything tuned."""

    def __init__(self, space: Space, x: np.ndarray):
        self.space = space
        self.x = np.asarray(x, dtype=float)
        rb = space.model.blocks[0]
        self.n_inputs = len(rb.inputs)
        kinds = {n.kind for n in space.numbers}
        self.analytic = "param" not in kinds and all(
            n.slots and SHAPES[self._premise_kind(n)].derivative is not None
            for n in space.numbers if n.kind == "term" and n.var in {v.name for v in rb.inputs})
        outputs = {v.name for v in rb.outputs}
        # consequent numbers: the outputs' singleton values and linear coefficients
        self.linear_part = np.array([n.kind == "term" and n.var in outputs
                                     for n in space.numbers])

    def _premise_kind(self, n) -> TermKind:
        rb = self.space.model.blocks[0]
        var = rb.inputs[rb.input_index(n.var)]
        return TermKind(int(var.kinds[var.index(n.term)]))

    # ---- the forward pass
    def _strengths(self):
        """mu products per rule: act (N, R) after the weight, and M (N, R, I) the clauses' mu
        (1 where a rule has no clause on an input)."""
        rb = self.space.model.blocks[0]
        n = self.x.shape[0]
        M = np.ones((n, rb.n_rules, self.n_inputs))
        for i, var in enumerate(rb.inputs):
            mu = memberships(var, self.x[:, i])
            used = rb.antecedents[:, i] >= 0
            M[:, used, i] = mu[:, rb.antecedents[used, i]]
        act = np.asarray(rb.weights)[None, :] * np.prod(M, axis=2)
        return act, M

    def _term_values(self, o: int) -> np.ndarray:
        """z (N, T) of output o's terms at the samples (linear terms at the clamped inputs)."""
        rb = self.space.model.blocks[0]
        var = rb.outputs[o]
        coef = linear_coefficients(var, self.n_inputs)
        lo = np.array([v.lo for v in rb.inputs])
        hi = np.array([v.hi for v in rb.inputs])
        z = np.clip(self.x, lo, hi) @ coef[:, 1:].T + coef[:, 0]
        return np.where(var.kinds == TermKind.LINEAR, z, var.peaks())

    def predict(self, theta: np.ndarray) -> np.ndarray:
        """(N, O) outputs at theta."""
        self.space.apply(theta)
        act, _ = self._strengths()
        fired = firing(act)
        return np.column_stack([self._output(fired, o)[0]
                                for o in range(len(self.space.model.blocks[0].outputs))])

    def _output(self, fired: np.ndarray, o: int):
        rb = self.space.model.blocks[0]
        cons = rb.consequents[:, o]
        rules = cons >= 0
        z = self._term_values(o)[:, cons[rules]]                     # (N, R_o)
        f = fired[:, rules]
        total = f.sum(axis=1)
        some = total > 0
        if rb.inference_of(o).defuzzifier == Defuzzifier.WEIGHTED_AVERAGE:
            y = np.where(some, (f * z).sum(axis=1) / np.where(some, total, 1.0), 0.0)
            share = f / np.where(some, total, 1.0)[:, None]
        else:
            y = (f * z).sum(axis=1)
            share = f
        y = np.where(some, y, rb.outputs[o].default)
        return y, share, rules, z, total, some

    # ---- derivatives
    def jacobian(self, theta: np.ndarray, columns=None) -> np.ndarray:
        """d y / d theta, (N * O, P) with rows sample-major (as predict(theta).ravel());
        `columns`: only those numbers' columns (indices into theta), in that order."""
        self.space.apply(theta)
        rb = self.space.model.blocks[0]
        act, M = self._strengths()
        fired = firing(act)
        live = act >= ACTIVATION_FLOOR         # a rule under the floor does not fire at all
        outs = [self._output(fired, o) for o in range(len(rb.outputs))]
        which = range(self.space.size) if columns is None else [int(c) for c in columns]
        n, P = self.x.shape[0], len(which)
        J = np.zeros((n, len(rb.outputs), P))
        for k, c in enumerate(which):
            for o, (y, share, rules, z, total, some) in enumerate(outs):
                J[:, o, k] = self._column(self.space.numbers[c], o, y, share, rules, z, total,
                                          some, act, M, live)
        return J.reshape(n * len(rb.outputs), P)

    def _column(self, number, o, y, share, rules, z, total, some, act, M, live):
        rb = self.space.model.blocks[0]
        out = rb.outputs[o]
        weighted_average = rb.inference_of(o).defuzzifier == Defuzzifier.WEIGHTED_AVERAGE
        if number.kind == "term" and number.var == out.name:         # a consequent
            t = out.index(number.term)
            concl = rb.consequents[rules, o] == t
            factor = np.ones(self.x.shape[0])       # a singleton's value, a linear c0
            if out.kinds[t] == TermKind.LINEAR and number.index > 0:
                read = rb.inputs[number.index - 1]   # c_i weighs input i, clamped
                factor = np.clip(self.x[:, number.index - 1], read.lo, read.hi)
            return np.where(some, share[:, concl].sum(axis=1) * factor, 0.0)
        if number.kind == "term" and any(v.name == number.var for v in rb.outputs):
            return np.zeros(self.x.shape[0])          # another output's consequent
        # d act_r / d theta for every rule, then through the defuzzifier
        dact = np.zeros_like(act)
        if number.kind == "weight":
            r = number.rule_index
            dact[:, r] = np.prod(M[:, r, :], axis=1)
        else:
            i = rb.input_index(number.var)
            var = rb.inputs[i]
            t = var.index(number.term)
            dmu = _dmu(TermKind(int(var.kinds[t])), var.params[t], number.slots, self.x[:, i])
            users = rb.antecedents[:, i] == t
            others = np.prod(np.delete(M[:, users, :], i, axis=2), axis=2)
            dact[:, users] = np.asarray(rb.weights)[users] * dmu[:, None] * others
        dact = np.where(live, dact, 0.0)[:, rules]
        if weighted_average:
            safe = np.where(some, total, 1.0)
            grad = ((z - y[:, None]) * dact).sum(axis=1) / safe
        else:
            grad = (z * dact).sum(axis=1)
        return np.where(some, grad, 0.0)

    def design(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(A, b): predict(theta).ravel() == A @ theta[linear_part] + b, A (N * O, C)."""
        J = self._consequent_columns(theta)
        y = self.predict(theta).ravel()
        return J, y - J @ theta[self.linear_part]

    def _consequent_columns(self, theta: np.ndarray) -> np.ndarray:
        self.space.apply(theta)
        rb = self.space.model.blocks[0]
        act, M = self._strengths()
        fired = firing(act)
        outs = [self._output(fired, o) for o in range(len(rb.outputs))]
        numbers = [n for n, lin in zip(self.space.numbers, self.linear_part) if lin]
        n = self.x.shape[0]
        A = np.zeros((n, len(rb.outputs), len(numbers)))
        for k, number in enumerate(numbers):
            for o, parts in enumerate(outs):
                A[:, o, k] = self._column(number, o, *parts, act, M, act >= ACTIVATION_FLOOR)
        return A.reshape(n * len(rb.outputs), len(numbers))


def _dmu(kind: TermKind, params, slots: tuple[int, ...], x: np.ndarray) -> np.ndarray:
    """d mu / d (a written number) at x: the shape record's derivative with respect to the
    model params the number sets (a tri's b is the trapezoid's b and c: their sum)."""
    d = SHAPES[kind].derivative(x[:, None], np.asarray(params, dtype=float)[None, :])[:, 0, :]
    d = d[:, list(slots)].sum(axis=1)
    return np.where(np.isfinite(d), d, 0.0)
