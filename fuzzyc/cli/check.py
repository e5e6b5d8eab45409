"""`fuzzyc check FILE...`: validate rule files and print a one-line summary of each."""
from __future__ import annotations

import sys

from .common import RULE_FILE_HELP
from ..errors import FuzzycError
from ..model import Model


def summary(model: Model) -> str:
    rb = model.rulebase
    terms = sum(v.n_terms for v in rb.inputs + rb.outputs)
    ins = ", ".join(f"{v.name}({v.n_terms})" for v in rb.inputs)
    outs = ", ".join(f"{v.name}({v.n_terms})" for v in rb.outputs)
    chain = ", ".join(o.name for o in model.outputs) or "-"
    return (f"{model.source_path}: {model.name}: inputs {ins}; outputs {outs}; {terms} terms; "
            f"{rb.n_rules} rules; controller outputs {chain}; {len(model.properties)} properties")


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("check", help="validate rule files (.fz, .fll, .fcl, .fis)")
    p.add_argument("files", nargs="+", metavar="FILE", help=RULE_FILE_HELP)
    p.set_defaults(run=run)


def run(args) -> int:
    from ..api import load
    status = 0
    for path in args.files:
        try:
            print(summary(load(path)))
        except FuzzycError as exc:
            for diagnostic in exc.diagnostics:
                print(diagnostic.format(), file=sys.stderr)
            status = 2
    return status
