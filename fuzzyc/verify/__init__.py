"""The verifier: properties of rule bases and closed loops, each answered as proved (exact, on
the tables or in closed form), held on N searched cases, or violated with a counterexample.

    from fuzzyc.verify import verify_model, verify_file, Options
    results = verify_file("rulebases/wedm_three_region.fz", Options(max_examples=50))

Meaning of the properties (the choices a user should know):
- covers I1, I2 at least L: at every point of the listed inputs' ranges some rule fires >= L;
  clauses on inputs not listed are ignored (coverage of the projection).
- monotone OUT DIR in IN where V is T: on the tables, along IN's terms (sorted by peak) with
  the other inputs fixed, in the cells of the guard; in the continuous space, where the guard
  is fully true (membership 1, e.g. e1 = 1 for a triangle peaking at 1).
- overshoot S below X: max over time of S minus its final value (mean of the last 10 %).
- A violation the file expects is written as `note "finding: <property text> -- <why>"`;
  for a rule-table violation the note must name every reported table place ([...] in the
  report), so a new bad cell is never hidden by an old note.
- closed_loop SCENARIO: `set a.b = v` overrides the scenario; `set learn.cycles = N` (and
  learn.eta, learn.rho) first trains the file's learnable weights on N cycles of the scenario;
  `vary plant.P in [lo, hi]` draws P per loop, and a varied plant input (e.g. height) may also
  get a step at a drawn time; `vary controller.P in [lo, hi]` does the same for a param of the
  file (set-point changes); `steps before T` bounds the step times. `fault S nan|stuck for T`:
  in some loops the measured plant output S reads NaN or sticks for T from a drawn time, for
  every block after the plant; checks read S's true value (the sensor's is `sensed_S`).
  In a check, `t` is the time (s) and `baseline_X` is signal X of the scenario's baseline
  controller run on the same cases (e.g. the corner controller's error against normal
  machining).
"""
from __future__ import annotations

from ..parser import load
from .result import Evidence, Result, Status
from .runner import Options, verify_model


def verify_file(path: str, options: Options | None = None) -> list[Result]:
    return verify_model(load(path), options)


__all__ = ["Evidence", "Options", "Result", "Status", "verify_file", "verify_model"]
