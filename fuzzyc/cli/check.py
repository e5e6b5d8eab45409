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


def fcl_summaries(path: str) -> list[str] | None:
    """An .fcl file named without `::NAME` is checked whole: every FUNCTION_BLOCK, and a block
    without outputs (a membership demo) by its inputs and terms; None for other files."""
    from ..formats import split_block
    from ..language.limits import read_rule_file
    from ..formats.fcl import check_fcl
    file, block = split_block(path)
    if block is not None or file.suffix.lower() != ".fcl":
        return None
    lines = []
    for label, read in check_fcl(read_rule_file(file), str(file)):
        if isinstance(read, Model):
            lines.append(summary(read))
        else:
            ins = ", ".join(f"{v.name}({len(v.terms)})" for v in read)
            lines.append(f"{label}: inputs {ins}; no outputs (membership functions only: "
                         "checked, nothing to evaluate)")
    return lines


def run(args) -> int:
    from ..api import load
    status = 0
    for path in args.files:
        try:
            lines = fcl_summaries(str(path))
            if lines is None:
                model = load(path)
                for warning in model.warnings:
                    print(warning.format(), file=sys.stderr)
                lines = [summary(model)]
            print("\n".join(lines))
        except FuzzycError as exc:
            for diagnostic in exc.diagnostics:
                print(diagnostic.format(), file=sys.stderr)
            status = 2
    return status
