"""`fuzzyc compile FILE --target c|lut -o DIR`: the C header (whole chain) or a lookup table."""
from __future__ import annotations

import shutil
from pathlib import Path

from ..errors import Diagnostic, FuzzycError, source_lines
from ..semantics.model import SourceLoc
from ..formats.tool_semantics import with_tool_semantics
from .common import RULE_FILE_HELP, add_semantics, check_output, whole_number

NUMERIC = ("float", "double", "q15", "q31")
LUT_HINT = 1e-3     # a lookup table's error above this fraction of the range names --resolution


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "compile", help="generate C: a self-contained header (--target c) or a lookup table",
        description="Writes DIR/NAME.h (target c) or DIR/NAME_lut.h (target lut) and prints "
                    "its code + constant data size and stack use as compiled by gcc -O2.")
    p.add_argument("file", metavar="FILE", help=RULE_FILE_HELP)
    p.add_argument("--target", choices=("c", "lut"), default="c")
    p.add_argument("-o", "--output", metavar="DIR", default=".")
    p.add_argument("--numeric", choices=NUMERIC, default="float",
                   help="arithmetic of the generated code (target c); q15/q31 emit the whole "
                        "chain on integers, NAME_q15.h / NAME_q31.h")
    p.add_argument("--resolution", type=whole_number, default=33,
                   help="grid points per input (target lut)")
    add_semantics(p)
    p.add_argument("--prove", action="store_true",
                   help="prove the header free of run-time errors with Frama-C's EVA over "
                        "every input (NaN and infinities too), see docs/c-proofs.md")
    p.set_defaults(run=run)


def _print_fixed_point_bounds(model, numeric: str) -> None:
    """The derived worst cases the header states, as fractions of each output's range."""
    from ..backends.c_fixed.header import CHAIN_STEPS, chain_error_bound, derived_error_bound
    from ..backends.rule_blocks import emitted_blocks
    emitted = emitted_blocks(model)
    for k, rb in enumerate(emitted):
        rb_bound = derived_error_bound(model, numeric, block=k if len(emitted) > 1 else None)
        if rb_bound is not None:
            which = f"rule block {k} ({rb.name})" if len(emitted) > 1 else "the rule base"
            print(f"derived worst case of {which}: " + ", ".join(
                f"{v.name} {e:.3g}" for v, e in zip(rb.outputs, rb_bound))
                + " of the output's range")
    after_one = chain_error_bound(model, numeric, 1)
    after_run = chain_error_bound(model, numeric, CHAIN_STEPS)
    print(f"derived worst case of the chain after 1 / {CHAIN_STEPS:,} steps: " + ", ".join(
        f"{name} {after_one[name]:.3g} / {after_run[name]:.3g}" for name in after_one)
        + " of the output's range")


def _check_file_name(file: str, model_name: str, filename: str) -> None:
    """FuzzycError, at the model's name in the file where it is found there, when the header's
    file name would pass MAX_FILE_NAME_BYTES (the system refuses it: `File name too long`)."""
    from ..formats import split_block
    from ..language.limits import MAX_FILE_NAME_BYTES, read_rule_file
    size = len(filename.encode())
    # fuzzyc.atomic writes it first as `.NAME.h.<12 hex digits>.h`: 16 bytes longer
    longest = MAX_FILE_NAME_BYTES - 16
    if size <= longest:
        return
    path = split_block(file)[0]
    lines = source_lines(read_rule_file(path))
    where = next(((n, line) for n, line in enumerate(lines, 1) if model_name in line), None)
    loc = None if where is None else SourceLoc(str(path), where[0], where[1].index(model_name) + 1)
    raise FuzzycError([Diagnostic(
        loc, f"the model name ({len(model_name)} characters) would make the header's file name "
             f"{size} bytes long: at most {longest} (a file name has at most "
             f"{MAX_FILE_NAME_BYTES} bytes, fuzzyc.language.limits.MAX_FILE_NAME_BYTES, and the header is "
             "first written under a name 16 bytes longer); give the model a shorter name",
        None if where is None else where[1])])


def _at_defuzzify(diag: Diagnostic, file: str) -> Diagnostic:
    """A back end's refusal of a defuzzifier (`... `centroid` is not supported`), placed at
    the file's `defuzzify = centroid` where the file says it so (a .fz); others as they are."""
    import re
    from ..formats import split_block
    from ..language.limits import read_rule_file
    word = re.search(r"`(\w+)` is not supported", diag.message)
    if diag.loc is not None or word is None:
        return diag
    path = split_block(file)[0]
    try:
        lines = source_lines(read_rule_file(path))
    except (FuzzycError, OSError):
        return diag
    pattern = re.compile(rf"\bdefuzzify\s*=\s*({re.escape(word.group(1))})\b")
    for n, line in enumerate(lines, 1):
        found = pattern.search(line.split("#", 1)[0])
        if found:
            return Diagnostic(SourceLoc(str(path), n, found.start(1) + 1), diag.message, line)
    return diag


def run(args) -> int:
    from ..api import compile_c, compile_lut, load
    from ..backends.c.load import STRICT_FLAGS, footprint, measured_entry_points
    from ..backends.c.proof import frama_c
    from ..escape import c_identifier
    check_output(args.output, folder=True)
    if args.prove and frama_c() is None:     # before writing anything
        raise FuzzycError([Diagnostic(None, "--prove needs Frama-C, which is not installed "
                                            "(`frama-c` on PATH; Debian: apt-get install "
                                            "frama-c-base); nothing was written")])
    model = with_tool_semantics(load(args.file), args.semantics, "compile")
    name = c_identifier(model.name)
    suffix = "_lut" if args.target == "lut" else {"float": "", "double": ""}.get(
        args.numeric, "_" + args.numeric)
    _check_file_name(args.file, model.name, f"{name}{suffix}.h")     # as api.compile_* name it
    if args.target == "lut":
        header = compile_lut(model, args.resolution)
        from ..backends.lut import Core
        for var in Core(model.blocks).outputs:
            e = header.max_error[var.name]
            print(f"lookup table max error {var.name}: {e:.4g} "
                  f"({e / (var.hi - var.lo):.3e} of its range)"
                  + (f"; a finer grid lowers it (--resolution, now {args.resolution})"
                     if e > LUT_HINT * (var.hi - var.lo) else ""))
    else:
        try:
            header = compile_c(model, args.numeric)
        except FuzzycError as exc:
            raise FuzzycError([_at_defuzzify(d, args.file) for d in exc.diagnostics]) from None
        if args.numeric in ("q15", "q31"):
            _print_fixed_point_bounds(model, args.numeric)
    path = Path(args.output) / header.filename
    # Built before it is published: a header gcc rejects is an error and never lands in DIR.
    kind = args.numeric if args.target == "c" else "lut"
    if shutil.which("gcc") is None:
        header.write(args.output)
        print(f"wrote {path} (not test-built: no C compiler `gcc` on PATH)")
    else:
        entry_points = measured_entry_points(name, kind)
        sizes = {level: footprint(header.filename, header.text, entry_points, (level,),
                                  failure=f"nothing was written to {path}")
                 for level in ("-O2", "-Os")}
        header.write(args.output)
        print(f"wrote {path} (test-built with gcc {' '.join(STRICT_FLAGS)})")
        for level, (code, _, stack) in sizes.items():
            print(f"  gcc {level}: {code} bytes code + constant data, {stack} bytes stack")
    if args.prove:
        from ..backends.c.proof import prove
        proof = prove(model, kind, (header.filename, header.text))
        print(proof.summary())
        if not proof.proved:
            return 1
    return 0
