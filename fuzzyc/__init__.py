"""fuzzyc: a declarative language, compiler, verifier and runtime for fuzzy controllers.

The public API is what this module exports (documented in docs/api.md); the modules under it
are internal and may change between versions. The names load on first use, so `import fuzzyc`
(and the command line's start) does not pay for numpy, sympy and lark until they are needed.
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .api import (Controller, Explanation, FuzzycError, Header, Learning, Model,
                      ModelBuilder, Simulation, compile_c, compile_lut, compiled_evaluator,
                      copy_examples, evaluate, example, examples, explain, learn, load, parse,
                      plot, save, simulate, tune, verify)
    from .verifier.report import VerifyReport
    from .verifier.result import Evidence, Result, Status

__version__ = "0.1.0"

_HOME = {**dict.fromkeys(["Controller", "Explanation", "FuzzycError", "Header", "Learning",
                          "Model", "ModelBuilder", "Simulation", "compile_c", "compile_lut",
                          "compiled_evaluator", "copy_examples", "evaluate", "example",
                          "examples", "explain", "learn", "load", "parse", "plot", "save",
                          "simulate", "tune", "verify"],
                         "fuzzyc.api"),
         "VerifyReport": "fuzzyc.verifier.report",
         **dict.fromkeys(["Evidence", "Result", "Status"], "fuzzyc.verifier.result")}

__all__ = sorted(_HOME) + ["__version__"]


def __getattr__(name: str) -> Any:
    if name not in _HOME:
        raise AttributeError(f"module 'fuzzyc' has no attribute '{name}'")
    return getattr(importlib.import_module(_HOME[name]), name)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOME))
