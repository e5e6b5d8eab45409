"""What a check says about a property: how strong the answer is, and the evidence.

PROVED    decided by a sound proof of the property as stated, over its stated domain (on the
          rule tables for the table properties consistent/complete/continuous, per grid
          cell in closed form, by reachable sets)
HELD      no violation in N searched cases (a dense grid, hypothesis examples, closed loops)
VIOLATED  a counterexample: contradicting or missing table cells for the table properties;
          otherwise an evaluation (two input points where the output moves the wrong way, a
          point out of bounds, a shrunk closed-loop trace) that the report shows
UNDECIDED no method applies (said why in `detail`)
WARNING   (evidence only, never a verdict) an observation that decides nothing: a monotone
          property's rule table going against the direction, which no evaluation reproduced
A verdict never rests on weaker evidence than its name: a monotone table is a remark, not a
proof that the defuzzified output is monotone (max-min center of area dips inside cells).
A VIOLATED property that the rule file records as a finding (a `note "finding: <property>..."`)
is reported as a known finding: expected, not a CI failure.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from ..display import plural
from ..semantics.model import Property


class Status(str, Enum):
    PROVED = "proved"
    HELD = "held"
    VIOLATED = "violated"
    UNDECIDED = "undecided"
    WARNING = "warning"


@dataclass
class Evidence:
    """One method's answer about one property."""
    method: str                     # "table", "proof", "grid", "hypothesis", "closed-loop"
    status: Status
    detail: str = ""
    cases: int = 0                  # points / examples / loops examined (search methods)
    cells: list[str] = field(default_factory=list)      # rule-table places that break it
    point: dict[str, float] | None = None               # an input point that breaks it
    to_point: dict[str, float] | None = None            # monotone: where the output moved back
    trace: dict[str, Any] | None = None                 # a closed-loop counterexample


@dataclass
class Result:
    """The verdict on one property: the strongest evidence decides."""
    prop: Property
    name: str                       # "file.fz::<property text>", stable for reports and pytest
    evidence: list[Evidence]
    finding: str | None = None      # the note that records a known violation, if any
    reproduce: str = ""             # a command that reproduces the check
    seconds: float = 0.0

    @property
    def status(self) -> Status:
        statuses = [e.status for e in self.evidence]
        for s in (Status.VIOLATED, Status.PROVED, Status.HELD):
            if s in statuses:
                return s
        return Status.UNDECIDED

    @property
    def violation(self) -> Evidence | None:
        return next((e for e in self.evidence if e.status == Status.VIOLATED), None)

    @property
    def is_failure(self) -> bool:
        """A violation nobody recorded: this fails CI."""
        return self.status == Status.VIOLATED and self.finding is None

    def summary(self) -> str:
        """The verdict and the method that decided it (proof / grid N points / search N
        examples / N closed loops), and `table warning` when the tables disagree."""
        s = self.status
        warn = "; table warning" if any(e.status == Status.WARNING for e in self.evidence) \
            else ""
        if s == Status.VIOLATED:
            how = self.violation.method
            return (f"violated (known finding, {how})" if self.finding else
                    f"violated ({how})") + warn
        if s == Status.PROVED:
            methods = "+".join(e.method for e in self.evidence if e.status == Status.PROVED)
            return f"proved ({methods})" + warn
        if s == Status.HELD:
            return "held: " + ", ".join(_cases(e) for e in self.evidence
                                        if e.status == Status.HELD) + warn
        return "undecided" + warn


def _cases(e: Evidence) -> str:
    if e.method == "closed-loop":
        return plural(e.cases, "closed loop")
    unit = {"grid": "grid {} points", "hypothesis": "search {} examples"}.get(
        e.method, e.method + " {} cases")
    return unit.format(e.cases)
