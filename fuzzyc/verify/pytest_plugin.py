"""pytest collects each property of each .fz file as a test item (activated by
rulebases/conftest.py). Proved / held pass; a violation fails, unless the file records it as a
finding (`note "finding: <property text> ..."`): then it is an expected failure (xfail)."""
from __future__ import annotations

import pytest

from ..model import Property
from .result import Status
from .runner import Options, finding_for, property_name, verify_model

# Fast settings for the test suite; `fuzzyc verify` runs the full search.
SUITE_OPTIONS = dict(max_examples=25, grid_budget=8000, seed=0)


class PropertyFile(pytest.File):
    def collect(self):
        from ..parser import load
        model = load(self.path)
        for prop in model.properties:
            if prop.kind == "closed_loop":
                for check in prop.args["checks"]:
                    yield PropertyItem.from_parent(self, name=property_name(model, check, prop)
                                                   .split("::", 1)[1], model=model,
                                                   prop=check, parent_prop=prop)
            else:
                yield PropertyItem.from_parent(self, name=prop.text or prop.kind, model=model,
                                               prop=prop, parent_prop=None)


class PropertyItem(pytest.Item):
    def __init__(self, *, model, prop: Property, parent_prop: Property | None, **kwargs):
        super().__init__(**kwargs)
        self.model, self.prop, self.parent_prop = model, prop, parent_prop
        finding = finding_for(model, prop)
        if finding:
            self.add_marker(pytest.mark.xfail(reason=finding, strict=True,
                                              raises=RecordedFinding))

    def runtest(self):
        from .report import format_result
        target = self.parent_prop or self.prop
        options = Options(**SUITE_OPTIONS)
        model = _only(self.model, target, self.prop)
        results = verify_model(model, options)
        if not results:
            raise PropertyFailure(f"{self.prop.text}: nothing was checked")
        for r in results:
            if r.is_failure:
                raise PropertyFailure(format_result(r))
            if r.status == Status.VIOLATED:
                raise RecordedFinding(format_result(r))

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


def _only(model, target: Property, check: Property):
    """The model with just this property (and, for a loop, just this check)."""
    from dataclasses import replace
    if target is check:
        return replace(model, properties=[target])
    loop = replace(target, args={**target.args, "checks": [check]})
    return replace(model, properties=[loop])


def collect_fz(file_path, parent):
    if file_path.suffix == ".fz":
        return PropertyFile.from_parent(parent, path=file_path)
    return None
