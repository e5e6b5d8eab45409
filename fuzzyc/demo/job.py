"""`make demo`: the main job on the shipped rule bases, end to end.

Checks every rule base, evaluates sample points with the rules that fired, draws the
membership functions and control surfaces, compiles the C headers, runs every paper scenario
against its baseline, and prints the verification summary. Pictures and reports go to out/.
"""
from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np

from ..atomic import write_text
from ..cli import main as fuzzyc
from ..cli.check import summary
from ..cli.eval import evaluate_batch
from ..language.parser import load
from ..plotting import plot_model
from ..verifier import Options, Status, verify_model
from ..verifier.report import format_result
from . import simulate as demo_simulate

OUT = Path("out")

# One sample point per rule base (raw controller inputs), to show one evaluation; every
# shipped rule base has one (tests/test_demo_names.py).
SAMPLES = {
    "wedm_three_region": {"spark_freq": 26.0, "abnormal_ratio": 0.325},
    "wedm_corner": {"feed": 92.5, "thickness": 50.0, "angle": 82.5},
    "milling_neurofuzzy": {"force": 350.0},
    "milling_neurofuzzy_learned": {"force": 350.0},
    "edm_sink_gap": {"gap_voltage": 62.0},
    "fopdt_pi": {"y": 0.5},
}


def shipped_rulebases() -> list[Path]:
    folder = resources.files("fuzzyc.rulebases")
    return sorted(Path(str(p)) for p in folder.iterdir() if p.name.endswith(".fz"))


def verify_lines(model) -> list[str]:
    """Each property's verdict line, as `fuzzyc verify FILE` prints it with its defaults (100
    examples, seed 0: fewer examples miss the rare closed-loop finding the README reports), and
    under a violation the finding that records it."""
    lines = []
    for result in verify_model(model, Options()):
        lines.append(format_result(result).splitlines()[0])
        if result.status == Status.VIOLATED and result.finding:
            lines.append(f"          {result.finding[:150]}...")
    return lines


def section(title: str) -> None:
    print(f"\n== {title} " + "=" * max(0, 70 - len(title)))


def main() -> int:
    models = [load(p) for p in shipped_rulebases()]
    section("check: the shipped rule bases")
    for model in models:
        print(summary(model))

    section("eval: one step of each controller from its initial state")
    for line in eval_lines(models):
        print(line)

    section("plot: membership functions and control surfaces")
    for model in models:
        paths = plot_model(model, OUT / "plots")
        print(f"{model.name}: {len(paths)} pictures in {OUT / 'plots'}")

    section("compile: C99 headers (float), size and stack")
    for model in models:
        fuzzyc(["compile", model.source_path, "--target", "c", "-o", str(OUT / "c")])

    section("simulate: every paper scenario, rule base against baseline")
    demo_simulate.main()

    section("verify: the properties in each rule file")
    for model in models:
        lines = verify_lines(model)
        print("\n".join(lines))
        write_text(OUT / "verify" / f"{model.name}.txt", "\n".join(lines) + "\n")
    print(f"\nverify reports in {OUT / 'verify'}; traces, pictures and headers in "
          f"{OUT.resolve()}")
    return 0


def eval_lines(models) -> list[str]:
    """One evaluation per rule base, at its sample point, named by the model."""
    lines = []
    for model in models:
        point = SAMPLES[model.name]
        outputs = evaluate_batch(model, {k: np.array([v]) for k, v in point.items()}, core=False)
        ins = ", ".join(f"{k}={v:g}" for k, v in point.items())
        outs = ", ".join(f"{k}={v[0]:.6g}" for k, v in outputs.items())
        lines.append(f"{model.name}: {ins} -> {outs}")
    return lines
