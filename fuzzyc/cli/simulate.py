"""`fuzzyc simulate FILE --scenario NAME`: run a rule base in a scenario's closed loop.

Writes to -o DIR: trace.csv (the first --csv-loops loops of the batch, 20 unless told: every
loop of 10,000 would be gigabytes), trace.png (the same loops drawn), summary.txt and
summary.json (the scenario's metrics: mean/min/max over the whole batch). --workers,
--scheduler or --chunk split the batch into chunks (runtime.campaign, docs/campaigns.md): the
same files, the trace of the first 20 loops only.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from ..atomic import write_text
from .common import (RULE_FILE_HELP, add_campaign_arguments, add_progress, add_semantics,
                     at_least, batch_size, check_output, cluster_from)
from ..language.limits import MAX_BATCH
from ..errors import Diagnostic, FuzzycError
from ..language.numbers import not_a_number, parse_integer, parse_number
from fuzzyc.runtime.trace import SHOWN_LOOPS


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("simulate", help="run a controller against a plant scenario")
    p.add_argument("file", nargs="?", metavar="FILE",
                   help=RULE_FILE_HELP + " (default: the scenario's own)")
    p.add_argument("--scenario", required=True, help="scenario name or YAML path")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="sets",
                   help="override a scenario setting, dotted (plant.tension=800)")
    p.add_argument("--batch", type=batch_size, default=1,
                   help=f"independent loops (default 1, at most {MAX_BATCH:,}: about 1 kB each)")
    p.add_argument("--randomize", action="store_true",
                   help="draw the plant params of each loop around the scenario's values")
    p.add_argument("--baseline", action="store_true", help="run the scenario's baseline")
    p.add_argument("--compare", action="store_true",
                   help="run the scenario's baseline too (same batch and seed): trace.png "
                        "draws both, summary.txt and .json hold both")
    p.add_argument("--backend", choices=("numpy", "c"), default="numpy")
    add_semantics(p)
    p.add_argument("--seed", type=at_least(0), default=0)
    p.add_argument("--pace", choices=("sim", "wall"), default="sim")
    add_progress(p)
    p.add_argument("--csv-loops", type=csv_loops, default=SHOWN_LOOPS, metavar="N|all",
                   help=f"loops written to trace.csv (default {SHOWN_LOOPS}, as many as trace.png "
                        f"draws: a big batch would make a huge file; `all` writes every loop); "
                        f"the metrics always cover the whole batch")
    p.add_argument("-o", "--out", default="out/simulate", help="output folder")
    add_allow_import(p)
    add_campaign_arguments(p)
    p.set_defaults(run=run)


def add_allow_import(parser) -> None:
    """--allow-import MODULE: the one way a scenario's `module:Class` gets imported (the user
    says so here; the YAML file alone never imports code, docs/security.md)."""
    parser.add_argument("--allow-import", action="append", default=[], metavar="MODULE",
                        help="let scenarios import MODULE (and its submodules) for a "
                             "Gymnasium `env: MODULE:Class`; repeat for more (a scenario file "
                             "alone imports nothing)")


def csv_loops(text: str) -> int | None:
    """--csv-loops: a positive count, or `all` (None: no limit)."""
    if text == "all":
        return None
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"`{text}` is not a positive number or `all`")
    return int(text)


def csv_note(batch: int, loops: int | None, recorded: int) -> str:
    """What trace.csv holds, said when it is not the whole batch. recorded: the loops the
    trace has (a campaign in chunks records the first 20 only)."""
    written = recorded if loops is None else min(loops, recorded)
    if written >= batch:
        return ""
    why = ("--csv-loops all writes every one" if recorded >= batch
           else f"a campaign in chunks records the first {recorded} only")
    return f" (trace.csv holds the first {written} of {batch} loops: {why})"


def parse_sets(items: list[str]) -> dict[str, str]:
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise FuzzycError([Diagnostic(None, f"--set {item}: write KEY=VALUE, "
                                                f"e.g. plant.tension=800")])
        out[key.strip()] = _yaml_value(item, value.strip())
    return out


def _yaml_value(item: str, text: str) -> str:
    """A --set value as the scenario's YAML reads it, numbers in fuzzyc's one syntax
    (fuzzyc.language.numbers): YAML alone reads `1_000` as 1000, `010` as 8, `1:30` as 90, `.inf`, and
    `1e3` as a string. A number is passed in YAML's canonical spelling; other YAML numbers are
    refused."""
    import yaml
    from fuzzyc.plants import scenario_yaml    # bounded: `[[[...` 1,000 deep is a YAMLError
    number = parse_number(text)
    if number is None:
        try:
            read = scenario_yaml.load(text)
        except yaml.YAMLError:
            return text     # the scenario loader says what is wrong with it
        if isinstance(read, (int, float)) and not isinstance(read, bool):
            raise FuzzycError([Diagnostic(None, f"--set {item}: {not_a_number(text)}")])
        return text
    if parse_integer(text) is not None:
        return str(int(text))
    if math.isnan(number):
        return ".nan"
    if math.isinf(number):
        return ".inf" if number > 0 else "-.inf"
    mantissa, e, exponent = repr(number).partition("e")     # YAML wants 1.0e+20, not 1e+20
    return (mantissa if "." in mantissa else mantissa + ".0") + (e + exponent if e else "")


BACKENDS = {"numpy": "numpy engine", "c": "generated C (float)",
            "baseline": "Python (the scenario's baseline)"}


def format_summary(title: str, controller: str, summary: dict, trace,
                   notes: list[str] = (), batch: int | None = None,
                   backend: str | None = None) -> str:
    """batch: the loops the summary is over (default the trace's). backend: what ran the
    controller, a key of BACKENDS (numpy, c, baseline), named on the controller's line."""
    ran = f"; back end: {BACKENDS.get(backend, backend)}" if backend else ""
    lines = [f"{title}", f"controller: {controller}{ran}; batch {batch or trace.batch}; "
             f"{trace.steps} periods of {trace.period * 1000:g} ms"]
    if trace.deadline_misses:
        lines.append(f"deadline misses: {trace.deadline_misses}")
    for label, v in summary.items():
        if v["mean"] != v["mean"]:   # NaN: the event never happened in any loop
            lines.append(f"  {label:45s} not reached in {trace.steps * trace.period:g} s "
                         "(a longer run: --set duration=...)")
            continue
        spread = "" if v["min"] == v["max"] else f"  (min {v['min']:.4g}, max {v['max']:.4g})"
        lines.append(f"  {label:45s} {v['mean']:.4g} {v['unit']}{spread}")
    lines += [f"note: {note}" for note in notes]
    return "\n".join(lines) + "\n"


def controller_notes(scenario, baseline: bool) -> list[str]:
    """The warning that the scenario's rule base is untrained, when it is (and it runs)."""
    from ..formats import load_any
    from ..learning import untrained_note
    from fuzzyc.runtime.simulate import rulebase_ref
    if baseline:
        return []
    note = untrained_note(load_any(rulebase_ref(scenario)))
    return [note] if note else []


def _block_named(ref: str) -> str:
    """The NAME of FILE::NAME (a function block of a several-block file); '' for FILE alone."""
    return ref.rpartition("::")[2] if "::" in ref else ""


def own_notes(scenario) -> list[str]:
    """The scenario's notes when the rule base run is the scenario's own: they describe that
    one ("the fuzzy PI ... does not overshoot" says nothing about the FILE a user gives)."""
    from fuzzyc.plants.scenario import RULEBASE_SETTING, load
    if RULEBASE_SETTING not in scenario.settings:
        return scenario.notes
    try:
        own = load(scenario.path, allow_import=scenario.allow_import)
        if own.rulebase_path() is None:
            return []
        same = (own.rulebase_path().resolve() == scenario.rulebase_path().resolve()
                and _block_named(own.rulebase_ref()) == _block_named(scenario.rulebase_ref()))
    except (FuzzycError, OSError):
        return []
    return scenario.notes if same else []


def run(args) -> int:
    from fuzzyc.runtime.plots import plot_runs
    from fuzzyc.runtime.simulate import references, rulebase_ref, signal_units
    from ..api import simulate
    check_output(args.out, folder=True)
    cluster = cluster_from(args)
    if cluster is not None and args.pace != "sim":
        raise FuzzycError([Diagnostic(None, "--pace wall runs one batch in real time; "
                                            "--workers, --scheduler and --chunk need --pace sim")])
    if args.compare and args.baseline:
        raise FuzzycError([Diagnostic(None, "--compare runs the baseline beside the rule "
                                            "base; --baseline alone runs only the baseline")])

    def run_loop(baseline: bool):
        return simulate(args.scenario, args.file, batch=args.batch,
                        settings=parse_sets(args.sets), baseline=baseline,
                        randomize=args.randomize, backend=args.backend, seed=args.seed,
                        pace=args.pace, progress=args.progress,
                        cluster=cluster, semantics=args.semantics,
                        allow_import=args.allow_import)

    run = run_loop(args.baseline)
    scenario, trace, summary = run.scenario, run.trace, run.metrics
    out = Path(args.out)
    trace.to_csv(out / "trace.csv", loops=args.csv_loops)
    controller = "baseline" if args.baseline else rulebase_ref(scenario)
    backend = "baseline" if args.baseline else args.backend
    shown = backend if args.semantics == "exact" or args.baseline else (
        f"{BACKENDS[backend]}, {args.semantics} semantics")
    text = format_summary(scenario.title, controller, summary, trace,
                          controller_notes(scenario, args.baseline) + own_notes(scenario),
                          args.batch, shown)
    runs = {"baseline" if args.baseline else "fuzzy": trace}
    compared = None
    if args.compare:
        base = run_loop(True)
        runs["baseline"], compared = base.trace, base.metrics
        text += "\n" + format_summary(scenario.title, "baseline", compared, runs["baseline"],
                                      batch=args.batch, backend="baseline")
    panels = [name for name in scenario.plots if name in trace] or None
    plot_runs(runs, out / "trace.png", panels, references(scenario), scenario.title,
              signal_units(scenario))
    write_text(out / "summary.txt", text)
    write_text(out / "summary.json", _json(scenario, controller, summary, args.batch,
                                           trace.deadline_misses, compared, backend))
    sys.stdout.write(text)
    print(f"wrote {out}/trace.csv, trace.png, summary.txt, summary.json"
          + csv_note(args.batch, args.csv_loops, trace.batch))
    return 0


def _json(scenario, controller: str, summary: dict, batch: int, deadline_misses: int,
          baseline: dict | None = None, backend: str = "numpy") -> str:
    """JSON without NaN (not valid JSON): a metric that does not exist is null. `baseline`: the
    metrics of the baseline run beside (--compare)."""
    def clean(metrics: dict) -> dict:
        return {k: {kk: None if isinstance(vv, float) and vv != vv else vv
                    for kk, vv in v.items()} for k, v in metrics.items()}
    result = {"scenario": scenario.name, "controller": controller, "backend": backend,
              "batch": batch,
              "deadline_misses": deadline_misses, "metrics": clean(summary)}
    if baseline is not None:
        result["baseline_metrics"] = clean(baseline)
    return json.dumps(result, indent=2) + "\n"
