"""The verifier: properties of rule bases and closed loops, each answered as proved (exact, on
the tables or in closed form), held on N searched cases, or violated with a counterexample.

    from fuzzyc.verifier import verify_model, verify_file, Options
    results = verify_file("rulebases/wedm_three_region.fz", Options(max_examples=50))

verify_file reads every format fuzzyc.formats.load_any reads (.fz .fll .fcl .fis,
FILE.fcl::NAME). A model that declares no properties (every imported one, a .fz without a
`verify` block) is checked on the structural defaults (runner.default_properties; result names
say `default: `), which need nothing but the rule base:
- consistent, and complete on every output (every cell of input terms has a rule);
- covers <every input> at least L, L = the rule base's AND of 0.5 over its n inputs (min: 0.5,
  product: 0.5^n): the level a complete table over terms that cross their neighbours at 0.5
  (the usual partition) reaches everywhere, so a sound design passes and a gap where the
  controller would fall back to its default is found. With an AND that gives 0 there (bounded
  difference, drastic, nilpotent min) no level can be asked and coverage is left out;
- bounded <every rule-base output> in its range (a TSK consequent can leave it).
Not continuous (a style of table, not a defect) and not monotone (it needs the direction the
designer intends); closed loops need a scenario. A file with a `verify` block gets only its own.

Meaning of the properties (the choices a user should know):
- covers I1, I2 at least L: at every point of the listed inputs' ranges some rule fires >= L;
  clauses on inputs not listed are ignored (coverage of the projection).
- monotone OUT DIR in IN where V is T: on the tables, along IN's terms (sorted by peak) with
  the other inputs fixed, in the cells of the guard; in the continuous space, where the guard
  is fully true (membership 1, e.g. e1 = 1 for a triangle peaking at 1).
- overshoot S below X: how far S goes past its final value F (mean of the last 10 %) on the
  far side from where it started: max over time of sign(F - S[0]) * (S - F), at most X
  (runtime.metrics.overshoot_excess with F as the target; 0 when S starts at F).
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

from ..formats import load_any
from .result import Evidence, Result, Status
from .runner import Options, verify_model


def verify_file(path: str, options: Options | None = None) -> list[Result]:
    """Any format load_any reads; a file without properties gets the structural defaults."""
    return verify_model(load_any(path), options)


__all__ = ["Evidence", "Options", "Result", "Status", "verify_file", "verify_model"]
