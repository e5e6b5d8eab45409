"""`fuzzyc plot FILE -o DIR`: membership functions and control surfaces as PNG (surfaces over
the rule base's inputs and, when they differ, over the controller's raw inputs)."""
from __future__ import annotations

from .common import RULE_FILE_HELP, check_output
from ..errors import Diagnostic, FuzzycError
from ..language.numbers import not_a_number, parse_number


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("plot", help="plot membership functions and control surfaces")
    p.add_argument("file", metavar="FILE", help=RULE_FILE_HELP)
    p.add_argument("-o", "--out", required=True, metavar="DIR")
    p.add_argument("--inputs", metavar="X,Y", help="the two rule-base inputs of the surface "
                                                   "(default: the last two)")
    p.add_argument("--at", action="append", default=[], metavar="NAME=VALUE",
                   help="value of another input on the surfaces, a rule-base or a raw input "
                        "(default: a rule-base input's upper end when its range is within "
                        "[-1, 1], else the middle of the range)")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..api import load
    from ..plotting import plot_model
    check_output(args.out, folder=True)
    model = load(args.file)
    names = [v.name for v in model.rulebase.inputs]
    axes = None
    if args.inputs:
        axes = tuple(a.strip() for a in args.inputs.split(","))
        unknown = [a for a in axes if a not in names]
        if len(axes) != 2 or unknown:
            raise FuzzycError([Diagnostic(None, f"--inputs takes two of {', '.join(names)}")])
    held = names + [s.name for s in model.signals]
    fixed = {}
    for pair in args.at:
        name, _, value = pair.partition("=")
        if name not in held:
            raise FuzzycError([Diagnostic(None, f"--at: `{name}` is not one of {', '.join(held)}")])
        fixed[name] = parse_number(value)
        if fixed[name] is None:
            raise FuzzycError([Diagnostic(None, f"--at: {not_a_number(value)}")])
    for path in plot_model(model, args.out, axes, fixed):
        print(path)
    return 0
