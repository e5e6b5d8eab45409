"""The verifier: properties of rule bases and closed loops, each answered as proved (exact, on
the tables or in closed form), held on N searched cases, or violated with a counterexample.

    from fuzzyc.verify import verify_model, verify_file, Options
    results = verify_file("rulebases/wedm_three_region.fz", Options(max_examples=50))
"""
from __future__ import annotations

from ..parser import load
from .result import Evidence, Result, Status
from .runner import Options, verify_model


def verify_file(path: str, options: Options | None = None) -> list[Result]:
    return verify_model(load(path), options)


__all__ = ["Evidence", "Options", "Result", "Status", "verify_file", "verify_model"]
