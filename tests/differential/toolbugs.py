"""Known bugs of the tools, recognised with evidence: a file the tool gets wrong is no
agreement and no disagreement of fuzzyc's, but a tool error whose message names the bug and the
rows it explains (`explain`).  A bug is claimed only where its evidence holds on every row in
question; anything else stays a disagreement.

- pyfuzzylite 8.0.6, SemiEllipse.membership (term.py): sqrt(r^2 - (x - c)^2) / r on
  [start, end]; at an end x - c rounds past r, the square root of a negative number is NaN,
  and the NaN membership makes the output NaN (the semi-ellipse is 0 at its ends: fuzzylite 6
  and fuzzyc give the number).
- Octave fuzzy-logic-toolkit 0.4.6, defuzzify_output_sugeno.m: where no rule fires for a
  Sugeno output, aggregate_output_sugeno.m removes every 0-height singleton and
  `next_agg_output(1, :)` indexes the empty matrix: evalfis fails for the whole input matrix
  ("out of bound 0 (dimensions are 0x0)"), where MATLAB gives the output's default.
- Octave fuzzy-logic-toolkit 0.4.6, hamacher_sum.m: the aggregation folds the rules' sets with
  (x + y - 2xy) / (1 - xy), guarded only where x and y are both exactly 1.  Where one is 1 and
  the other within rounding of 1 both the numerator and the denominator are rounding errors:
  the "s-norm" gives 2, 0 or 1 + 2^-52 where it is 1 (measured: evalfis's fourth output,
  the aggregated set, holds 2 and 1.0000000000000002), and the maximum-based defuzzifiers
  (som, lom, mom) and the centroid follow that noise.  fuzzyc's hamacher sum is the same
  formula, whose noise depends on the last bits of its inputs (exp, powers), so the two pick
  different ties.  Claimed where every disagreeing row's Mamdani fold, recomputed as the
  toolkit folds (`_hamacher_noise`), meets such a step: one argument 1 and the value not 1,
  the other argument within 1e-9 of 1 or the defuzzifier one of the maximum.
"""
from __future__ import annotations

import numpy as np

from fuzzyc.formats import load_any
from fuzzyc.formats.tool_semantics import Chain, fired, octave_activations, octave_dsigmf

OCTAVE_EMPTY_SUGENO = "next_agg_output(1,_): out of bound 0"
EVIDENCE = " | evidence: "      # a bug's name, then this file's evidence (grouped on the name)


def input_terms(system) -> list[tuple[str, list[tuple[str, list[float]]]]]:
    """A spec System's inputs as (name, [(shape, params)])."""
    return [(v.name, [(t.shape, list(t.params)) for t in v.terms]) for v in system.inputs]


def fll_input_terms(text: str) -> list[tuple[str, list[tuple[str, list[float]]]]]:
    """The same read off an FLL file (a kept case)."""
    inputs, current = [], None
    for line in text.splitlines():
        words = line.split()
        if line.startswith("InputVariable:"):
            current = (words[1], [])
            inputs.append(current)
        elif not line.startswith(" "):
            current = None
        elif current is not None and words[:1] == ["term:"]:
            current[1].append((words[2], [float(w) for w in words[3:]]))
    return inputs


def fll_output_defaults(text: str) -> list[float]:
    """The outputs' `default:` values of an FLL file, in order (NaN where none)."""
    defaults = []
    for line in text.splitlines():
        if line.startswith("OutputVariable:"):
            defaults.append(float("nan"))
        elif line.strip().startswith("default:") and defaults:
            defaults[-1] = float(line.split(":", 1)[1])
    return defaults


def _semi_ellipse_nan(inputs, x_row: np.ndarray) -> str | None:
    """The first input at a SemiEllipse end where pyfuzzylite's formula gives NaN."""
    for i, (name, terms) in enumerate(inputs):
        v = float(x_row[i])
        for shape, params in terms:
            if shape != "SemiEllipse":
                continue
            s, e = min(params[:2]), max(params[:2])
            r = (e - s) / 2
            c = s + r
            with np.errstate(invalid="ignore"):
                if s <= v <= e and np.isnan(np.sqrt(r ** 2 - np.square(v - c)) / r):
                    return f"{name} = {v!r} at an end of SemiEllipse {s:g} {e:g}"
    return None


def semi_ellipse_nudged(inputs, x_row: np.ndarray) -> np.ndarray | None:
    """x_row with every input where pyfuzzylite's SemiEllipse formula is NaN (at a term's end)
    moved the fewest ulps (at most 8) toward the term's centre for the formula to be a number;
    None where no input is at such an end."""
    nudged, moved = np.array(x_row, dtype=float), False
    for i, (_, terms) in enumerate(inputs):
        for shape, params in terms:
            if shape != "SemiEllipse":
                continue
            s, e = min(params[:2]), max(params[:2])
            r, v = (e - s) / 2, nudged[i]
            c = s + r
            for _ in range(8):
                with np.errstate(invalid="ignore"):
                    if not (s <= v <= e and np.isnan(np.sqrt(r ** 2 - np.square(v - c)) / r)):
                        break
                v, moved = np.nextafter(v, c), True
            nudged[i] = v
    return nudged if moved else None


def explain_disagreement(tool_key: str, inputs, x: np.ndarray, ours: np.ndarray,
                         tool: np.ndarray, tolerance: np.ndarray, rows: np.ndarray,
                         defaults=None) -> str | None:
    """The tool bug that explains every disagreeing row (each output apart there is NaN in
    the tool only, or the output's numeric default, which the tool gives for a NaN, and the
    bug's evidence holds at the row), or None.  `inputs`: the file's inputs as (name,
    [(shape, params)]) (`input_terms`, `fll_input_terms`); `defaults`: the outputs' defaults
    in the columns' order (NaN: none)."""
    defaults = np.full(tool.shape[1], np.nan) if defaults is None else \
        np.asarray(defaults, dtype=float)
    if tool_key != "pyfuzzylite-fll" or not len(rows):
        return None
    evidence = []
    for r in rows:
        with np.errstate(invalid="ignore"):
            apart = ~((np.abs(ours[r] - tool[r]) <= tolerance)
                      | (np.isnan(ours[r]) & np.isnan(tool[r])))
        nan_only_there = (np.isnan(tool[r]) | (tool[r] == defaults)) & ~np.isnan(ours[r])
        where = _semi_ellipse_nan(inputs, x[r]) if np.all(nan_only_there[apart]) else None
        if where is None:
            return None
        evidence.append(where)
    return ("pyfuzzylite 8 bug: SemiEllipse membership NaN at its end (sqrt of a negative "
            f"r^2 - (x - c)^2 by rounding){EVIDENCE}{len(rows)} row(s), e.g. {evidence[0]}; "
            "the other rows agree")


def octave_silent_rows(path, x: np.ndarray) -> np.ndarray | None:
    """The rows where a Sugeno output of the file fires nothing as the toolkit computes its
    activations (its clipped dsigmf: 0, not |difference|), or None where that cannot be said
    (not a single Sugeno block)."""
    try:
        blocks = Chain(load_any(path)).blocks
    except Exception:   # noqa: BLE001 -- no evidence, no claim
        return None
    if len(blocks) != 1:
        return None
    rb = octave_dsigmf(blocks[0])
    if rb.inference.defuzzifier.name not in ("WEIGHTED_AVERAGE", "WEIGHTED_SUM",
                                             "CENTER_OF_AREA"):
        return None
    return np.flatnonzero((~fired(rb, x, octave_activations)).any(axis=1))


def _empty_sugeno(silent: np.ndarray, n: int) -> str:
    return ("Octave toolkit bug: evalfis fails where no rule fires for a Sugeno output "
            f"(defuzzify_output_sugeno.m indexes the empty aggregate){EVIDENCE}"
            f"{len(silent)} of {n} rows fire nothing, e.g. row {int(silent[0])}")


def explain_error(tool_key: str, message: str, path, x: np.ndarray) -> str | None:
    """The tool bug behind a tool error, with its evidence, or None."""
    if tool_key != "octave-fis" or OCTAVE_EMPTY_SUGENO not in message:
        return None
    silent = octave_silent_rows(path, x)
    return _empty_sugeno(silent, len(x)) if silent is not None and len(silent) else None


def explain_failed_rows(tool_key: str, message: str, path, x: np.ndarray,
                        failed: np.ndarray) -> str | None:
    """The tool bug behind the rows a tool failed on one by one (it evaluated the others),
    claimed only where the failed rows are exactly the rows its evidence names."""
    if tool_key != "octave-fis" or OCTAVE_EMPTY_SUGENO not in message:
        return None
    silent = octave_silent_rows(path, x)
    if silent is None or set(silent.tolist()) != set(failed.tolist()):
        return None
    return _empty_sugeno(silent, len(x))


HAMACHER_NEAR_ONE = 1e-9      # |1 - v| below this (v != 1): the fold's step is rounding noise


def _hamacher_noise(rb, x_row: np.ndarray, o: int) -> str | None:
    """Where the toolkit's hamacher_sum fold of output o's rule sets at x_row meets one
    argument exactly 1 and the other within HAMACHER_NEAR_ONE of 1 (not 1): `u = ...`."""
    from fuzzyc.engine.membership import memberships
    from fuzzyc.engine.norms import implied
    from fuzzyc.formats.fuzzylite_compat import octave_linspace
    from fuzzyc.formats.octave_hedges import octave_mamdani_hedges
    from fuzzyc.formats.tool_semantics import octave_dsigmf
    from fuzzyc.semantics.model import Aggregation, Defuzzifier
    rb = octave_mamdani_hedges(octave_dsigmf(rb))
    inf = rb.inference_of(o)
    if inf.aggregation != Aggregation.HAMACHER_SUM:
        return None
    by_maximum = inf.defuzzifier in (Defuzzifier.MEAN_OF_MAXIMUM, Defuzzifier.SMALLEST_OF_MAXIMUM,
                                     Defuzzifier.LARGEST_OF_MAXIMUM)
    var = rb.outputs[o]
    u = octave_linspace(var.lo, var.hi, 101)
    act = octave_activations(rb, x_row[None])[0]
    total = np.zeros_like(u)
    for r in range(rb.n_rules):        # evalfis's column per rule, 0 where it does not fire
        t = rb.consequents[r, o]
        y = np.zeros_like(u) if t < 0 or act[r] == 0 else \
            implied(np.array(act[r]), memberships(var, u)[:, t], inf.implication)
        # one argument exactly 1: the value is 1, computed (1 - v) / (1 - v) with each side
        # rounded its own way; noise of an ulp decides which samples tie at the maximum (som,
        # lom, mom), noise of any size where v rounds near 1
        one = (total == 1.0) != (y == 1.0)
        other = np.where(total == 1.0, y, total)
        with np.errstate(invalid="ignore", divide="ignore"):
            step = (total + y - 2 * total * y) / (1 - total * y)
        noisy = one & (step != 1.0) & ((np.abs(1.0 - other) < HAMACHER_NEAR_ONE) | by_maximum)
        if noisy.any():
            k = int(np.flatnonzero(noisy)[0])
            return (f"{var.name}: rule {r + 1} at u = {float(u[k])!r} folds {float(y[k])!r} "
                    f"into {float(total[k])!r}: {float(step[k])!r}")
        total = np.where((total == 1.0) & (y == 1.0), 1.0, step)
    return None


def explain_octave_disagreement(path, x: np.ndarray, ours: np.ndarray, tool: np.ndarray,
                                tolerance: np.ndarray, rows: np.ndarray) -> str | None:
    """The Octave toolkit bug (hamacher_sum.m's rounding noise) behind every disagreeing row,
    with its evidence at each, or None."""
    try:
        blocks = Chain(load_any(path)).blocks
    except Exception:   # noqa: BLE001 -- no evidence, no claim
        return None
    if len(blocks) != 1 or not len(rows):
        return None
    rb = blocks[0]
    evidence = []
    for r in rows:
        with np.errstate(invalid="ignore"):
            apart = np.flatnonzero(~((np.abs(ours[r] - tool[r]) <= tolerance)
                                     | (np.isnan(ours[r]) & np.isnan(tool[r]))))
        found = [_hamacher_noise(rb, x[r], int(o)) for o in apart]
        if not apart.size or not all(found):
            return None
        evidence.append(found[0])
    return ("Octave toolkit bug: hamacher_sum.m's (x + y - 2xy) / (1 - xy) is rounding noise "
            "where one argument is 1 (2 or 1 + 2^-52 for 1; the maximum's ties follow the noise)"
            f"{EVIDENCE}"
            f"{len(rows)} row(s), e.g. {evidence[0]}")
