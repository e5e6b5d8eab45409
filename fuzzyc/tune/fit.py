"""Fitting a model's tuned numbers to data: least squares within the declared bounds.

Takagi-Sugeno rule bases (fuzzyc.tune.sugeno) get the hybrid rule of ANFIS: each pass solves
the consequents by bounded linear least squares with the premises fixed, then moves the
premises (and rule weights) by a few trust-region least-squares steps with the analytic
Jacobian; a joint polish of everything follows.  Other rule bases get scipy's trust-region
least squares with finite differences through the engine.  The file's monotone, covers and
bounded properties that held before are penalties during the search (a few weights in turn)
and decided by the verifier after it (fuzzyc.tune.constraints); when every candidate loses
one, the result is the point nearest the candidate, on the segment from the written numbers
(which kept them), that the verifier accepts (bisection).  Nothing here draws a random
number but the fold split, from the seed: the same data and seed give the same numbers, bit
for bit (the verifier's searches are seeded too)."""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares, lsq_linear

from ..engine import inference as engine
from ..semantics.model import Model
from ..semantics.tunable import TunedNumber
from . import anfis
from .consequent_bounds import CornerBounds, corner_bounds
from .constraints import KEPT, Penalties, PropertyCheck, check, kept_properties, status
from .space import Space
from .sugeno import SugenoForm, sugeno_problem

PENALTY_WEIGHTS = (1e2, 1e4, 1e6)   # rounds 1, 2, 3 and on (the last for every later round)
COUNTEREXAMPLE_ROUNDS = 6         # searches the verifier may reject before the bisection


@dataclass
class FitResult:
    """The tuned numbers and how well they fit. rmse_* are root mean square errors over
    every output column; `validation` is the RMSE on the validation data, or the mean over the
    folds of the held-out RMSE (each fold fitted on the others)."""
    numbers: list[TunedNumber]
    values: np.ndarray
    model: Model                       # a copy of the model with the tuned values
    rmse_before: float
    rmse_after: float
    validation_before: float | None = None
    validation: float | None = None
    method: str = ""
    properties: list[PropertyCheck] = field(default_factory=list)
    rejected: list[str] = field(default_factory=list)
    seed: int = 0


def fit_data(model: Model, x, y, *, validate: tuple | None = None, folds: int | None = None,
             seed: int = 0, passes: int = 20, max_nfev: int | None = None,
             keep_properties: bool = True, method: str = "least_squares") -> FitResult:
    """Fit `model`'s tuned numbers (its `tune` section) to inputs x (N, I) -> outputs y (N, O)
    (columns in the rule base's input / output order; a mapping by name works too).
    validate: (x, y) to report the error on; folds: K-fold cross-validation instead.
    passes: hybrid passes (Takagi-Sugeno); max_nfev: function evaluations of each
    least-squares run (None: scipy's default).  method "anfis" (Takagi-Sugeno): Jang's
    hybrid rule, `passes` epochs of it (fuzzyc.tune.anfis), instead of the hybrid passes and
    the joint least squares."""
    if method not in ("least_squares", "anfis"):
        raise ValueError(f"method is least_squares or anfis, not {method!r}")
    X, Y = _columns(model, x, True), _columns(model, y, False)
    if len(X) != len(Y):
        raise ValueError(f"{len(X)} input rows but {len(Y)} output rows")
    fit = _fit(model, X, Y, seed, passes, max_nfev, keep_properties, method)
    if validate is not None:
        Xv, Yv = _columns(model, validate[0], True), _columns(model, validate[1], False)
        fit.validation_before = _rmse(_predict(model, Xv), Yv)
        fit.validation = _rmse(_predict(fit.model, Xv), Yv)
    elif folds:
        fit.validation = _cross_validate(model, X, Y, folds, seed, passes, max_nfev, method)
    return fit


def _fit(model: Model, X, Y, seed, passes, max_nfev, keep_properties,
         how: str = "least_squares") -> FitResult:
    space = Space(model)
    if any(n.kind == "param" for n in space.numbers):
        names = ", ".join(n.target for n in space.numbers if n.kind == "param")
        raise ValueError(f"params ({names}) move the signal chain, which a fit to data of the "
                         "rule base does not run; tune them in closed loop, or leave them out "
                         "of the `tune` section for this fit")
    if np.any(~np.isfinite(X)) or np.any(~np.isfinite(Y)):
        raise ValueError("the data has NaN or infinite values; drop those rows")
    props = kept_properties(model) if keep_properties else []
    checks = [PropertyCheck(p.text, status(model, p, seed)[0].value) for p in props]
    held = [(p, c) for p, c in zip(props, checks) if c.before in {s.value for s in KEPT}]
    form = SugenoForm(space, X) if not sugeno_problem(model) else None
    before = _rmse(_predict(model, X), Y)
    rejected: list[str] = []
    corner = corner_bounds(space, form, [p for p, _ in held]) if held else None
    rest = [p for p, _ in held if not corner or p not in corner.props]
    penalties = Penalties(model, rest) if rest else None
    theta, candidate, start, weight, added = None, None, None, 0.0, 0
    for rounds in range(1, (COUNTEREXAMPLE_ROUNDS if penalties else 1) + 1):
        # the weight grows after the first rejection; each round starts from the last
        # candidate, its penalty sets grown by the verifier's counterexamples
        weight = PENALTY_WEIGHTS[min(rounds - 1, len(PENALTY_WEIGHTS) - 1)] if penalties \
            else 0.0
        candidate, name = _search(space, form, X, Y, passes, max_nfev, penalties, weight, start,
                                  corner, how)
        method = name if start is None else method
        found: list = []
        lost = _lost(space, candidate, held, seed, found)
        if not lost:
            theta = candidate
            break
        new = sum(penalties.add(space.apply(candidate), p, e) for p, e in found)
        added += new
        rejected.append(f"round {rounds}, penalty weight {weight:g}: " + "; ".join(lost)
                        + f"; {new} counterexample points added to the penalty")
        if not new:
            break
        start = candidate
    if corner:
        method += "; " + ", ".join(f"`{p.text}`" for p in corner.props) + " kept by " \
            f"construction: each consequent within the bounds at the input box's " \
            f"{corner.corners} corners (linear constraints on the consequent least squares)"
    if penalties:
        method += (f", penalty weight{'s' if rounds > 1 else ''} "
                   f"{', '.join(f'{w:g}' for w in sorted({*PENALTY_WEIGHTS[:rounds]}))}, "
                   f"{rounds} round{'s' if rounds > 1 else ''} of the verifier "
                   f"({added} counterexample points added)")
    if theta is None:       # back along the way to the numbers as written, which keep them
        theta, share = _keeping(space, candidate, held, seed)
        method += f", then {share:.4g} of the way from the written numbers (the most that " \
                  "keeps the properties)"
    tuned = space.apply(theta)
    for p, c in zip(props, checks):
        verdict, c.detail = status(tuned, p, seed)
        c.after = verdict.value
    result_model = copy.deepcopy(tuned)
    return FitResult(space.numbers, theta, result_model, before,
                     _rmse(_predict(result_model, X), Y), method=method, properties=checks,
                     rejected=rejected, seed=seed)


def _keeping(space: Space, candidate, held, seed, steps: int = 12):
    """x0 + t (candidate - x0) for the largest t (bisection, `steps` halvings) that the
    verifier accepts: t = 0, the written numbers, kept every property."""
    good, bad = 0.0, 1.0
    for _ in range(steps):
        t = 0.5 * (good + bad)
        if _lost(space, space.x0 + t * (candidate - space.x0), held, seed):
            bad = t
        else:
            good = t
    return space.x0 + good * (candidate - space.x0), good


def _lost(space: Space, theta, held, seed, found: list | None = None) -> list[str]:
    """Why the verifier rejects theta (empty: it keeps every held property); `found` gets
    (property, failing evidence) of each lost one."""
    if not held:
        return []
    model = space.apply(theta)
    lost = []
    for p, _ in held:
        verdict, why, evidence = check(model, p, seed)
        if verdict not in KEPT:
            lost.append(f"loses `{p.text}` ({verdict.value}{': ' + why if why else ''})")
            if found is not None:
                found.append((p, evidence))
    return lost


def _search(space: Space, form: SugenoForm | None, X, Y, passes, max_nfev, penalties,
            weight, start=None, corner: CornerBounds | None = None,
            how: str = "least_squares") -> tuple[np.ndarray, str]:
    """The least-squares search; returns the numbers and the method's name. `start`: a
    candidate to go on from (a counterexample round), without the hybrid passes. `corner`:
    linear constraints on the consequents, which the joint polish cannot take: it moves the
    premises alone, and the constrained consequent solve follows."""
    target = Y.ravel()
    scale = np.sqrt(weight)

    def data_residual(theta):
        if form is not None:
            return form.predict(theta).ravel() - target
        return engine.evaluate(space.apply(theta).rulebase, X).ravel() - target

    def penalty_residual(theta):
        return scale * penalties.residuals(space.apply(theta))

    def residual(theta):
        r = data_residual(theta)
        return np.concatenate([r, penalty_residual(theta)]) if weight else r

    def jacobian(theta):
        J = form.jacobian(theta)
        if not weight:
            return J
        return np.vstack([J, scale * penalties.jacobian(
            space, theta, lambda fun, t: _forward_differences(fun, t, space))])

    theta = space.x0.copy() if start is None else start.copy()
    analytic = form is not None and form.analytic
    if start is not None:
        method = "counterexample round"      # the caller keeps the first round's name
    elif how == "anfis" and form is not None and form.analytic and form.linear_part.any():
        theta = anfis.train(form, theta, target, space.lo, space.hi, epochs=passes).theta
        method = f"ANFIS (Jang 1993: {passes} epochs of least-squares consequents and one " \
                 "normalised gradient step on the premises)"
        if not weight and corner is None:     # Jang's rule alone; a penalty polishes after
            return theta, method
    elif form is not None and form.linear_part.any():     # the penalised search starts there too
        theta = _hybrid(form, theta, space, target, passes, max_nfev, corner)
        method = "ANFIS hybrid (bounded linear least squares + trust-region least squares)"
    else:
        method = "trust-region least squares" + (" (analytic Jacobian)" if analytic else
                                                  " (finite differences)")
    theta = np.clip(theta, space.lo, space.hi)     # bvls may end a rounding outside
    if corner is not None:
        return _premises_then_consequents(form, theta, space, target, residual, jacobian,
                                          max_nfev, corner), method
    result = least_squares(residual, theta, jac=jacobian if analytic else "2-point",
                           bounds=(space.lo, space.hi), x_scale="jac", max_nfev=max_nfev,
                           method="trf")
    return np.clip(result.x, space.lo, space.hi), method


def _premises_then_consequents(form, theta, space, target, residual, jacobian, max_nfev,
                               corner, rounds: int = 12) -> np.ndarray:
    """The polish under corner constraints: the premises by least squares (the consequents
    held), then the consequents by the constrained solve; again while the error drops, at
    most `rounds` times (Mackey-Glass, bounded, the former series with method least_squares:
    NDEI check 0.027 after 3, 0.021 after 12, 0.019 after 40 at four times the CPU)."""
    lin, premises = form.linear_part, ~form.linear_part
    cost = np.inf
    for _ in range(rounds):
        if premises.any():
            def part(p, fun):
                full = theta.copy()
                full[premises] = p
                return fun(full)
            step = least_squares(lambda p: part(p, residual), theta[premises],
                                 jac=(lambda p: part(p, jacobian)[:, premises])
                                 if form.analytic else "2-point",
                                 bounds=(space.lo[premises], space.hi[premises]),
                                 x_scale="jac", max_nfev=max_nfev, method="trf")
            theta[premises] = np.clip(step.x, space.lo[premises], space.hi[premises])
        A, b = form.design(theta)
        theta[lin] = corner.solve(A, target - b, space.lo[lin], space.hi[lin], theta[lin])
        new = float(np.sum(residual(theta) ** 2))
        if not new < cost * (1 - 1e-6):
            break
        cost = new
    return theta


def _hybrid(form: SugenoForm, theta, space: Space, target, passes, max_nfev,
            corner: CornerBounds | None = None) -> np.ndarray:
    lin = form.linear_part
    premises = ~lin
    cost = np.inf
    for _ in range(passes):
        A, b = form.design(theta)
        if corner is not None:
            theta[lin] = corner.solve(A, target - b, space.lo[lin], space.hi[lin], theta[lin])
        else:
            theta[lin] = lsq_linear(A, target - b, bounds=(space.lo[lin], space.hi[lin]),
                                    method="bvls").x
        if premises.any() and form.analytic:
            def residual(p):
                full = theta.copy()
                full[premises] = p
                return form.predict(full).ravel() - target

            def jacobian(p):
                full = theta.copy()
                full[premises] = p
                return form.jacobian(full)[:, premises]
            step = least_squares(residual, theta[premises], jac=jacobian,
                                 bounds=(space.lo[premises], space.hi[premises]),
                                 x_scale="jac", max_nfev=max_nfev or 5, method="trf")
            theta[premises] = np.clip(step.x, space.lo[premises], space.hi[premises])
        new = float(np.mean((form.predict(theta).ravel() - target) ** 2))
        if not new < cost * (1 - 1e-9):
            break
        cost = new
    return theta


def _forward_differences(fun, theta, space: Space) -> np.ndarray:
    base = fun(theta)
    J = np.zeros((len(base), len(theta)))
    for k in range(len(theta)):
        h = 1e-7 * max(1.0, abs(theta[k]))
        if theta[k] + h > space.hi[k]:
            h = -h
        moved = theta.copy()
        moved[k] += h
        J[:, k] = (fun(moved) - base) / h
    return J


def _cross_validate(model, X, Y, folds, seed, passes, max_nfev,
                    how: str = "least_squares") -> float:
    if not 2 <= folds <= len(X):
        raise ValueError(f"--folds needs 2 <= K <= {len(X)} (the rows), got {folds}")
    order = np.random.default_rng(seed).permutation(len(X))
    errors = []
    for part in np.array_split(order, folds):
        train = np.setdiff1d(order, part)
        fold = _fit(model, X[train], Y[train], seed, passes, max_nfev, False, how)
        errors.append(_rmse(_predict(fold.model, X[part]), Y[part]))
    return float(np.mean(errors))


def _predict(model: Model, X) -> np.ndarray:
    return engine.evaluate(model.rulebase, X)


def _rmse(a, b) -> float:
    return float(np.sqrt(np.mean((np.asarray(a) - np.asarray(b)) ** 2)))


def _columns(model: Model, data, inputs: bool) -> np.ndarray:
    """(N, I) inputs or (N, O) outputs from an array or a mapping of names to columns."""
    rb = model.rulebase
    names = [v.name for v in (rb.inputs if inputs else rb.outputs)]
    if hasattr(data, "keys"):
        missing = [n for n in names if n not in data]
        if missing:
            raise KeyError(f"no column for {', '.join(missing)}")
        data = np.column_stack([np.asarray(data[n], dtype=float) for n in names])
    array = np.asarray(data, dtype=float)
    if array.ndim == 1:
        array = array[:, None]
    if array.shape[1] != len(names):
        raise ValueError(f"expected {len(names)} columns ({', '.join(names)}), got "
                         f"{array.shape[1]}")
    return array
