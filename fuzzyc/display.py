"""How the API's results show themselves: a short `repr` for the terminal and an HTML table
(`_repr_html_`) for Jupyter, for the model, the verify report and a simulation.

The dataclasses' own reprs dump every array (thousands of characters); these say what a
reader wants first: names, ranges and units, counts, verdicts. Every user text (names, units,
rule text) is HTML-escaped: a rule file is data, and a name may hold `<script>`.

>>> from fuzzyc.language.parser import parse
>>> model = parse('''controller c { input x : degC in [0, 10]
...   terms x : lo = lshoulder(2, 8), hi = rshoulder(2, 8)
...   var y in [0, 1]
...   terms y : singletons off = 0 on = 1
...   rule if x is lo then y is on
...   rule if x is hi then y is off
...   output u : W in [0, 100] = 100 * y }''', "c.fz")
>>> print(model_text(model))
Model c (c.fz): 1 rule block, 2 rules, 0 properties
  inputs:  x in [0, 10] degC
  rules:   x (2 terms) -> y (2 terms), 2 rules
  outputs: u in [0, 100] W
"""
from __future__ import annotations

from collections.abc import Iterable
from html import escape
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .semantics.model import Model, RuleBase
    from .verifier.report import VerifyReport

MAX_HTML_RULES = 200     # a 1,000-rule table is a scroll bar, not an overview
MAX_LINES = 8            # metrics and failures listed in a repr


def plural(n: int, word: str, words: str = "") -> str:
    """`1 rule`, `2 rules`, `1 property`, `0 properties` (words: an irregular plural)."""
    return f"{n} {word if n == 1 else words or word + 's'}"


_plural = plural


def _range(lo: float, hi: float, unit: str | None) -> str:
    return f"in [{lo:g}, {hi:g}]" + (f" {unit}" if unit else "")


def _rules(model: Model) -> int:
    return sum(rb.n_rules for rb in model.blocks)


def _block_line(rb: RuleBase) -> str:
    def side(variables) -> str:
        return ", ".join(f"{v.name} ({_plural(v.n_terms, 'term')})" for v in variables)
    return f"{side(rb.inputs)} -> {side(rb.outputs)}, {_plural(rb.n_rules, 'rule')}"


# -- the model ------------------------------------------------------------------------------

def model_text(model: Model) -> str:
    """A few lines: the name, the raw inputs and outputs with ranges and units, per rule block
    its variables' term counts and its rule count."""
    # the file's name, not its folder: a repr does not depend on where the file lies
    source = f" ({Path(model.source_path).name})" if model.source_path else ""
    lines = [f"Model {model.name}{source}: {_plural(len(model.blocks), 'rule block')}, "
             f"{_plural(_rules(model), 'rule')}, "
             f"{_plural(len(model.properties), 'property', 'properties')}"]
    if model.signals:
        lines.append("  inputs:  " + ", ".join(f"{s.name} {_range(s.lo, s.hi, s.unit)}"
                                               for s in model.signals))
    lines += [f"  rules:   {_block_line(rb)}" for rb in model.blocks]
    if model.outputs:
        lines.append("  outputs: " + ", ".join(f"{o.name} {_range(o.lo, o.hi, o.unit)}"
                                               for o in model.outputs))
    return "\n".join(lines)


def _table(header: Iterable[str], rows: Iterable[Iterable[Any]]) -> str:
    """An HTML table; every cell escaped."""
    head = "".join(f"<th>{escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{escape(str(c))}</td>" for c in row) + "</tr>"
                   for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _variable_rows(model: Model):
    for s in model.signals:
        yield "raw input", s.name, f"[{s.lo:g}, {s.hi:g}]", s.unit or "-", ""
    for rb in model.blocks:
        for role, variables in (("rule-base input", rb.inputs), ("rule-base output", rb.outputs)):
            for v in variables:
                yield role, v.name, f"[{v.lo:g}, {v.hi:g}]", v.unit or "-", " ".join(v.names)
    for o in model.outputs:
        yield "output", o.name, f"[{o.lo:g}, {o.hi:g}]", o.unit or "-", ""


def _rule_rows(rb: RuleBase):
    for r in range(min(rb.n_rules, MAX_HTML_RULES)):
        yield r + 1, rb.describe_rule(r), f"{float(rb.weights[r]):g}"


def model_html(model: Model) -> str:
    """The variables and terms, the rule table of each block and the properties, as HTML."""
    parts = [f"<p><b>{escape(model.name)}</b> {escape(model.title)}</p>",
             _table(["role", "name", "range", "unit", "terms"], _variable_rows(model))]
    for rb in model.blocks:
        more = (f" (the first {MAX_HTML_RULES} of {rb.n_rules})"
                if rb.n_rules > MAX_HTML_RULES else "")
        parts.append(f"<p>rules of {escape(rb.name)}{escape(more)}</p>")
        parts.append(_table(["#", "rule", "weight"], _rule_rows(rb)))
    if model.properties:
        parts.append(_table(["property"], ([p.text or p.kind] for p in model.properties)))
    return "".join(parts)


# -- the verify report ----------------------------------------------------------------------

def report_text(report: VerifyReport) -> str:
    """The verdict counts (as `fuzzyc verify`'s last line) and the failures, one a line."""
    from .verifier.report import format_text
    tail = format_text(report.results).rsplit("\n", 1)[-1]
    verdict = "passed" if report.passed else f"{_plural(len(report.failures), 'failure')}"
    lines = [f"VerifyReport: {tail}; {verdict}"]
    lines += [f"  {r.status.value.upper()} {r.name} [{r.summary()}]"
              for r in report.failures[:MAX_LINES]]
    if len(report.failures) > MAX_LINES:
        lines.append(f"  ... and {len(report.failures) - MAX_LINES} more")
    return "\n".join(lines)


def report_html(report: VerifyReport) -> str:
    """One row per property: its name, verdict (a recorded finding says so) and summary."""
    def verdict(r) -> str:
        return "finding" if r.status.value == "violated" and r.finding else r.status.value
    head = report_text(report).split("\n", 1)[0]
    return (f"<p>{escape(head)}</p>"
            + _table(["property", "verdict", "how"],
                     ([r.name, verdict(r), r.summary()] for r in report.results)))


# -- a simulation ---------------------------------------------------------------------------

def _number(value: Any) -> str:
    return f"{float(value):.4g}"


def _metric_rows(metrics: dict[str, dict[str, Any]]):
    for label, m in metrics.items():
        yield label, _number(m["mean"]), _number(m["min"]), _number(m["max"]), m.get("unit", "")


def simulation_text(sim: Any) -> str:
    """The scenario, the run's length, period and batch, the signals and the metrics (mean,
    and min to max over the batch)."""
    trace = sim.trace
    end = float(trace.time[-1]) if len(trace.time) else 0.0
    who = trace.meta.get("controller", "")
    lines = [f"Simulation {sim.scenario.name}" + (f" ({who})" if who else "")
             + f": {_plural(len(trace.time), 'sample')} to t = {end:g} s, period "
               f"{trace.period:g} s, batch {trace.batch}",
             f"  signals: {', '.join(trace.signals)}"]
    rows = list(_metric_rows(sim.metrics))
    for label, mean, lo, hi, unit in rows[:MAX_LINES]:
        spread = "" if lo == hi else f" ({lo} to {hi})"
        lines.append(f"  {label} = {mean}{spread}" + (f" {unit}" if unit else ""))
    if len(rows) > MAX_LINES:
        lines.append(f"  ... and {len(rows) - MAX_LINES} more metrics (sim.metrics)")
    return "\n".join(lines)


def simulation_html(sim: Any) -> str:
    head = simulation_text(sim).split("\n", 1)[0]
    return (f"<p>{escape(head)}</p>"
            + _table(["metric", "mean", "min", "max", "unit"], _metric_rows(sim.metrics)))


# -- a learning run -------------------------------------------------------------------------

def learning_text(learning: Any) -> str:
    """The model, the scenario, the cycles and the performance index from first to last."""
    pi = learning.pi
    return (f"Learning {learning.model.name} on {learning.scenario}: "
            f"{_plural(len(pi), 'cycle')}, performance index {pi[0]:.4g} -> {pi[-1]:.4g}; "
            f"`{learning.table}` table learned")
