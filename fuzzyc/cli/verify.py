"""`fuzzyc verify FILE...`: check every property of rule files; exit 0 all held, 1 a property
violated (not a recorded finding), 2 bad input.

FILE is any format `fuzzyc.formats.load_any` reads (.fz, .fll, .fcl, .fis, FILE.fcl::NAME).
A file that declares no properties (every imported one, a .fz without `verify`) gets the
default structural ones (`fuzzyc.verifier.runner.default_properties`): consistent; complete;
covers every input at least the level a complete table over terms crossing at 0.5 reaches
(0.5 under min, 0.5^n under product of n inputs); bounded every rule-base output in its range.
They are said to be defaults, before the results and in each result's name (`default: `).
"""
from __future__ import annotations

import contextlib
import sys

from ..formats.tool_semantics import with_tool_semantics
from .common import (RULE_FILE_HELP, add_campaign_arguments, add_progress, add_semantics,
                     at_least, check_output, cluster_from, non_negative)
from .simulate import add_allow_import
from ..errors import FuzzycError


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("verify", help="prove or search the properties in verify blocks "
                                             "(structural defaults for a file without any)")
    p.add_argument("files", nargs="+", metavar="FILE", help=RULE_FILE_HELP)
    p.add_argument("--backend", choices=["numpy", "c"], default="numpy",
                   help="closed loops drive the numpy engine or the generated C")
    p.add_argument("--max-examples", type=at_least(1), default=100,
                   help="hypothesis examples and closed-loop cases per property")
    p.add_argument("--seed", type=at_least(0), default=0)
    p.add_argument("--report", metavar="DIR",
                   help="write verify.json, verify.junit.xml and counterexample plots here")
    p.add_argument("--only", metavar="TEXT", help="only properties whose text contains TEXT")
    p.add_argument("--prove", action="store_true",
                   help="closed loops: compute sound reachable sets first (PROVED, or UNKNOWN "
                        "with the bound and horizon reached), then search (see docs/proofs.md)")
    p.add_argument("--prove-boxes", type=at_least(1), default=64, metavar="N",
                   help="branch-and-bound budget: boxes of the vary ranges per closed loop")
    p.add_argument("--noise-sigmas", type=non_negative, default=0.0, metavar="K",
                   help="cover Gaussian plant noise up to K standard deviations (0: not at "
                        "all; the proof states it)")
    p.add_argument("--scenario", action="append", default=[], metavar="NAME=FILE",
                   type=_loop_scenario,
                   help="run the closed loops that name scenario NAME on the scenario file "
                        "FILE instead (your own plant, e.g. a Gymnasium environment); repeat "
                        "for more")
    add_allow_import(p)
    add_campaign_arguments(p)
    add_progress(p)
    add_semantics(p)
    p.set_defaults(run=run)


def _loop_scenario(text: str) -> tuple[str, str]:
    """--scenario NAME=FILE: a closed loop's scenario name and the YAML file it runs on."""
    import argparse
    name, sep, path = text.partition("=")
    if not sep or not name or not path:
        raise argparse.ArgumentTypeError(f"`{text}`: give NAME=FILE, the scenario name a "
                                         f"closed_loop uses and a scenario YAML file")
    return name, path


def _scenarios_for(model, given: dict[str, str]) -> dict[str, str]:
    """The --scenario files of the closed loops of this model (a name the model's loops do not
    use may be another FILE's)."""
    used = {p.args["scenario"] for p in model.properties if p.kind == "closed_loop"}
    return {name: path for name, path in given.items() if name in used}


def _unused_scenarios(models: list, given: dict[str, str]) -> str | None:
    """The error for a --scenario NAME no closed loop of any FILE names (a misspelt one would
    leave the loop on the shipped scenario of its name)."""
    used = sorted({p.args["scenario"] for m in models for p in m.properties
                   if p.kind == "closed_loop"})
    unused = [name for name in given if name not in used]
    if not unused:
        return None
    return (f"error: --scenario {unused[0]}={given[unused[0]]}: no closed_loop names the "
            f"scenario `{unused[0]}`; the closed loops name: {', '.join(used) or 'none'}")


class _Progress:
    """One line on stderr, rewritten per property: [k/n] file: property. enabled: None on a
    terminal only (--progress: True, --no-progress: False)."""

    def __init__(self, stream=None, enabled: bool | None = None):
        self.stream, self.count = stream or sys.stderr, 0
        self.enabled = self.stream.isatty() if enabled is None else enabled

    def __call__(self, text: str) -> None:
        self.count += 1
        if self.enabled:
            self.stream.write(f"\r\033[K[{self.count}] {text[:70]}")
            self.stream.flush()

    def done(self) -> None:
        if self.enabled:
            self.stream.write("\r\033[K")


def defaults_note(path: str, model) -> str | None:
    """What verify checks in a file without properties, and why those; None when it has some."""
    from ..verifier.runner import default_properties, default_level
    if model.properties:
        return None
    texts = "; ".join(p.text for p in default_properties(model))
    note = (f"{path}: declares no properties; checking the structural defaults: {texts} "
            "(write a `verify` block in a .fz to state your own)")
    for rb in model.blocks:
        if default_level(rb) == 0:
            where = f" in block `{rb.name}`" if len(model.blocks) > 1 else ""
            note += (f"; no `covers`{where}: with and = {rb.inference.and_.name.lower()} a "
                     "rule fires 0 where its terms cross at 0.5, so no level can be asked")
    return note


def run(args) -> int:
    from ..api import load, verify
    from ..verifier.report import VerifyReport
    if args.report:
        check_output(args.report, folder=True)
    progress = _Progress(enabled=args.progress)
    report, notes, bad_input = VerifyReport([]), [], False
    cluster = cluster_from(args)
    given, models = dict(args.scenario), []
    with cluster or contextlib.nullcontext():     # one Dask cluster for every property
        for path in args.files:
            try:
                model = with_tool_semantics(load(path), args.semantics, "verify")
                models.append(model)
                notes.append(defaults_note(path, model))
                report.results += verify(model, max_examples=args.max_examples,
                                         seed=args.seed, backend=args.backend, only=args.only,
                                         report_dir=args.report,
                                         progress=None if args.progress is False else progress,
                                         cluster=cluster, prove=args.prove,
                                         prove_boxes=args.prove_boxes,
                                         noise_sigmas=args.noise_sigmas,
                                         allow_import=args.allow_import,
                                         scenarios=_scenarios_for(model, given)).results
            except FuzzycError as exc:
                progress.done()
                for diagnostic in exc.diagnostics:
                    print(diagnostic.format(), file=sys.stderr)
                bad_input = True
    progress.done()
    for note in filter(None, notes):
        print(note)
    print(report.text())
    if args.report:
        for written in report.write(args.report):
            print(f"wrote {written}")
    unused = _unused_scenarios(models, given)
    if unused:
        print(unused, file=sys.stderr)
    if bad_input or unused:
        return 2
    return 0 if report.passed else 1
