"""`fuzzyc check FILE...`: validate rule files and print a one-line summary of each."""
from __future__ import annotations

import sys

from .common import RULE_FILE_HELP
from ..display import plural
from ..errors import FuzzycError
from ..semantics.model import Model


def summary(model: Model) -> str:
    blocks = model.blocks
    inputs, outputs = _variables(blocks, "inputs"), _variables(blocks, "outputs")
    terms = sum(v.n_terms for v in inputs + outputs)
    ins = ", ".join(f"{v.name}({v.n_terms})" for v in inputs)
    outs = ", ".join(f"{v.name}({v.n_terms})" for v in outputs)
    chain = ", ".join(o.name for o in model.outputs) or "-"
    several = f"{len(blocks)} rule blocks; " if len(blocks) > 1 else ""
    return (f"{model.source_path}: {model.name}: inputs {ins}; outputs {outs}; "
            f"{plural(terms, 'term')}; {several}"
            f"{plural(sum(rb.n_rules for rb in blocks), 'rule')}; controller outputs {chain}; "
            f"{plural(len(model.properties), 'property', 'properties')}")


def _variables(blocks, kind: str) -> list:
    """The blocks' input or output variables, each once (blocks may share inputs)."""
    return list({v.name: v for rb in blocks for v in getattr(rb, kind)}.values())


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
