"""The `fuzzyc` command line: one module per command (`check`, `eval`, ...), each with
add_parser(subparsers) and run(args); `main` parses and reports errors without a traceback."""
from .main import build_parser, main

__all__ = ["build_parser", "main"]
