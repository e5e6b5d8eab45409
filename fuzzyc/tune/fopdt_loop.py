"""The FOPDT loop tuned (issue 31): the fuzzy PI's gains (rulebases/fopdt_pi.fz, its `tune`
section: GE, GCE, GU) for the integrated absolute error of the set-point step, its overshoot at
most OVERSHOOT and its closed-loop `settles` property kept; beside it the PI baseline's gains
(Kp, Ki: the scenario's baseline.params) tuned by the same optimizer for the same cost.

    python -m fuzzyc.tune.fopdt_loop [--seed S] [--max-evaluations N]

prints both before and after: IAE, overshoot, settling time (5 %) on the nominal plant, and the
fuzzy PI's properties before and after."""
from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

import numpy as np

SCENARIO = "fopdt_step"
METRIC = "iae(y)"
OVERSHOOT = 0.02
PI_BOUNDS = {"Kp": (0.25, 10.0), "Ki": (0.05, 2.0)}    # around SIMC's 2.5, 0.5


@dataclass
class Row:
    name: str
    iae: float
    overshoot: float
    settling: float


def _scenario(sets: dict | None = None):
    from fuzzyc.plants import scenario as scenarios
    return scenarios.load(SCENARIO, sets)


def _figures(name: str, trace, scenario) -> Row:
    from .loop import metric_function
    iae, over, settle = (float(metric_function(scenario, m)(trace)[0])
                         for m in (METRIC, "overshoot(y)", "settling time (5 %)"))
    return Row(name, iae, over, settle)


def tune_fuzzy(seed: int = 0, max_evaluations: int | None = 80, max_examples: int = 30):
    """The LoopFit of the fuzzy PI and its rows before / after."""
    import fuzzyc
    from .loop import ClosedLoop, tune_loop
    from .space import Space
    scenario = _scenario()
    model = fuzzyc.load(scenario.rulebase_path())
    fit = tune_loop(model, scenario, METRIC, seed=seed, max_evaluations=max_evaluations,
                    limits=(("overshoot(y)", OVERSHOOT),), max_examples=max_examples)
    loop = ClosedLoop(scenario, Space(model), METRIC, seed=seed)
    rows = [_figures(f"fuzzy PI, {label}", loop.trace(x), scenario)
            for label, x in (("as written", loop.space.x0), ("tuned", fit.values))]
    return fit, rows


def baseline_cost(seed: int = 0):
    """theta = (Kp, Ki) -> the same cost as the fuzzy PI's: IAE plus the penalty on an
    overshoot over OVERSHOOT (fuzzyc.tune.loop.LIMIT_WEIGHT per unit)."""
    from fuzzyc.runtime.simulate import simulate
    from .loop import LIMIT_WEIGHT, REJECT_COST, metric_function

    def run(theta):
        scenario = _scenario({f"baseline.params.{k}": repr(float(v))
                              for k, v in zip(PI_BOUNDS, theta)})
        return scenario, simulate(scenario, baseline=True, seed=seed)

    def cost(theta) -> float:
        scenario, trace = run(theta)
        iae = float(metric_function(scenario, METRIC)(trace)[0])
        over = float(metric_function(scenario, "overshoot(y)")(trace)[0])
        total = iae + LIMIT_WEIGHT * max(0.0, over - OVERSHOOT)
        return total if np.isfinite(total) else REJECT_COST
    return cost, run


def tune_baseline(seed: int = 0, max_evaluations: int | None = 80):
    """(Kp, Ki) as written and tuned, and the rows before / after."""
    from .loop import minimize_within
    cost, run = baseline_cost(seed)
    written = _scenario().baseline["params"]
    x0 = np.array([float(written[k]) for k in PI_BOUNDS])
    lo, hi = (np.array([b[i] for b in PI_BOUNDS.values()]) for i in (0, 1))
    best = minimize_within(cost, x0, lo, hi, "powell", max_evaluations)
    rows = [_figures(f"PI baseline, {label}", run(x)[1], run(x)[0])
            for label, x in (("SIMC", x0), ("tuned", best))]
    return x0, best, rows


def table(rows: list[Row]) -> str:
    lines = [f"| loop on {SCENARIO} (nominal plant) | IAE | overshoot | settling time 5 % s |",
             "|---|---|---|---|"]
    lines += [f"| {r.name} | {r.iae:.4f} | {r.overshoot:.4f} | {r.settling:.1f} |"
              for r in rows]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzzyc.tune.fopdt_loop",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-evaluations", type=int, default=80,
                        help="closed-loop runs of each search (default 80)")
    args = parser.parse_args(argv)
    fit, fuzzy_rows = tune_fuzzy(args.seed, args.max_evaluations)
    x0, best, pi_rows = tune_baseline(args.seed, args.max_evaluations)
    out = [f"cost: {METRIC} with overshoot(y) <= {OVERSHOOT:g} (seed {args.seed})", "",
           table(fuzzy_rows + pi_rows),
           "fuzzy PI: " + ", ".join(f"{n.target} {n.value:.6g} -> {v:.6g}"
                                    for n, v in zip(fit.numbers, fit.values)),
           "PI baseline: " + ", ".join(f"{k} {a:.6g} -> {b:.6g}"
                                       for k, a, b in zip(PI_BOUNDS, x0, best)),
           f"fuzzy PI search: {fit.method}"]
    out += [f"property `{c.text}`: {c.before} before, {c.after} after" for c in fit.properties]
    out += [f"rejected: {why}" for why in fit.rejected]
    sys.stdout.write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
