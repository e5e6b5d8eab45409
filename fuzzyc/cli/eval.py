"""`fuzzyc eval`: one evaluation with the rules that fired, or a whole CSV.

Without --core the values are the controller's raw inputs and one step of the whole signal
chain runs from its initial state (so delta() is 0 and integrators start from their `from`
value); with --core they are the rule base's own (scaled) inputs.

A CSV's rows are independent points by default, each evaluated from the initial state in one
batch; with --series they are successive samples of one controller (delta() and the
integrators carry over from row to row), as examples/c's program reads its input.
NAME=VALUE beside --csv holds an input the CSV lacks at that value on every row.
"""
from __future__ import annotations

import csv
import io
import json
import math
import sys

import numpy as np

from .common import RULE_FILE_HELP, add_semantics, check_output
from ..errors import Diagnostic, FuzzycError, read_source, source_lines
from ..csvtext import csv_line
from ..semantics.model import Model
from ..language.numbers import not_a_number, parse_number


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("eval", help="evaluate a controller at one point or over a CSV")
    p.add_argument("file", metavar="FILE", help=RULE_FILE_HELP)
    p.add_argument("values", nargs="*", metavar="NAME=VALUE",
                   help="every input's value; with --csv, an input the CSV lacks, held on "
                        "every row")
    p.add_argument("--core", action="store_true",
                   help="feed the rule base's scaled inputs directly (e.g. e1=0.5)")
    p.add_argument("--json", action="store_true", help="print {outputs, fired} as JSON")
    p.add_argument("--plot", metavar="OUT.png",
                   help="draw the rule viewer of this evaluation: per fired rule the input "
                        "terms and the cut consequent, per output the aggregate and the "
                        "defuzzified value")
    p.add_argument("--csv", metavar="IN.csv",
                   help="evaluate every row of a CSV; the rows are independent points, each "
                        "from the initial state, unless --series")
    p.add_argument("--series", action="store_true",
                   help="with --csv: the rows are successive samples of one controller "
                        "(delta() and integrators carry over), as examples/c reads them")
    add_semantics(p)
    p.set_defaults(run=run)


def input_names(model: Model, core: bool) -> list[str]:
    return [v.name for v in model.rulebase.inputs] if core else [s.name for s in model.signals]


def _fail(message: str) -> FuzzycError:
    return FuzzycError([Diagnostic(None, message)])


def parse_assignments(model: Model, pairs: list[str], core: bool,
                      complete: bool = True) -> dict[str, float]:
    """{input: value} from NAME=VALUE; complete: every input must have one."""
    names = input_names(model, core)
    values: dict[str, float] = {}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        if not sep:
            raise _fail(f"`{pair}` is not NAME=VALUE")
        if name not in names:
            raise _fail(f"`{name}` is not an input of {model.name}: known: "
                        f"{', '.join(names)}" + ("" if core else " (use --core for the rule "
                                                               "base's scaled inputs)"))
        value = parse_number(text)
        if value is None:
            raise _fail(f"{not_a_number(text)} (in `{pair}`)")
        values[name] = value
    missing = [n for n in names if n not in values]
    if missing and complete:
        raise _fail(f"missing input{'s' if len(missing) > 1 else ''}: {', '.join(missing)}; "
                    "give each as NAME=VALUE")
    return values


def warn_out_of_range(model: Model, values: dict[str, np.ndarray], core: bool,
                      semantics: str = "exact") -> None:
    from ..formats.tool_semantics import clamped_inputs
    ranges = ({v.name: (v.lo, v.hi) for v in model.rulebase.inputs} if core
              else {s.name: (s.lo, s.hi) for s in model.signals})
    clamped = clamped_inputs(model, semantics)
    for name, column in values.items():
        lo, hi = ranges[name]
        bad = np.count_nonzero((column < lo) | (column > hi))
        if bad:
            what = "clamped: the file's lock-range" if name in clamped else "not clamped"
            print(f"warning: {bad} value{'s' if bad > 1 else ''} of `{name}` outside its range "
                  f"[{lo:g}, {hi:g}] ({what})", file=sys.stderr)


def evaluate_batch(model: Model, columns: dict[str, np.ndarray], core: bool,
                   semantics: str = "exact") -> dict[str, np.ndarray]:
    """Every output for a batch of independent points (rule-base outputs, then the chain's)."""
    from ..api import Controller, evaluate
    if core and semantics == "exact":
        return evaluate(model, columns)
    if core:
        from ..formats.tool_semantics import ToolEngine, file_settings
        rb = model.rulebase
        x = np.column_stack([columns[v.name] for v in rb.inputs])
        y = ToolEngine(rb, semantics, file_settings(model)).evaluate_rows(x.T).T
        return {v.name: y[:, o] for o, v in enumerate(rb.outputs)}
    controller = Controller(model, batch=len(next(iter(columns.values()))), semantics=semantics)
    return _step(controller, columns)


def evaluate_series(model: Model, columns: dict[str, np.ndarray],
                    semantics: str = "exact") -> dict[str, np.ndarray]:
    """Every output of one controller stepped through the rows in order (the rule base's
    outputs, then the chain's), its state carried from row to row."""
    from ..api import Controller
    n = len(next(iter(columns.values())))
    if n == 0:
        return evaluate_batch(model, columns, core=False, semantics=semantics)
    controller = Controller(model, batch=1, semantics=semantics)
    rows = [_step(controller, {k: v[i:i + 1] for k, v in columns.items()}) for i in range(n)]
    return {name: np.concatenate([row[name] for row in rows]) for name in rows[0]}


def _step(controller, columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """One step: the rule base's outputs (copied: the controller reuses its arrays), then the
    chain's."""
    outputs = controller.step(columns)
    # every block's outputs (a model may chain several: found by the fuzzer)
    result = {v.name: np.array(controller.signals[v.name])
              for rb in controller.model.blocks for v in rb.outputs}
    result.update(outputs)
    return result


def run(args) -> int:
    from ..api import load
    from ..formats.tool_semantics import parse_semantics
    parse_semantics(args.semantics)
    model = load(args.file)
    if args.csv:
        if args.plot:
            raise _fail("--plot draws one evaluation; it does not go with --csv")
        return _run_csv(model, args)
    if args.series:
        raise _fail("--series reads the rows of --csv IN.csv as a time series; one point "
                    "has no series")
    values = parse_assignments(model, args.values, args.core)
    if args.plot:
        check_output(args.plot)
    columns = {k: np.array([v]) for k, v in values.items()}
    warn_out_of_range(model, columns, args.core, args.semantics)
    outputs = {k: float(v[0]) + 0.0 for k, v in     # + 0.0: -0.0 is 0 (no `-0` printed)
               evaluate_batch(model, columns, args.core, args.semantics).items()}
    fired, rb_inputs = _explain(model, columns, args.core)
    if args.plot:
        from ..atomic import save_figure
        from ..ruleview import draw_rule_view
        print(f"wrote {save_figure(draw_rule_view(model, rb_inputs), args.plot, dpi=110)}",
              file=sys.stderr)
    if args.json:
        # Strict JSON: a value that is not finite (the engine gives none) would be null.
        print(json.dumps(_finite_or_null({"outputs": outputs, "fired": fired}), indent=2,
                         allow_nan=False))
        return 0
    _print_table(model, rb_inputs, outputs, fired)
    return 0


def _explain(model: Model, columns, core: bool):
    """The rules that fired at the rule base's inputs, strongest first."""
    from ..api import Controller, explain
    if len(model.blocks) > 1 and not core:
        return _explain_blocks(model, columns)
    if core:
        point = {name: float(column[0]) for name, column in columns.items()}
    else:
        controller = Controller(model, batch=1)
        controller.step(columns)
        point = {v.name: float(controller.signals[v.name][0]) for v in model.rulebase.inputs}
    explanation = explain(model, point)
    fired = [{"rule": int(r) + 1, "activation": float(a), "text": text, "origin": origin}
             for r, a, text, origin in explanation.fired]
    fired.sort(key=lambda f: -f["activation"])
    return fired, explanation.inputs


def _explain_blocks(model: Model, columns):
    """Every block's fired rules at its inputs (a chained block's are earlier blocks'
    outputs), strongest first, each rule numbered within its block."""
    from ..api import Controller
    from ..engine.inference import explain
    controller = Controller(model, batch=1)
    controller.step(columns)
    fired, inputs = [], {}
    for rb in model.blocks:
        point = np.array([float(controller.signals[v.name][0]) for v in rb.inputs])
        explanation = explain(rb, point)
        inputs.update(explanation.inputs)
        fired += [{"block": rb.name, "rule": int(r) + 1, "activation": float(a),
                   "text": text, "origin": origin}
                  for r, a, text, origin in explanation.fired]
    fired.sort(key=lambda f: -f["activation"])
    return fired, inputs


def _print_table(model: Model, rb_inputs, outputs, fired) -> None:
    print(f"{model.name}: rule-base inputs " +
          ", ".join(f"{k} = {_short(v)}" for k, v in rb_inputs.items()))
    if not fired:
        print("  no rule fired: every output takes its declared default")
    else:
        print(f"  {'rule':>5}  {'act':>6}  rule (origin)")
        for f in fired:
            rule = f"{f['block']}:{f['rule']}" if "block" in f else f["rule"]
            print(f"  {rule:>5}  {f['activation']:6.3f}  {f['text']}   [{f['origin']}]")
    print("outputs: " + ", ".join(f"{k} = {_short(v)}" for k, v in outputs.items()))


def _run_csv(model: Model, args) -> int:
    if args.series and args.core:
        raise _fail("--series steps the signal chain; the rule base alone (--core) has no "
                    "state, so its rows are independent anyway: drop one of the two")
    names = input_names(model, args.core)
    held = parse_assignments(model, args.values, args.core, complete=False)
    rows = read_csv(args.csv)
    if not rows:
        raise _fail(f"{args.csv}:1:1: the file is empty; its first line must name the inputs")
    header = [h.strip() for h in rows[0]]
    twice = [n for n in held if n in header]
    if twice:
        raise _fail(f"{', '.join(twice)}: given both as NAME=VALUE and as a column of "
                    f"{args.csv}; NAME=VALUE is for an input the CSV lacks")
    missing = [n for n in names if n not in header and n not in held]
    if missing:
        raise _fail(f"{args.csv}:1:1: the header lacks {', '.join(missing)} "
                    f"(inputs of {model.name}: {', '.join(names)}; NAME=VALUE holds one "
                    f"at a value on every row)")
    columns = {n: np.full(len(rows) - 1, held[n]) if n in held else np.empty(len(rows) - 1)
               for n in names}
    for line_no, row in enumerate(rows[1:], start=2):
        for name in (n for n in names if n not in held):
            col = header.index(name)
            value = parse_number(row[col]) if col < len(row) else None
            if value is None:
                cell = row[col] if col < len(row) else ""
                raise _fail(f"{args.csv}:{line_no}:{col + 1}: {not_a_number(cell)} "
                            f"(column {name})")
            columns[name][line_no - 2] = value
    warn_out_of_range(model, columns, args.core, args.semantics)
    outputs = (evaluate_series(model, columns, args.semantics) if args.series
               else evaluate_batch(model, columns, args.core, args.semantics))
    lines = [csv_line(names + list(outputs))]
    for i in range(len(rows) - 1):
        lines.append(csv_line([_fmt(columns[n][i]) for n in names]
                              + [_fmt(v[i]) for v in outputs.values()]))
    sys.stdout.write("".join(lines))
    return 0


def read_csv(path: str) -> list[list[str]]:
    """The rows of a UTF-8 CSV file; FuzzycError with file:line:col for a byte that is not UTF-8
    or what the csv module refuses (a field over its 128 KiB limit)."""
    text = read_source(path)
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        return list(reader)
    except csv.Error as exc:
        line = reader.line_num
        if "field limit" not in str(exc):
            raise _fail(f"{path}:{line}:1: {exc}") from None
        # the field starts after the comma that begins the longest stretch of the line
        lines = source_lines(text)
        fields = lines[min(line, len(lines)) - 1].split(",")
        longest = max(range(len(fields)), key=lambda i: len(fields[i]))
        col = sum(len(f) + 1 for f in fields[:longest]) + 1
        raise _fail(f"{path}:{line}:{col}: a field longer than {csv.field_size_limit()} "
                    "characters: not a number") from None


def _finite_or_null(value):
    if isinstance(value, dict):
        return {k: _finite_or_null(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite_or_null(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _fmt(value: float) -> str:
    """A CSV cell: the shortest text that reads back as the value; -0.0 is written 0.0."""
    return repr(float(value) + 0.0) if math.isfinite(value) else str(value)


def _short(value: float) -> str:
    """A printed number, 6 significant digits; -0.0 (e.g. -delta(y) / GCE of a still y) is
    printed 0, not -0 (adding 0.0 turns -0.0 into 0.0 and changes no other value)."""
    return f"{float(value) + 0.0:.6g}"
