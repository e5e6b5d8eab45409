"""The API target: `fuzzyc.evaluate(model, values)` with generated values.

An input is (model file, seed); the values are rebuilt from the seed, so a failure reproduces
with `python -m tests.fuzz.api MODEL SEED` (from the repository root).

The contract (docs/api.md): a missing or unknown input is a KeyError, a value that is not a
real number (or an array of them) a ValueError, inputs that are no mapping a TypeError; the
message names the input (its "location").
A result is one float array per output, of the inputs' broadcast shape. Any other exception is
a failure, and so is a rejection that names no input.
"""
from __future__ import annotations

import random
import sys
import traceback
from functools import lru_cache

from .generate import api_value, name
from .runner import Run, bounded

API_CALLS = ("evaluate", "explain")


@lru_cache(maxsize=None)
def _model(path: str):
    from fuzzyc.formats import load_any
    return load_any(path)


def values_for(model, seed: int):
    """The inputs' values drawn from `seed`: one per rule-base input, now and then one missing,
    one too many, or no mapping at all."""
    rnd = random.Random(seed)
    names = [v.name for v in model.rulebase.inputs]
    values = {n: api_value(rnd) for n in names}
    kind = rnd.random()
    if kind < 0.05 and names:
        del values[rnd.choice(names)]
    elif kind < 0.1:
        values[rnd.choice((name(rnd), 1, None, (1, 2)))] = 1.0
    elif kind < 0.13:
        values = rnd.choice((None, [1.0], "x", 1.0))
    return values


def run(argv: list[str], seconds: float) -> Run:
    """`argv`: [call, model file, seed]."""
    import numpy as np
    import fuzzyc
    call, path, seed = argv
    result = Run(argv, None, "")
    model = _model(path)
    names = [v.name for v in model.rulebase.inputs]
    values = None
    try:
        with bounded(seconds):
            values = values_for(model, int(seed))
            out = getattr(fuzzyc, call)(model, values)
    except (KeyError, ValueError, TypeError) as exc:   # the documented rejections
        message = str(exc)
        result.code, result.stderr = 2, f"error: {message}\n"
        # the message must say which input (KeyError: the model's inputs are listed)
        result.located = any(f"{n}" in message for n in names) or not names
        return result
    except BaseException as exc:               # noqa: B036 - classifying is the point
        if isinstance(exc, KeyboardInterrupt):
            raise
        result.error = traceback.format_exc()
        return result
    result.code, result.located = 0, True      # located: set on every API run, read by classify
    if call == "evaluate":
        bad = [k for k, v in out.items()
               if not (isinstance(v, np.ndarray) and v.dtype == float and np.isfinite(v).all())]
        result.stdout = f"outputs {', '.join(bad)} are not finite float arrays" if bad else ""
    return result


def main(argv: list[str]) -> int:
    done = run(["evaluate", *argv] if len(argv) == 2 else argv, 60.0)
    print(done.error or done.stderr or done.stdout or f"ok (exit {done.code})")
    return 1 if done.error else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
