"""`fuzzyc tune FILE --scenario NAME --minimize METRIC`: the closed-loop tune of a .fz file,
its tuned text and provenance (fuzzyc.tune.loop does the tuning)."""
from __future__ import annotations

import hashlib
from pathlib import Path

from ..display import plural
from ..semantics.model import Model
from .loop import LoopFit, parse_limit, tune_loop


def tune_scenario(model: Model, scenario: str, minimize: str, *, sets: dict | None = None,
                  limits=(), seed: int = 0, batch: int = 1, randomize: bool = False,
                  method: str = "powell", max_evaluations: int | None = None,
                  max_examples: int = 30, prove: bool = False, prove_boxes: int = 64,
                  scenarios: dict | None = None, cluster=None):
    """The TuneResult of tuning `model` (read from .fz) to minimize the metric `minimize` of
    scenario `scenario` (a name or a YAML path) with the overrides `sets` (KEY -> value, as
    `simulate --set`). limits: 'METRIC<=VALUE' texts kept as constraints. prove: the
    closed-loop properties proved first (one proved before must be proved after).
    scenarios: the user's own loops by name, as fuzzyc.verify takes them (`scenario` may name
    one). cluster (runtime.campaign.Cluster): where each cost's loops run, held open for the
    whole search (one Dask client and its workers serve every evaluation); the numbers are
    the same as in this process."""
    import contextlib
    from ..verifier.closed_loop import load_scenario
    from . import TuneResult, _check_reads_back
    from .loop import LoopChecks
    from .rewrite import rewrite
    loaded = load_scenario(scenario, {k: str(v) for k, v in (sets or {}).items()},
                           LoopChecks(scenarios=scenarios))
    parsed = tuple(parse_limit(text) for text in limits)
    with cluster if cluster is not None else contextlib.nullcontext():
        fit = tune_loop(model, loaded, minimize, seed=seed, batch=batch, randomize=randomize,
                        method=method, max_evaluations=max_evaluations, limits=parsed,
                        max_examples=max_examples, prove=prove, prove_boxes=prove_boxes,
                        scenarios=scenarios, cluster=cluster)
    lines = provenance(model, loaded, minimize, sets or {}, fit, batch, randomize,
                       max_evaluations, max_examples, prove_boxes if prove else None)
    text = rewrite(model.source_text or "", fit.numbers, fit.values, lines)
    _check_reads_back(text, fit)
    return TuneResult(fit, text, lines)


def provenance(model: Model, scenario, minimize: str, sets: dict, fit: LoopFit, batch: int,
               randomize: bool, max_evaluations, max_examples: int,
               prove_boxes: int | None = None) -> list[str]:
    """No time, path or machine: the same inputs give the same lines."""
    name = Path(model.source_path or "model.fz").name
    source = hashlib.sha256((model.source_text or "").encode()).hexdigest()
    if scenario.text:
        origin = f"sha256 {hashlib.sha256(scenario.text.encode()).hexdigest()}"
    else:                 # a mapping given from Python: no file to hash
        origin = f"given from Python, plant {scenario.plant_name}"
    settings = ", ".join(f"{k}={v}" for k, v in sorted(sets.items())) or "none"
    lines = [f"tuned from {name} (sha256 {source})",
             f"closed loop: scenario {scenario.name} ({origin}), --set {settings}, "
             f"batch {batch}{', randomized plants' if randomize else ''}",
             f"seed {fit.seed}, max evaluations {max_evaluations}, closed-loop checks "
             f"{max_examples} loops"
             + (f" and proofs in {prove_boxes} boxes" if prove_boxes is not None else "")
             + f"; method: {fit.method}",
             f"{plural(len(fit.numbers), 'number')} tuned; {minimize} before {fit.cost_before:.6g}, "
             f"after {fit.cost_after:.6g}"]
    lines += [f"property `{c.text}`: {c.before} before, {c.after} after" for c in fit.properties]
    lines += [f"rejected: {why}" for why in fit.rejected]
    return lines
