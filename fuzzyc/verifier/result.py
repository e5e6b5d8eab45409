"""What a check says about a property: how strong the answer is, and the evidence.

PROVED    decided exactly (on the rule tables, or per grid cell in closed form)
HELD      no violation in N searched cases (a dense grid, hypothesis examples, closed loops)
VIOLATED  a counterexample: table cells, an input point or a shrunk closed-loop trace
UNDECIDED no method applies (said why in `detail`)
A VIOLATED property that the rule file records as a finding (a `note "finding: <property>..."`)
is reported as a known finding: expected, not a CI failure.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from ..model import Property


class Status(str, Enum):
    PROVED = "proved"
    HELD = "held"
    VIOLATED = "violated"
    UNDECIDED = "undecided"


@dataclass
class Evidence:
    """One method's answer about one property."""
    method: str                     # "table", "proof", "grid", "hypothesis", "closed-loop"
    status: Status
    detail: str = ""
    cases: int = 0                  # points / examples / loops examined (search methods)
    cells: list[str] = field(default_factory=list)      # rule-table places that break it
    point: dict[str, float] | None = None               # an input point that breaks it
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
        s = self.status
        if s == Status.VIOLATED:
            return "violated (known finding)" if self.finding else "violated"
        if s == Status.PROVED:
            methods = "+".join(e.method for e in self.evidence if e.status == Status.PROVED)
            return f"proved ({methods})"
        if s == Status.HELD:
            cases = sum(e.cases for e in self.evidence if e.status == Status.HELD)
            return f"held on {cases} cases"
        return "undecided"
