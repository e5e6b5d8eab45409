"""Hold the corner plant's predictions against measured corner errors (the paper's Table 4).

Table 4 of seeds/001 (normal machining beside the corner controller, 8 rows x 5 angles) is kept
outside the project as a validation set. Whoever holds it writes it as a small CSV file and runs

    python -m fuzzyc.plants.corner_table --against table4.csv

which runs the closed loop (27 rules, plants/wedm_corner.py) at the file's rows and scores it
by the validation target of issue 15: at least 75 % of the controlled cells (30 of Table 4's
40) within +-25 % of the measurements, and the model's machining time at most +10 % in every
row. The exit status says whether the target is met (0) or not (1); a bad file gives
file:line:col and status 2.

The file: a header line naming the columns, then one line per row, numbers only; blank lines
and lines starting with # are skipped. Columns: thickness (mm), feed (mm^2/min), normal_30 ...
normal_150 and controlled_30 ... controlled_150 (um), in any order, each once.

Besides the score, the report prints per cell the measured ratio controlled / normal beside
the model's. With kerf-wide corner blocks the model's ratio is exactly the rules' keep = 1 -
y/100, so a measured ratio is the force cut that corner behaved as if it had: where the two
differ by the same amount at every feed, the mechanism is off; where they differ most at the
feeds whose outputs are smallest, the output singletons (ours, Fig. 12 being lost) are.

The report also prints, per cell, the force-linear floor: the least ratio controlled / normal
that any model allows in which the lag and the vibration follow the sparking force (eq. 1 and
eq. 3 are linear in the load q, and the load follows the removal rate: keep = 1 - y/100 of
normal at the rules' commanded y), even with the edge over-cut E0 removed entirely:
    floor = keep s x / (E0 + s x),   s x the force part of Table 2's fit (plants/wedm_corner.py).
A measured ratio below the floor cannot come from the physics of section 2 at our singletons:
it asks for larger reductions than they command (the lost Fig. 12, or the user's like) or a
mechanism that section 2 does not describe. A measured ratio above it leaves room for a law of
the edge over-cut under the raised off-time that the paper does not quantify.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fuzzyc.errors import Diagnostic, FuzzycError, read_source, source_lines
from fuzzyc.semantics.model import SourceLoc

from . import scenario as scenarios
from .wedm_corner import FIT, TABLE2_ANGLES, corner_error

ANGLES = tuple(int(a) for a in TABLE2_ANGLES)
COLUMNS = ("thickness", "feed", *(f"normal_{a}" for a in ANGLES),
           *(f"controlled_{a}" for a in ANGLES))
# the controller's input ranges (rulebases/wedm_corner.fz): a row outside them is refused
LIMITS = {"thickness": (0.0, 100.0), "feed": (0.0, 250.0)}
TOLERANCE = 0.25          # a cell agrees when the model is within +-25 % of the measurement
TARGET_SHARE = 0.75       # of the controlled cells: 30 of Table 4's 40
TIME_LIMIT = 0.10         # the model's machining time at most +10 % over normal machining


@dataclass(frozen=True)
class Measured:
    conditions: np.ndarray    # (N, 2) thickness mm, feed mm^2/min
    normal: np.ndarray        # (N, 5) um, per Table 2 angle
    controlled: np.ndarray    # (N, 5) um


def _fields(line: str) -> list[tuple[int, str]]:
    """(1-based column, text) of each comma-separated field, surrounding blanks stripped."""
    out, start = [], 0
    for piece in line.split(","):
        lead = len(piece) - len(piece.lstrip())
        out.append((start + lead + 1, piece.strip()))
        start += len(piece) + 1
    return out


def read_measured(path: str | Path) -> Measured:
    """The measured table from `path`; FuzzycError (file:line:col) for every mistake found."""
    text = read_source(path)
    lines = source_lines(text)
    problems: list[Diagnostic] = []

    def fail(line_no: int, col: int, message: str) -> None:
        problems.append(Diagnostic(SourceLoc(str(path), line_no, col), message,
                                   lines[line_no - 1]))

    numbered = [(i + 1, line) for i, line in enumerate(lines)
                if line.strip() and not line.lstrip().startswith("#")]
    if not numbered:
        raise FuzzycError([Diagnostic(SourceLoc(str(path), 1, 1),
                                      "no header line: name the columns " + ", ".join(COLUMNS))])
    head_no, head = numbered[0]
    index: dict[str, int] = {}
    for at, (col, name) in enumerate(_fields(head)):
        if name not in COLUMNS:
            fail(head_no, col, f"unknown column {name!r}: known: " + ", ".join(COLUMNS))
        elif name in index:
            fail(head_no, col, f"column {name!r} named twice; name each column once")
        else:
            index[name] = at
    missing = [name for name in COLUMNS if name not in index]
    if missing and not problems:
        fail(head_no, 1, "missing column(s) " + ", ".join(missing))
    if problems:
        raise FuzzycError(problems)

    rows, seen = [], {}
    for line_no, line in numbered[1:]:
        fields = _fields(line)
        if len(fields) != len(COLUMNS):
            fail(line_no, 1, f"{len(fields)} fields, the header names {len(COLUMNS)}")
            continue
        values = {}
        for name, at in index.items():
            col, word = fields[at]
            value = _number(word)
            low, high = LIMITS.get(name, (0.0, math.inf))
            if value is None:
                fail(line_no, col, f"{name}: {word!r} is not a finite number")
            elif not low < value <= high:
                fail(line_no, col, f"{name}: {word} is outside ({low:g}, {high:g}]"
                     + (" (the controller's input range)" if name in LIMITS else
                        " (a corner error in um, above 0)"))
            values[name] = value
        if any(v is None for v in values.values()):
            continue
        key = (values["thickness"], values["feed"])
        if key in seen:
            fail(line_no, 1, f"the row {key[0]:g} mm, {key[1]:g} mm^2/min is already on line "
                             f"{seen[key]}")
            continue
        seen[key] = line_no
        rows.append([values[name] for name in COLUMNS])
    if not rows and not problems:
        fail(head_no, 1, "no rows under the header")
    if problems:
        raise FuzzycError(problems)
    table = np.array(rows, float)
    return Measured(table[:, :2], table[:, 2:7], table[:, 7:12])


def _number(word: str) -> float | None:
    try:
        value = float(word)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def commanded_reduction(conditions: np.ndarray, like: float = 1.0, model=None) -> np.ndarray:
    """The reduction y * like (%) that the corner_path loop's controller (the 27 rules) commands
    at each Table 2 angle of each row (thickness mm, feed mm^2/min), its inputs steady: (N, 5).
    (Its low-pass starts at its input, so the first sample is already the steady value.)
    model: another corner controller (a tuned one), with its own `like` (`like` is ignored)."""
    import fuzzyc
    if model is None:
        model = fuzzyc.load(scenarios.load("corner_path").rulebase_path())
        model.params["like"].value = float(like)
    conditions = np.asarray(conditions, float)
    rows, cols = len(conditions), len(ANGLES)
    controller = fuzzyc.Controller(model, batch=rows * cols)
    out = controller.step({"feed": np.repeat(conditions[:, 1], cols),
                           "thickness": np.repeat(conditions[:, 0], cols),
                           "angle": np.tile(np.array(ANGLES, float), rows)})
    return np.asarray(out["reduction"], float).reshape(rows, cols)


def force_linear_floor(conditions: np.ndarray, reduction: np.ndarray) -> np.ndarray:
    """keep s x / (E0 + s x) per cell (module docstring): the least ratio controlled / normal
    of any model whose lag and vibration follow the force, the edge over-cut removed."""
    conditions = np.asarray(conditions, float)
    normal = corner_error(FIT, conditions[:, 1:2], conditions[:, 0:1], TABLE2_ANGLES)
    keep = 1.0 - np.clip(np.asarray(reduction, float), 0.0, 100.0) / 100.0
    return keep * (normal - FIT.edge) / normal


@dataclass(frozen=True)
class Score:
    controlled_within: np.ndarray   # (N, 5) bool
    normal_within: np.ndarray       # (N, 5) bool
    time_ratio: np.ndarray          # (N,) controlled / normal machining time, the model's
    floor: np.ndarray               # (N, 5) the force-linear floor of the ratio at the rules'
                                    # commands (force_linear_floor)
    below_floor: np.ndarray         # (N, 5) bool: measured ratio under it

    @property
    def met(self) -> bool:
        share = self.controlled_within.mean()
        return bool(share >= TARGET_SHARE and np.all(self.time_ratio <= 1 + TIME_LIMIT))


def within(model: np.ndarray, measured: np.ndarray, tolerance: float = TOLERANCE) -> np.ndarray:
    """Cells where the model is within +-tolerance of the measurement (relative to it)."""
    return np.abs(model / measured - 1.0) <= tolerance + 1e-12


def score(measured: Measured, predicted: dict[str, np.ndarray],
          reduction: np.ndarray) -> Score:
    """reduction: (N, 5) % commanded at the measured rows (`commanded_reduction`)."""
    floor = force_linear_floor(measured.conditions, reduction)
    return Score(within(predicted["controlled"], measured.controlled),
                 within(predicted["normal"], measured.normal),
                 predicted["time"] / predicted["normal_time"], floor,
                 measured.controlled / measured.normal < floor)


def report(measured: Measured, predicted: dict[str, np.ndarray], result: Score) -> str:
    """Markdown: per cell measured and model (controlled, and ratio to normal), then the score."""
    head = " | ".join(f"{a}° measured / model" for a in ANGLES)
    lines = ["Controlled error, um (ratio controlled / normal), `*` outside +-25 %:", "",
             f"| h mm | feed mm²/min | {head} | model time |",
             "|---" * (3 + len(ANGLES)) + "|"]
    for i, (h, f) in enumerate(measured.conditions):
        cells = []
        for j in range(len(ANGLES)):
            m_c, p_c = measured.controlled[i, j], predicted["controlled"][i, j]
            m_r, p_r = m_c / measured.normal[i, j], p_c / predicted["normal"][i, j]
            mark = "" if result.controlled_within[i, j] else " *"
            cells.append(f"{m_c:.1f} ({m_r:.2f}) / {p_c:.1f} ({p_r:.2f}){mark}")
        lines.append(f"| {h:g} | {f:g} | " + " | ".join(cells)
                     + f" | {result.time_ratio[i] - 1:+.1%} |")
    n_c, n_n = result.controlled_within.sum(), result.normal_within.sum()
    cells = result.controlled_within.size
    need = math.ceil(TARGET_SHARE * cells)
    slowest = float(result.time_ratio.max()) - 1
    lines += ["",
              f"controlled cells within +-25 %: {n_c} of {cells} (target {need})",
              f"normal machining cells within +-25 %: {n_n} of {cells}",
              f"model machining time: at most {slowest:+.1%} (target +10.0 %)",
              "mean ratio controlled / normal: measured "
              f"{np.mean(measured.controlled / measured.normal):.2f}, model "
              f"{np.mean(predicted['controlled'] / predicted['normal']):.2f}",
              "target " + ("met" if result.met else "NOT met"), ""]
    lines += floor_table(measured, result)
    return "\n".join(lines) + "\n"


def floor_table(measured: Measured, result: Score) -> list[str]:
    """Markdown lines: per cell the measured ratio beside the force-linear floor, `!` under it,
    and how many cells are under it."""
    head = " | ".join(f"{a}° measured / floor" for a in ANGLES)
    lines = ["Measured ratio controlled / normal beside the force-linear floor at the rules' "
             "commands (`!` under it: out of reach of lag and vibration that follow the force, "
             "even with the edge over-cut removed):", "",
             f"| h mm | feed mm²/min | {head} |", "|---" * (2 + len(ANGLES)) + "|"]
    ratio = measured.controlled / measured.normal
    for i, (h, f) in enumerate(measured.conditions):
        cells = [f"{ratio[i, j]:.2f} / {result.floor[i, j]:.2f}"
                 + (" !" if result.below_floor[i, j] else "") for j in range(len(ANGLES))]
        lines.append(f"| {h:g} | {f:g} | " + " | ".join(cells) + " |")
    lines += ["", f"measured under the force-linear floor: {int(result.below_floor.sum())} of "
                  f"{result.below_floor.size} cells"]
    return lines
