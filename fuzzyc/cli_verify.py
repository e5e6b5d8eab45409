"""`fuzzyc verify FILE...`: check every property of rule files; exit 0 all held, 1 a property
violated (not a recorded finding), 2 bad input."""
from __future__ import annotations

import sys

from .errors import FuzzycError


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("verify", help="prove or search the properties in verify blocks")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--backend", choices=["numpy", "c"], default="numpy",
                   help="closed loops drive the numpy engine or the generated C")
    p.add_argument("--max-examples", type=int, default=100,
                   help="hypothesis examples and closed-loop cases per property")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--report", metavar="DIR",
                   help="write verify.json, verify.junit.xml and counterexample plots here")
    p.add_argument("--only", metavar="TEXT", help="only properties whose text contains TEXT")
    p.set_defaults(run=run)


class _Progress:
    """One line on stderr, rewritten per property: [k/n] file: property."""

    def __init__(self, stream=None):
        self.stream, self.count = stream or sys.stderr, 0
        self.enabled = self.stream.isatty()

    def __call__(self, text: str) -> None:
        self.count += 1
        if self.enabled:
            self.stream.write(f"\r\033[K[{self.count}] {text[:70]}")
            self.stream.flush()

    def done(self) -> None:
        if self.enabled:
            self.stream.write("\r\033[K")


def run(args) -> int:
    from .parser import load
    from .verify import Options, verify_model
    from .verify.report import format_text, write_reports
    progress = _Progress()
    options = Options(backend=args.backend, max_examples=args.max_examples, seed=args.seed,
                      report_dir=args.report, only=args.only, progress=progress)
    results, bad_input = [], False
    for path in args.files:
        try:
            results += verify_model(load(path), options)
        except FuzzycError as exc:
            progress.done()
            for diagnostic in exc.diagnostics:
                print(diagnostic.format(), file=sys.stderr)
            bad_input = True
    progress.done()
    print(format_text(results))
    if args.report:
        for written in write_reports(results, args.report):
            print(f"wrote {written}")
    if bad_input:
        return 2
    return 1 if any(r.is_failure for r in results) else 0
