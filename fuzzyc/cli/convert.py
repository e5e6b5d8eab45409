"""`fuzzyc convert IN OUT`: import .fz/.fll/.fcl/.fis, export .fz/.fll/.fcl/.fis (by extension).

What the output file cannot carry is printed as warnings (the bare rule base is still written);
a rule base the target format cannot say at all, or a bad input file, exits with status 2.
OUT is never IN (also not through a link), and an existing OUT is replaced only with --force:
a conversion may leave things out, and it would do so for good over the only copy.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

from .common import RULE_FILE_HELP, check_output


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "convert", help="convert between .fz, fuzzylite .fll, IEC 61131-7 .fcl and MATLAB .fis "
                        "(both ways)")
    p.add_argument("input", metavar="IN", help=RULE_FILE_HELP)
    p.add_argument("output", metavar="OUT", help="a .fz, .fll, .fcl or .fis file to write")
    p.add_argument("--strict", action="store_true",
                   help="refuse (exit 2) instead of writing when something would be left out")
    p.add_argument("--force", action="store_true",
                   help="replace OUT if it exists (never when OUT is IN)")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..api import load, save
    from ..errors import Diagnostic, FuzzycError
    from ..formats import WRITERS
    from ..formats.blocks import file_variables

    check_output(args.output)      # first: a folder or a device as OUT is its own error
    _check_not_overwriting(args.input, args.output, args.force)
    model = load(args.input)
    imported = _suffix(args.input) != ".fz"   # a .fz file's notes are its own findings
    for note in model.notes if imported else []:
        print(f"{args.input}: note: {note}", file=sys.stderr)
    if args.strict:
        writer = WRITERS.get(_suffix(args.output))
        lost: list[str] = []
        if writer is not None:
            writer(model, lost)
        if lost:
            raise FuzzycError([Diagnostic(None, f"--strict: {args.output} would leave out {w}")
                               for w in lost])
    for warning in save(model, args.output):
        print(f"{args.output}: warning: {warning}", file=sys.stderr)
    inputs, outputs = file_variables(model)
    blocks = f"{len(model.blocks)} rule blocks, " if len(model.blocks) > 1 else ""
    from ..display import plural
    print(f"wrote {args.output}: {blocks}{plural(sum(rb.n_rules for rb in model.blocks), 'rule')}"
          f", {plural(len(inputs), 'input')}, {plural(len(outputs), 'output')}")
    return 0


def _check_not_overwriting(source_ref: str, output: str, force: bool) -> None:
    """FuzzycError when OUT is the input file (samefile: also through a symbolic or hard link),
    or exists and --force is not given. lexists: a dangling link counts as existing."""
    from ..errors import Diagnostic, FuzzycError
    from ..formats import split_block
    source = split_block(source_ref)[0]
    try:
        same = os.path.exists(output) and os.path.samefile(source, output)
    except OSError:         # the input is missing or unreadable: load() says so
        same = False
    if same:
        raise FuzzycError([Diagnostic(None, f"{output} is the input file {source_ref}: a "
                                            "conversion may leave things out, write it to "
                                            "another file")])
    if os.path.lexists(output) and not force:
        raise FuzzycError([Diagnostic(None, f"not overwriting {output}, which exists: give "
                                            "--force to replace it")])


def _suffix(path: str) -> str:
    return Path(path).suffix.lower()
