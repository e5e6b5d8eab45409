"""The corner plant's predictions for the rows of the paper's Table 4, as a Markdown table.

`python -m fuzzyc.plants.corner_table` runs the `corner_path` scenario (27-rule controller,
plants/wedm_corner.py) once, as one batch of the eight rows of Table 4 (50 mm at 160, 120, 80,
40 mm^2/min; 21 mm at 175, 125, 75, 40 mm^2/min), and prints per angle the corner error of
normal machining and of the controlled cut (um, the mean of the path's corners at that angle)
and the machining time of both. Table 4's own numbers are held out of the project: hold these
against them: `--against FILE` does it (plants/corner_validation.py: the file's format, the
score and the exit status).
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from . import scenario as scenarios
from .wedm_corner import ANGLE_OUTPUTS, NORMAL_OUTPUTS, TABLE2_ANGLES, TABLE4_CONDITIONS


def predict(conditions: np.ndarray = TABLE4_CONDITIONS, like: float = 1.0, model=None
            ) -> dict[str, np.ndarray]:
    """Run the closed loop for rows (thickness mm, feed mm^2/min): normal and controlled error
    per Table 2 angle, (N, 5) um, and machining times, (N,) s. model: another corner
    controller than the scenario's file (a tuned one), run with its own `like`."""
    from fuzzyc.runtime.simulate import simulate
    corner = scenarios.load("corner_path")
    corner.data["plant"]["params"].update(thickness=conditions[:, 0], feed=conditions[:, 1])
    corner.data["controller"]["params"]["like"] = like
    if model is None:
        trace = simulate(corner, batch=len(conditions))
    else:
        trace = _run_model(corner, model, len(conditions))
    done = trace["done"] > 0.5
    if not done[-1].all():
        raise RuntimeError("a row did not finish the path within the scenario's duration")
    return {"normal": np.stack([trace[n][-1] for n in NORMAL_OUTPUTS], axis=1),
            "controlled": np.stack([trace[n][-1] for n in ANGLE_OUTPUTS], axis=1),
            "normal_time": trace["normal_time"][-1],
            "time": trace.time[np.argmax(done, axis=0)]}


def _run_model(corner, model, batch: int):
    """The scenario's loop around `model` (its params as they are: the scenario's `like` is
    not applied)."""
    from fuzzyc.engine.chain import Controller
    from fuzzyc.runtime.loop import run
    from fuzzyc.runtime.simulate import build
    blocks = build(corner, Controller(model, batch), batch)
    return run(blocks, corner.period, corner.duration, batch, initial=corner.data.get("initial"))


def markdown(conditions: np.ndarray, result: dict[str, np.ndarray]) -> str:
    head = " | ".join(f"{int(a)}° normal / controlled" for a in TABLE2_ANGLES)
    lines = [f"| h mm | feed mm²/min | {head} | time normal / controlled s |",
             "|---" * (3 + len(TABLE2_ANGLES)) + "|"]
    for (h, f), normal, ctl, t0, t in zip(conditions, result["normal"], result["controlled"],
                                          result["normal_time"], result["time"]):
        cells = " | ".join(f"{n:.1f} / {c:.1f} ({c / n:.2f})" for n, c in zip(normal, ctl))
        lines.append(f"| {h:g} | {f:g} | {cells} | {t0:.0f} / {t:.0f} ({t / t0 - 1:+.1%}) |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzzyc.plants.corner_table",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--against", metavar="FILE",
                        help="measured errors (CSV, plants/corner_validation.py): score the "
                             "model at their rows; exit 0 when the validation target is met")
    args = parser.parse_args(argv)
    if args.against is None:
        sys.stdout.write(markdown(TABLE4_CONDITIONS, predict()))
        return 0
    from fuzzyc.errors import FuzzycError

    from . import corner_validation as validation
    try:
        measured = validation.read_measured(args.against)
    except FuzzycError as exc:
        sys.stderr.write(f"{exc}\n")
        return 2
    predicted = predict(measured.conditions)
    result = validation.score(measured, predicted,
                              validation.commanded_reduction(measured.conditions))
    sys.stdout.write(validation.report(measured, predicted, result))
    return 0 if result.met else 1


if __name__ == "__main__":
    sys.exit(main())
