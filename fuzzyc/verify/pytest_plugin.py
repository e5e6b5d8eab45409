"""pytest collects each property of each .fz file as a test item (activated by
rulebases/conftest.py). Proved / held pass; a violation fails, unless the file records it as a
finding (`note "finding: <property text> ..."`): then it is an expected failure (xfail).
Findings on the tables and proofs are strict (the xfail must fail); closed-loop findings come
from a search that a smaller suite-sized search may miss, so they are not strict."""
from __future__ import annotations

from dataclasses import replace

import pytest

from ..model import Property
from .result import Status
from .runner import Options, finding_for, verify_model

# Fast settings for the test suite; `fuzzyc verify` runs the full search.
SUITE_OPTIONS = dict(max_examples=25, grid_budget=8000, seed=0, shrink_rounds=1)


class PropertyFile(pytest.File):
    def collect(self):
        from ..parser import load
        model = load(self.path)
        self.loop_results: dict[int, dict] = {}
        for prop in model.properties:
            if prop.kind == "closed_loop":
                head = prop.text.split("{")[0].strip()
                for check in prop.args["checks"]:
                    yield PropertyItem.from_parent(self, name=f"{head} :: {check.text}",
                                                   model=model, prop=check, loop=prop)
            else:
                yield PropertyItem.from_parent(self, name=prop.text or prop.kind, model=model,
                                               prop=prop, loop=None)

    def results_of_loop(self, model, loop: Property) -> dict:
        """One batched run per closed loop serves all of its checks."""
        if id(loop) not in self.loop_results:
            results = verify_model(replace(model, properties=[loop]), Options(**SUITE_OPTIONS))
            self.loop_results[id(loop)] = {id(r.prop): r for r in results}
        return self.loop_results[id(loop)]


class PropertyItem(pytest.Item):
    def __init__(self, *, model, prop: Property, loop: Property | None, **kwargs):
        super().__init__(**kwargs)
        self.model, self.prop, self.loop = model, prop, loop
        finding = finding_for(model, prop)
        if finding:
            self.add_marker(pytest.mark.xfail(reason=finding, strict=loop is None,
                                              raises=RecordedFinding))

    def runtest(self):
        from .report import format_result
        if self.loop is None:
            results = verify_model(replace(self.model, properties=[self.prop]),
                                   Options(**SUITE_OPTIONS))
            result = results[0]
        else:
            result = self.parent.results_of_loop(self.model, self.loop)[id(self.prop)]
        if result.is_failure:
            raise PropertyFailure(format_result(result))
        if result.status == Status.VIOLATED:
            raise RecordedFinding(format_result(result))

    def repr_failure(self, excinfo):
        if isinstance(excinfo.value, (PropertyFailure, RecordedFinding)):
            return str(excinfo.value)
        return super().repr_failure(excinfo)

    def reportinfo(self):
        line = self.prop.loc.line - 1 if self.prop.loc else 0
        return self.path, line, f"{self.path.name}: {self.prop.text}"


class PropertyFailure(Exception):
    """A violation nobody recorded: a real failure even on an item marked xfail."""


class RecordedFinding(Exception):
    """The violation the file's `note "finding: ..."` records: the expected failure."""


def collect_fz(file_path, parent):
    if file_path.suffix == ".fz":
        return PropertyFile.from_parent(parent, path=file_path)
    return None
