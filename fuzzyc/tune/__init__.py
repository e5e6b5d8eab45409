"""`fuzzyc tune`: fit the numbers a rule file's `tune` section frees to data, keep the file's
monotone / covers / bounded properties, and write the tuned .fz with its provenance.

    from fuzzyc.tune import fit_data, tune
    fit = fit_data(model, x, y, seed=0)                 # numbers only
    result = tune("rule.fz", "train.csv", validate="check.csv", seed=0)
    result.text                                         # the tuned file
"""
from __future__ import annotations

import hashlib
import os
import sys
import types
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..display import plural
from ..semantics.model import Model

if TYPE_CHECKING:
    from .data import Table
    from .fit import FitResult

__all__ = ["FitResult", "TuneResult", "fit_data", "tune"]


def fit_data(model: Model, x, y, **options: Any) -> FitResult:
    """fuzzyc.tune.fit.fit_data (scipy loads on first use, not with `import fuzzyc`)."""
    from .fit import fit_data as fit
    return fit(model, x, y, **options)


def __getattr__(name: str) -> Any:
    if name == "FitResult":
        from .fit import FitResult
        return FitResult
    raise AttributeError(f"module 'fuzzyc.tune' has no attribute '{name}'")


@dataclass
class TuneResult:
    fit: Any                   # a FitResult (data) or a fuzzyc.tune.loop.LoopFit (closed loop)
    text: str                  # the tuned .fz: the source with the tuned numbers replaced
    provenance: list[str]


def tune(model: Model | str | os.PathLike, data: str | os.PathLike | None = None, *,
         validate: str | os.PathLike | None = None, folds: int | None = None, seed: int = 0,
         passes: int = 20, max_nfev: int | None = None, scenario: str | None = None,
         minimize: str | None = None, sets: dict | None = None, limits: tuple = (),
         batch: int = 1, randomize: bool = False, method: str | None = None,
         max_evaluations: int | None = None, max_examples: int = 30, prove: bool = False,
         prove_boxes: int = 64, scenarios: dict | None = None, cluster=None) -> TuneResult:
    """Tune a .fz file (or a model parsed from .fz text) against the CSV `data`; `validate`
    (a CSV) or `folds` (K-fold cross-validation) measure the error on data it was not fitted
    to.  Or, with `scenario` instead of data, against a closed loop: minimize the metric
    `minimize` of the scenario's loop (overrides `sets`, as simulate's --set; `limits`
    'METRIC<=VALUE' kept; fuzzyc.tune.loop).  `method`: with data, "least_squares" (the
    default) or "anfis" (Jang's rule, `passes` epochs); with a scenario, "powell" (the
    default) or "nelder-mead"; `prove`: the closed-loop properties get the reachable-set
    proof first (`prove_boxes` boxes), and one proved before must be proved after;
    `scenarios`: your own loops by name, as fuzzyc.verify takes them; `cluster` (a
    fuzzyc.runtime.campaign.Cluster): each cost's loops run in chunks on Dask, the same
    numbers as in this process.  The result's text differs from the source only
    in the tuned numbers and the provenance comment block on top; the same files and seed give
    the same text, byte for byte."""
    if not isinstance(model, Model):
        from ..language.parser import load
        model = load(model)
    if not model.source_text or not str(model.source_path or "").endswith((".fz", "<string>")):
        raise ValueError("tune rewrites a .fz file: convert the model to .fz first "
                         "(fuzzyc convert), add a `tune` section, and tune that")
    if (data is None) == (scenario is None):
        raise ValueError("tune against data (a CSV) or a closed loop (--scenario), one of them")
    data_methods, loop_methods = ("least_squares", "anfis"), ("powell", "nelder-mead")
    allowed = loop_methods if scenario is not None else data_methods
    if method is not None and method not in allowed:
        raise ValueError(f"method {method} goes with {'data' if scenario else '--scenario'}; "
                         f"use {' or '.join(allowed)} here")
    if cluster is not None and scenario is None:
        raise ValueError("a cluster runs a closed loop's batch, so it goes with a scenario: "
                         "drop it for a fit to data")
    if scenario is not None:
        if not minimize:
            raise ValueError("a closed-loop tune needs the metric to minimize (--minimize)")
        from .scenario_tune import tune_scenario
        return tune_scenario(model, scenario, minimize, sets=sets, limits=limits, seed=seed,
                             batch=batch, randomize=randomize, method=method or "powell",
                             max_evaluations=max_evaluations, max_examples=max_examples,
                             prove=prove, prove_boxes=prove_boxes, scenarios=scenarios,
                             cluster=cluster)
    from .data import read_csv
    from .rewrite import rewrite
    train = read_csv(data, model)
    check: Table | None = read_csv(validate, model) if validate is not None else None
    fit = fit_data(model, train.x, train.y, seed=seed, passes=passes, max_nfev=max_nfev,
                   validate=(check.x, check.y) if check else None, folds=folds,
                   method=method or "least_squares")
    lines = provenance(model, fit, train, check, folds, passes, max_nfev)
    text = rewrite(model.source_text, fit.numbers, fit.values, lines)
    _check_reads_back(text, fit)
    return TuneResult(fit, text, lines)


def _check_reads_back(text: str, fit: Any) -> None:
    """The tuned text parses to exactly the tuned numbers and bounds (a bug otherwise)."""
    from ..language.parser import parse
    again = parse(text, "<tuned>").tunables
    said = [(n.target, n.value, n.lo, n.hi) for n in again]
    meant = [(n.target, float(v), n.lo, n.hi) for n, v in zip(fit.numbers, fit.values)]
    if said != meant:
        raise AssertionError(f"the tuned text reads back otherwise: {said} != {meant}")


def provenance(model: Model, fit: FitResult, train: Table, check: Table | None,
               folds: int | None, passes: int, max_nfev: int | None) -> list[str]:
    """What the tuned file came from and how well it fits: no time, no path, no machine (the
    same inputs give the same lines)."""
    name = Path(model.source_path or "model.fz").name
    source = hashlib.sha256((model.source_text or "").encode()).hexdigest()
    lines = [f"tuned from {name} (sha256 {source})",
             f"data {train.name} sha256 {train.sha256}, {len(train.x)} rows",
             f"seed {fit.seed}, passes {passes}, max_nfev {max_nfev}; method: {fit.method}",
             f"{plural(len(fit.numbers), 'number')} tuned; RMSE on the data before {fit.rmse_before:.6g}, "
             f"after {fit.rmse_after:.6g}"]
    if check is not None:
        lines.append(f"validation {check.name} sha256 {check.sha256}, {len(check.x)} rows: "
                     f"RMSE before {fit.validation_before:.6g}, after {fit.validation:.6g}")
    elif folds:
        lines.append(f"{folds}-fold cross-validation RMSE {fit.validation:.6g}")
    for c in fit.properties:
        lines.append(f"property `{c.text}`: {c.before} before, {c.after} after")
    lines += [f"rejected: {why}" for why in fit.rejected]
    return lines


class _CallableModule(types.ModuleType):
    """`fuzzyc.tune(...)` is the API's tune whether `fuzzyc.tune` names this package (once it
    is imported, Python sets the attribute) or the function fuzzyc exports."""

    def __call__(self, *args: Any, **options: Any) -> TuneResult:
        return tune(*args, **options)


sys.modules[__name__].__class__ = _CallableModule
