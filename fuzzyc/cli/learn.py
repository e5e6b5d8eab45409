"""`fuzzyc learn FILE --scenario NAME -o OUT`: neuro-fuzzy learning of a rule base's weights.

Runs the scenario's cutting cycle `--cycles` times with on-line learning (`fuzzyc.learning`),
writes the rule file with the learned table (atomically; everything else in the file is kept)
and a plot of the performance index per cycle.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ..atomic import save_figure, write_text
from ..escape import plot_text
from .common import RULE_FILE_HELP, check_output, finite, whole_number
from ..errors import Diagnostic, FuzzycError


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("learn", help="learn the weights of a neuro-fuzzy rule base "
                                            "over cutting cycles of a scenario")
    p.add_argument("file", metavar="FILE", help="rule file with a `learnable` table (" +
                   RULE_FILE_HELP + "; only a .fz can say `learnable`)")
    p.add_argument("--scenario", required=True, help="scenario name or YAML path (the cycle)")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="trained rule file")
    p.add_argument("--cycles", type=whole_number, default=15, help="learning cycles (default 15)")
    p.add_argument("--eta", type=finite, default=0.25, help="learning rate (default 0.25)")
    p.add_argument("--rho", type=finite, default=6.0, help="weight of cf^2 in PI (default 6)")
    p.add_argument("--table", default="du", help="the learnable output (default du)")
    p.add_argument("--plot", metavar="PNG", help="PI plot (default: OUT with _pi.png)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scenario setting (repeatable)")
    p.set_defaults(run=run)


def plot_pi(pi: np.ndarray, path: str | Path, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(np.arange(1, len(pi) + 1), pi, "o-")
    ax.set_xlabel("learning (cutting) cycle")
    ax.set_ylabel("performance index PI")
    ax.set_title(plot_text(title))
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path)


def check_learnable(path: str, table: str) -> None:
    """FuzzycError unless FILE's output `table` has learnable terms; said before the scenario
    runs, and for an imported model (FLL, FCL and FIS have no way to mark a term learnable)."""
    from ..formats import load_any, split_block
    rb = load_any(path).rulebase
    learnable = [v.name for v in rb.outputs if np.any(v.learnable)]
    if table in learnable:
        return
    if not learnable:
        problem = "the model has no learnable terms"
    else:
        problem = (f"output `{table}` has no learnable terms (choose one of "
                   f"{', '.join(learnable)} with --table)")
    hint = ("`fuzzyc learn` trains the terms of a .fz `table ... learnable`; an .fll, .fcl or "
            ".fis cannot mark terms learnable: `fuzzyc convert` it to .fz and mark the table "
            "there") if split_block(path)[0].suffix.lower() != ".fz" else \
        "`fuzzyc learn` trains the terms of a `table ... learnable`"
    raise FuzzycError([Diagnostic(None, f"{path}: {problem}; {hint}")])


def run(args) -> int:
    from fuzzyc.plants import scenario as scenarios

    from ..formats import absolute_ref
    from ..learning import learn_scenario, provenance, trained_text

    if args.cycles < 1:
        print("error: --cycles must be at least 1", file=sys.stderr)
        return 2
    plot = args.plot or str(Path(args.output).with_suffix("")) + "_pi.png"
    check_output(args.output)   # before the training, which takes the whole run
    check_output(plot)
    from .simulate import parse_sets     # numbers in fuzzyc's one syntax, as simulate's
    try:
        overrides = parse_sets(args.set)
        check_learnable(args.file, args.table)
        scenario = scenarios.load(args.scenario, overrides)
        scenario.data.setdefault("controller", {})["rulebase"] = absolute_ref(args.file)
        controller, result = learn_scenario(scenario, args.cycles, args.eta, args.rho, args.table)
        text = trained_text(controller.model, result.weights, args.table, provenance(
            Path(args.file).name, args.scenario, args.cycles, args.eta, args.rho, result.pi))
    except FuzzycError as exc:
        for diagnostic in exc.diagnostics:
            print(diagnostic.format(), file=sys.stderr)
        return 2
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    write_text(args.output, text)
    plot_pi(result.pi, plot, f"{controller.model.name} on {scenario.name}")
    for i, (pi, cycle) in enumerate(zip(result.pi, result.cycles), 1):
        state = "" if cycle.finished else " (time limit reached)"
        print(f"cycle {i:3d}: PI = {pi:10.4f}, machining time {cycle.time:8.2f} s{state}")
    print(f"wrote {args.output} (learned `{args.table}` table) and {plot}")
    return 0
