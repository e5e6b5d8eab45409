"""`fuzzyc tune FILE --data train.csv [--validate check.csv | --folds K] --seed S -o OUT`:
fit the numbers FILE's `tune` section frees to the data (least squares within their bounds),
keep its monotone / covers / bounded properties, and write the tuned .fz (only the tuned
numbers changed, a provenance comment block on top).

`fuzzyc tune FILE --scenario NAME --minimize METRIC [--set K=V] [--limit 'M<=X'] -o OUT`:
the same against a closed loop, the cost a metric of the scenario's batched loop, searched
derivative-free; the closed-loop properties of FILE are re-verified on the result (with
--prove, by the reachable-set proof first). --workers N / --scheduler ADDRESS / --chunk LOOPS
run each cost's batch in chunks on Dask (runtime.campaign), with the same numbers."""
from __future__ import annotations

import os

from ..atomic import write_text
from ..display import plural
from ..errors import Diagnostic, FuzzycError
from .common import add_campaign_arguments, at_least, check_output, cluster_from


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("tune", help="fit the numbers a .fz file's `tune` section frees "
                                           "to data, keeping its properties")
    p.add_argument("file", metavar="FILE", help="a .fz rule file with a `tune` section")
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument("--data", metavar="CSV", help="training data: a header naming the "
                        "rule base's inputs and outputs")
    source.add_argument("--scenario", metavar="NAME", help="tune against this scenario's "
                        "closed loop (a name from plants/scenarios or a YAML file)")
    p.add_argument("--minimize", metavar="METRIC", help="with --scenario: the cost, a metric "
                   "label of the scenario or NAME(SIGNAL[, TARGET]), e.g. 'iae(y)'")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="sets",
                   help="with --scenario: override a scenario setting, as simulate --set")
    p.add_argument("--limit", action="append", default=[], metavar="METRIC<=VALUE",
                   dest="limits", help="with --scenario: a metric kept at most VALUE "
                   "(e.g. 'overshoot(y)<=0.02'); repeatable")
    p.add_argument("--method", choices=("least_squares", "anfis", "powell", "nelder-mead"),
                   default=None, help="with --data: least_squares (default) or anfis (Jang's "
                   "1993 hybrid rule, --passes epochs); with --scenario: scipy's "
                   "derivative-free powell (default) or nelder-mead")
    p.add_argument("--max-evaluations", type=at_least(1), default=None, metavar="N",
                   help="with --scenario: closed-loop runs of the search, at most N (the run "
                        "at the written numbers included; the property checks and --limit "
                        "re-checks run loops of their own, not counted; default: scipy's "
                        "own stopping rule)")
    p.add_argument("--batch", type=at_least(1), default=1, help="with --scenario: loops per "
                   "run, the cost their mean (with --randomize: drawn plants)")
    p.add_argument("--randomize", action="store_true",
                   help="with --scenario: draw the plant params of the batch (the seed's)")
    p.add_argument("--max-examples", type=at_least(1), default=30, metavar="N",
                   help="with --scenario: loops of each closed-loop property check (30)")
    p.add_argument("--prove", action="store_true",
                   help="with --scenario: the closed-loop properties get the reachable-set "
                        "proof first (as verify --prove); one proved before must be proved "
                        "after, or the candidate is rejected")
    add_campaign_arguments(p)
    p.add_argument("--prove-boxes", type=at_least(1), default=64, metavar="N",
                   help="with --prove: boxes per closed loop, at most N (64)")
    group = p.add_mutually_exclusive_group()
    group.add_argument("--validate", metavar="CSV", help="data to report the error on")
    group.add_argument("--folds", type=at_least(2), metavar="K",
                       help="K-fold cross-validation error instead")
    p.add_argument("--seed", type=at_least(0), default=0, help="seed (default 0): the fold "
                   "split and the property searches; the same seed gives the same file")
    p.add_argument("--passes", type=at_least(1), default=20,
                   help="hybrid passes for Takagi-Sugeno rule bases (default 20)")
    p.add_argument("--max-nfev", type=at_least(1), default=None, metavar="N",
                   help="evaluations per least-squares run (default: scipy's)")
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="the tuned .fz (never one of the inputs)")
    p.add_argument("--force", action="store_true", help="replace OUT if it exists")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..tune import tune
    _check_not_overwriting([args.file, args.data, args.validate], args.output, args.force)
    check_output(args.output)
    if args.scenario is not None:
        return _run_scenario(args)
    if args.minimize or args.sets or args.limits or args.prove or cluster_from(args):
        raise FuzzycError([Diagnostic(None, "--minimize, --set, --limit, --prove, --workers, "
                                            "--scheduler and --chunk go with --scenario (a "
                                            "closed-loop tune), not with --data")])
    try:
        result = tune(args.file, args.data, validate=args.validate, folds=args.folds,
                      seed=args.seed, passes=args.passes, max_nfev=args.max_nfev,
                      method=args.method)
    except (ValueError, KeyError, OSError) as exc:
        message = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
        raise FuzzycError([Diagnostic(None, message)]) from None
    write_text(args.output, result.text)
    fit = result.fit
    print(f"{args.file}: {plural(len(fit.numbers), 'number')} tuned by {fit.method}")
    print(f"RMSE on {args.data}: {fit.rmse_before:.6g} before, {fit.rmse_after:.6g} after")
    if fit.validation is not None:
        said = args.validate or f"{args.folds}-fold cross-validation"
        before = "" if fit.validation_before is None else f"{fit.validation_before:.6g} before, "
        print(f"RMSE on {said}: {before}{fit.validation:.6g} after")
    for c in fit.properties:
        print(f"property `{c.text}`: {c.before} before, {c.after} after")
    for why in fit.rejected:
        print(f"rejected: {why}")
    print(f"wrote {args.output}")
    return 0


def _run_scenario(args) -> int:
    from ..tune import tune
    from .simulate import parse_sets
    if not args.minimize:
        raise FuzzycError([Diagnostic(None, "--scenario needs --minimize METRIC, e.g. "
                                            "--minimize 'iae(y)'")])
    _check_not_overwriting([args.file], args.output, args.force)
    check_output(args.output)
    try:
        result = tune(args.file, scenario=args.scenario, minimize=args.minimize,
                      sets=parse_sets(args.sets), limits=tuple(args.limits), seed=args.seed,
                      batch=args.batch, randomize=args.randomize, method=args.method,
                      max_evaluations=args.max_evaluations, max_examples=args.max_examples,
                      prove=args.prove, prove_boxes=args.prove_boxes,
                      cluster=cluster_from(args))
    except (ValueError, KeyError, OSError) as exc:
        message = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
        raise FuzzycError([Diagnostic(None, message)]) from None
    write_text(args.output, result.text)
    fit = result.fit
    print(f"{args.file}: {plural(len(fit.numbers), 'number')} tuned by {fit.method}")
    print(f"{args.minimize} on {args.scenario}: {fit.cost_before:.6g} before, "
          f"{fit.cost_after:.6g} after")
    for n, value in zip(fit.numbers, fit.values):
        print(f"  {n.target} = {value:.6g} (was {n.value:.6g}, bounds [{n.lo:g}, {n.hi:g}])")
    for c in fit.properties:
        print(f"property `{c.text}`: {c.before} before, {c.after} after")
    for why in fit.rejected:
        print(f"rejected: {why}")
    print(f"wrote {args.output}")
    return 0


def _check_not_overwriting(inputs: list[str | None], output: str, force: bool) -> None:
    """FuzzycError when OUT is one of the inputs (also through a link: samefile), or exists
    and --force is not given (lexists: a dangling link counts)."""
    for source in filter(None, inputs):
        try:
            same = os.path.exists(output) and os.path.samefile(source, output)
        except OSError:        # a missing input: reading it says so
            same = False
        if same:
            raise FuzzycError([Diagnostic(None, f"{output} is the input file {source}: write "
                                                "the tuned file to another file")])
    if os.path.lexists(output) and not force:
        raise FuzzycError([Diagnostic(None, f"not overwriting {output}, which exists: give "
                                            "--force to replace it")])
