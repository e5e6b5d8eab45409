"""The pytest plugin (entry point `pytest11: fuzzyc`, installed with the package): with
`--fuzzyc-verify` on the command line or `fuzzyc_verify = true` in the pytest configuration,
pytest collects each property of each .fz file as a test item (docs/pytest-plugin.md).

Proved / held pass; a violation fails, unless the file records it as a finding
(`note "finding: <property text> ..."`): then it is an expected failure (xfail). Findings on
the tables and proofs are strict (the xfail must fail); closed-loop findings come from a search
that a smaller suite-sized search may miss, so they are not strict. Opt-in, because a project
that happens to hold .fz files would not expect pytest to start verifying them. The fuzzyc
modules load only when a .fz file is collected: the plugin costs nothing to other test runs."""
from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import pytest

if TYPE_CHECKING:
    from .semantics.model import Property

# Fast settings for the test suite; `fuzzyc verify` runs the full search.
SUITE_OPTIONS: dict[str, Any] = dict(max_examples=25, grid_budget=8000, seed=0, shrink_rounds=1)
OPTION, INI = "--fuzzyc-verify", "fuzzyc_verify"


def pytest_addoption(parser: pytest.Parser) -> None:
    help_text = "collect the properties in the verify blocks of .fz files as tests"
    parser.getgroup("fuzzyc").addoption(OPTION, action="store_true", help=help_text)
    parser.addini(INI, help_text + " (true/false)", type="bool", default=False)


def pytest_collect_file(file_path, parent):
    config = parent.config
    if file_path.suffix == ".fz" and (config.getoption(OPTION) or config.getini(INI)):
        return PropertyFile.from_parent(parent, path=file_path)
    return None


class PropertyFile(pytest.File):
    def collect(self):
        from .language.parser import load
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

    def repr_failure(self, excinfo):
        """A rule file with mistakes: its diagnostics (file:line:col), not a traceback."""
        from .errors import FuzzycError
        if isinstance(excinfo.value, FuzzycError):
            return str(excinfo.value)
        return super().repr_failure(excinfo)

    def results_of_loop(self, model, loop: Property) -> dict:
        """One batched run per closed loop serves all of its checks."""
        from .verifier.runner import Options, verify_model
        if id(loop) not in self.loop_results:
            results = verify_model(replace(model, properties=[loop]), Options(**SUITE_OPTIONS))
            self.loop_results[id(loop)] = {id(r.prop): r for r in results}
        return self.loop_results[id(loop)]


class PropertyItem(pytest.Item):
    def __init__(self, *, model, prop: Property, loop: Property | None, **kwargs):
        from .verifier.runner import finding_for
        super().__init__(**kwargs)
        self.model, self.prop, self.loop = model, prop, loop
        finding = finding_for(model, prop)
        if finding:
            self.add_marker(pytest.mark.xfail(reason=finding, strict=loop is None,
                                              raises=RecordedFinding))

    def runtest(self):
        from .verifier.report import format_result
        from .verifier.result import Status
        from .verifier.runner import Options, verify_model
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
