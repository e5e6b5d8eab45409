"""Every message the parser and builder give on the corpus of bad inputs (tests/bad_inputs/), as
one reviewed list (issue 30: "right line, what is wrong, what to write instead").

Each corpus file marks the line of each mistake with `# <- error`, and `# <- error (hint)` where
the message must say what to write ("write ...", "did you mean ...", "declare them with ...",
"written in backticks").
The test holds every file to: errors only on the marked lines and one on each (no follow-on
error, no stray "unexpected `}`"), file:line:col with the caret under the column, the hint where
marked, and the exact text of tests/bad_inputs/MESSAGES.txt, so a change of wording shows in
review.  After a deliberate change, regenerate the list and read its diff:

    FUZZYC_REGENERATE_MESSAGES=1 .venv/bin/python -m pytest -q tests/test_error_messages.py
    (or: .venv/bin/python tests/test_error_messages.py --regenerate)
"""
from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import parse

CORPUS = Path(__file__).parent / "bad_inputs"
MESSAGES = CORPUS / "MESSAGES.txt"
MARK = re.compile(r"#\s*<- error( \(hint\))?\s*$")
HINT = re.compile(r"write `|did you mean `|declare them with `|written in backticks")
REGENERATE = "FUZZYC_REGENERATE_MESSAGES"


def corpus() -> list[Path]:
    return sorted(CORPUS.glob("*.fz"))


def marked_lines(text: str) -> dict[int, bool]:
    """line -> whether its message must carry a hint."""
    marks = {}
    for number, line in enumerate(text.split("\n"), start=1):
        found = MARK.search(line)
        if found:
            marks[number] = found.group(1) is not None
    return marks


def diagnostics_of(path: Path) -> list:
    with pytest.raises(FuzzycError) as info:
        parse(path.read_text(), path.name)
    return info.value.diagnostics


def reviewed_list() -> str:
    """The messages of the whole corpus, file by file, as the CLI prints them."""
    parts = []
    for path in corpus():
        try:
            parse(path.read_text(), path.name)
            shown = "(no error)"
        except FuzzycError as exc:
            shown = "\n".join(d.format() for d in exc.diagnostics)
        parts.append(f"== {path.name}\n{shown}\n")
    return "\n".join(parts)


def test_the_corpus_is_there_and_marked():
    files = corpus()
    assert len(files) >= 30
    for path in files:
        assert marked_lines(path.read_text()), f"{path.name} marks no line"


@pytest.mark.parametrize("path", corpus(), ids=lambda p: p.stem)
def test_each_mistake_is_reported_at_its_line_with_its_fix(path):
    marks = marked_lines(path.read_text())
    found = diagnostics_of(path)
    assert sorted(d.loc.line for d in found) == sorted(marks), \
        "\n".join(d.format() for d in found)
    for diagnostic in found:
        loc = diagnostic.loc
        assert loc.file == path.name and loc.col >= 1
        shown = diagnostic.format()
        assert shown.startswith(f"{path.name}:{loc.line}:{loc.col}: error: ")
        assert shown.splitlines()[2].index("^") == 4 + loc.col - 1
        if marks[loc.line]:
            assert HINT.search(diagnostic.message), f"no hint: {shown}"


def test_the_reviewed_list_is_the_one_the_corpus_gives():
    current = reviewed_list()
    if os.environ.get(REGENERATE):
        MESSAGES.write_text(current)
    print(current)
    assert MESSAGES.read_text() == current, (
        f"the messages changed: review the difference and regenerate ({REGENERATE}=1)")


if __name__ == "__main__":
    if "--regenerate" in sys.argv:
        MESSAGES.write_text(reviewed_list())
    print(MESSAGES.read_text() if MESSAGES.exists() else reviewed_list())
