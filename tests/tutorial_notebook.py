"""docs/tutorial.ipynb, built from docs/tutorial.md: the same steps as a Jupyter notebook.

    python tests/tutorial_notebook.py        # writes docs/tutorial.ipynb

The page's prose becomes markdown cells; its rule file a `%%writefile` cell; each command line
a cell of its own (`!fuzzyc ...`, `%cd my-project`), whose stored output is the output the
page shows (trimmed the same way, with `...`). `pip install fuzzyc` is said in the first cell,
not run. tests/test_tutorial.py checks that the committed notebook is what this builds and, with
nbclient, executes it and compares every cell's output with the stored one.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "tutorial.md"
NOTEBOOK = ROOT / "docs" / "tutorial.ipynb"

INTRO = ("*This notebook is built from [tutorial.md](tutorial.md) by `tests/tutorial_notebook.py`; "
         "the outputs shown are the page's. Run it in an empty folder, in a Python environment "
         "where `pip install fuzzyc` (in a notebook: `%pip install fuzzyc`) has put the `fuzzyc` "
         "command on the PATH.*")


def segments(text: str) -> list[tuple[str, str, str]]:
    """(kind, info, body) in order: ("prose", "", text) or ("block", fence info, body)."""
    found, prose, lines, i = [], [], text.splitlines(), 0
    while i < len(lines):
        fence = re.match(r"^```(\w*)\s*$", lines[i])
        if not fence:
            prose.append(lines[i])
            i += 1
            continue
        if "\n".join(prose).strip():
            found.append(("prose", "", "\n".join(prose).strip("\n")))
        prose = []
        end = next(j for j in range(i + 1, len(lines)) if lines[j].startswith("```"))
        body = "\n".join(lines[i + 1:end]) + "\n" if end > i + 1 else ""
        found.append(("block", fence[1], body))
        i = end + 1
    if "\n".join(prose).strip():
        found.append(("prose", "", "\n".join(prose).strip("\n")))
    return found


def source_lines(text: str) -> list[str]:
    """A cell's text as the notebook format keeps it: lines with their newlines."""
    return text.splitlines(keepends=True)


def build(text: str) -> dict:
    """The notebook (nbformat 4.5, as a plain dict) of the tutorial's text."""
    cells: list[dict] = []

    def cell(kind: str, source: str, output: str | None = None) -> dict:
        new = {"cell_type": kind, "id": f"cell-{len(cells) + 1}", "metadata": {},
               "source": source_lines(source.rstrip("\n"))}
        if kind == "code":
            new["execution_count"] = None
            new["outputs"] = ([] if output is None else
                              [{"name": "stdout", "output_type": "stream",
                                "text": source_lines(output)}])
        cells.append(new)
        return new

    cell("markdown", INTRO)
    for kind, info, body in segments(text):
        if kind == "prose":
            cell("markdown", body)
        elif info == "fz":
            name = re.findall(r"`([\w.-]+\.fz)`", cells[-1]["source"][-1])[-1]
            cell("code", f"%%writefile {name}\n{body}", f"Writing {name}\n")
        elif info == "text":
            assert cells[-1]["cell_type"] == "code", "an output block with no command before it"
            cells[-1]["outputs"] = [{"name": "stdout", "output_type": "stream",
                                     "text": source_lines(body)}]
        else:
            for line in body.splitlines():
                if not line.strip() or line.startswith("pip install "):
                    continue
                if line.startswith("cd "):
                    cell("code", f"%{line}", f".../{line.split()[1]}\n")
                else:
                    cell("code", f"!{line}")
    return {"cells": cells,
            "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python",
                                        "name": "python3"},
                         "language_info": {"name": "python"}},
            "nbformat": 4, "nbformat_minor": 5}


def dumps(notebook: dict) -> str:
    return json.dumps(notebook, indent=1, ensure_ascii=False, sort_keys=True) + "\n"


if __name__ == "__main__":
    NOTEBOOK.write_text(dumps(build(TUTORIAL.read_text(encoding="utf-8"))), encoding="utf-8")
    print(f"wrote {NOTEBOOK.relative_to(ROOT)}")
