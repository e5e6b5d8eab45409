"""The corner controller's lost numbers identified against Table 4's 50 mm rows (issue 31).

The corner paper's Fig. 12 (the five output singletons of the 27-rule controller) and the
constant of its eq. 5 (the user's `like`) are lost. Its Table 4 gives the corner errors measured
with the controller; the 50 mm rows (examples/tuning/table4_50mm.csv, 20 controlled cells) are
the data, the 21 mm rows are held out (not in the repository). The rule table stays as printed
(rulebases/wedm_corner.fz, its `tune` section frees the singletons and like only) and so do its
verify properties (fuzzyc.tune.loop keeps them, the closed-loop one re-verified by search).

The cost: the sum over the 20 cells of log(model / measured)^2, the model being the corner
plant's closed loop (plants/wedm_corner.py, scenario corner_path). In that loop a corner's
controlled error is its normal error times keep = 1 - reduction / 100, the reduction the
controller commands at the row's steady feed and thickness and the corner's angle (kerf-wide
corner blocks: plants/corner_validation.py), and the normal errors do not depend on the
controller. So each cost evaluation reads the controller at the 20 cells (one batched step)
times the loop's normal errors, run once; the closed loop is run again with the result, and
the program prints the largest difference between that shortcut and the loop (0 up to
rounding, or the shortcut would be wrong and the fit with it). A closed-loop run takes about
20 s (12,600 periods for the 40 mm^2/min row): the shortcut makes the search take seconds.

    python -m fuzzyc.tune.corner_identify [--against CSV] [--seed S]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

HELD_OUT_ROWS = slice(4, 8)      # TABLE4_CONDITIONS: 21 mm at 175, 125, 75, 40 mm^2/min


def data_file() -> Path:
    """examples/tuning/table4_50mm.csv, in the source tree or as installed (examples/ sits
    beside rulebases/ in both)."""
    import fuzzyc.rulebases
    return (Path(fuzzyc.rulebases.__file__).resolve().parent.parent / "examples" / "tuning"
            / "table4_50mm.csv")


def log_errors(model_errors: np.ndarray, measured: np.ndarray) -> np.ndarray:
    return np.log(np.asarray(model_errors, float) / np.asarray(measured, float))


def identify(data: str | Path | None = None, seed: int = 0, max_examples: int = 10):
    """(fit, measured, before, after): the LoopFit, the measured table, and the closed loop's
    predictions (plants.corner_table.predict) before tuning at the measured rows and after it
    at the measured rows followed by the held-out ones."""
    import fuzzyc
    from fuzzyc.plants import corner_validation as validation
    from fuzzyc.plants import scenario as scenarios
    from fuzzyc.plants.corner_table import predict
    from fuzzyc.plants.wedm_corner import TABLE4_CONDITIONS
    from .loop import tune_loop
    from .space import Space
    scenario = scenarios.load("corner_path")
    model = fuzzyc.load(scenario.rulebase_path())
    measured = validation.read_measured(data or data_file())
    before = predict(measured.conditions, model=model)
    space = Space(model)

    def cost(theta) -> float:
        reduction = validation.commanded_reduction(measured.conditions,
                                                   model=space.apply(theta))
        controlled = (1.0 - reduction / 100.0) * before["normal"]
        return float(np.sum(log_errors(controlled, measured.controlled) ** 2))

    fit = tune_loop(model, scenario, "final(error_sum)", seed=seed, cost=cost,
                    max_examples=max_examples)
    rows = np.vstack([measured.conditions, TABLE4_CONDITIONS[HELD_OUT_ROWS]])
    after = predict(rows, model=fit.model)
    return fit, measured, before, after


def order_only(measured, normal: np.ndarray):
    """A diagnosis, not a tune: the least-squares singletons when only their order is kept
    (each anywhere in [5, 60], `bounded y`, like in its box), not the boxes, which must hold the
    written numbers. (theta, cost, model / measured per cell), by the same search and cost.
    `normal`: the loop's normal errors at the measured rows."""
    import fuzzyc
    from fuzzyc.plants import corner_validation as validation
    from fuzzyc.plants import scenario as scenarios
    from .loop import LIMIT_WEIGHT, minimize_within
    from .space import Space
    space = Space(fuzzyc.load(scenarios.load("corner_path").rulebase_path()))
    singletons = space.indices("term")
    lo, hi = space.lo.copy(), space.hi.copy()
    lo[singletons], hi[singletons] = 5.0, 60.0

    def ratio(theta) -> np.ndarray:
        reduction = validation.commanded_reduction(measured.conditions,
                                                   model=space.apply(theta))
        return (1.0 - reduction / 100.0) * normal / measured.controlled

    def cost(theta) -> float:
        disorder = np.maximum(0.0, -np.diff(theta[singletons])).sum()
        return float(np.sum(np.log(ratio(theta)) ** 2) + LIMIT_WEIGHT * disorder)
    theta = minimize_within(cost, space.x0, lo, hi)
    return space, theta, cost(theta), ratio(theta)


def report(fit, measured, before, after) -> str:
    from fuzzyc.plants import corner_validation as validation
    from fuzzyc.plants.corner_table import markdown
    from fuzzyc.plants.wedm_corner import TABLE2_ANGLES
    n = len(measured.conditions)
    fitted = {k: v[:n] for k, v in after.items()}
    loop_cost = [float(np.sum(log_errors(p["controlled"], measured.controlled) ** 2))
                 for p in (before, fitted)]
    shortcut = (1.0 - validation.commanded_reduction(measured.conditions, model=fit.model)
                / 100.0) * before["normal"]
    gap = float(np.max(np.abs(shortcut / fitted["controlled"] - 1.0)))
    within = [validation.within(p["controlled"], measured.controlled) for p in (before, fitted)]
    reduction = validation.commanded_reduction(measured.conditions, model=fit.model)
    floor = validation.force_linear_floor(measured.conditions, reduction)
    ratio = measured.controlled / measured.normal
    lines = ["Fit to Table 4, 50 mm (controlled corner error, um): measured, model, "
             "model / measured; `*` outside +-25 %, `!` measured ratio controlled / normal "
             "under the force-linear floor at the tuned commands", "",
             "| feed mm²/min | " + " | ".join(f"{int(a)}°" for a in TABLE2_ANGLES) + " |",
             "|---" * (1 + len(TABLE2_ANGLES)) + "|"]
    for i, (_, feed) in enumerate(measured.conditions):
        cells = []
        for j in range(len(TABLE2_ANGLES)):
            m, p = measured.controlled[i, j], fitted["controlled"][i, j]
            mark = ("" if within[1][i, j] else " *") + (" !" if ratio[i, j] < floor[i, j]
                                                        else "")
            cells.append(f"{m:.1f} / {p:.1f} / {p / m:.2f}{mark}")
        lines.append(f"| {feed:g} | " + " | ".join(cells) + " |")
    lines += ["", "Identified (bounds from the tune section of rulebases/wedm_corner.fz):", ""]
    lines += [f"- {num.target} = {value:.4g} (was {num.value:g}, bounds [{num.lo:g}, "
              f"{num.hi:g}])" for num, value in zip(fit.numbers, fit.values)]
    lines += ["",
              f"sum of log(model / measured)^2 over the 20 cells, closed loop: "
              f"{loop_cost[0]:.4f} before, {loop_cost[1]:.4f} after",
              f"cells within +-25 %: {int(within[0].sum())} of {within[0].size} before, "
              f"{int(within[1].sum())} after",
              f"the search's shortcut against the closed loop at the result: largest "
              f"relative difference {gap:.2g}",
              f"search: {fit.method}"]
    lines += [f"property `{c.text}`: {c.before} before, {c.after} after"
              for c in fit.properties]
    lines += [f"rejected: {why}" for why in fit.rejected]
    space, theta, cost, ratio_free = order_only(measured, before["normal"])
    misses = [f"{int(a)}° at {f:g} mm²/min ({r:.2f})" for (_, f), row in
              zip(measured.conditions, ratio_free) for a, r in zip(TABLE2_ANGLES, row)
              if abs(r - 1.0) > validation.TOLERANCE]
    lines += ["", "Diagnosis (not a tune): the singletons when only their order is kept, each "
              "anywhere in [5, 60] (the tune section's boxes must hold the written numbers): "
              + ", ".join(f"{num.target} = {value:.4g}"
                          for num, value in zip(space.numbers, theta)),
              f"sum of log(model / measured)^2 {cost:.4f} (the loop's shortcut); cells within "
              f"+-25 %: {ratio_free.size - len(misses)} of {ratio_free.size}; missing: "
              + ("; ".join(misses) or "none")]
    held = {k: v[n:] for k, v in after.items()}
    from fuzzyc.plants.wedm_corner import TABLE4_CONDITIONS
    lines += ["", "Predictions for the held-out 21 mm rows of Table 4 (um, normal / controlled "
              "(ratio); machining time s):", "",
              markdown(TABLE4_CONDITIONS[HELD_OUT_ROWS], held)]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzzyc.tune.corner_identify",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--against", default=None, metavar="CSV",
                        help="the measured rows (plants/corner_validation.py's format; "
                             "default: examples/tuning/table4_50mm.csv)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-examples", type=int, default=10,
                        help="loops of the closed-loop property's check (default 10)")
    args = parser.parse_args(argv)
    sys.stdout.write(report(*identify(args.against, args.seed, args.max_examples)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
