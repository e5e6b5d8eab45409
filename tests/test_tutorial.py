"""docs/tutorial.md runs as written, in order, in one folder, as a user types it after
`pip install fuzzyc`: its rule file is written from the tutorial's own `fz` block, its commands
run one after the other (each step builds on the files of the steps before), and every output
the tutorial shows is what the command prints.

The page's blocks, in order:

- a block fenced `fz`: a file, written under the name in backticks on the line before the block
  (``Save this as `my_pi.fz`:``);
- a block fenced with nothing: commands, one a line; `cd my-project` moves the session into
  the folder `fuzzyc examples my-project` made; `pip install fuzzyc` is not run (the suite
  runs against the installed package); a comment `# exits N` gives the exit status (else 0);
- a block fenced `text`: what the command before it printed (standard output and error, as a
  terminal shows them). Each line must be the next line printed, except after a line `...`,
  which stands for any number of lines left out; `...` inside a line stands for any text (a
  folder of the user's). Lines left out at the end are marked by a last `...` too.

So the page and this test cannot drift: a changed output, a step that stops working or a
trimmed output without its `...` fails here, naming the tutorial's line.

docs/tutorial.ipynb is the page as a notebook (tests/tutorial_notebook.py builds it): the
committed file must be what the page gives, and with nbclient, nbformat and ipykernel (the
`test` extra) it is executed in a fresh folder, each cell's output checked by the same rules.
"""
from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from conftest import ROOT

TUTORIAL = ROOT / "docs" / "tutorial.md"
PROJECT = "my-project"
TIMEOUT = 300
EXIT = re.compile(r"\s#\s*exits (\d+)\b.*$")


@dataclass
class Block:
    kind: str          # "file", "commands" or "output"
    line: int          # the tutorial's line of the block's first content line
    text: str
    name: str = ""     # a file's name


def blocks(text: str) -> list[Block]:
    """The tutorial's fenced blocks, in order."""
    found, lines = [], text.splitlines()
    i = 0
    while i < len(lines):
        fence = re.match(r"^```(\w*)\s*$", lines[i])
        if not fence:
            i += 1
            continue
        end = next(j for j in range(i + 1, len(lines)) if lines[j].startswith("```"))
        body = "\n".join(lines[i + 1:end]) + "\n" if end > i + 1 else ""
        info = fence[1]
        if info == "fz":
            before = next(lines[j] for j in range(i - 1, -1, -1) if lines[j].strip())
            names = re.findall(r"`([\w.-]+\.fz)`", before)
            assert names, f"docs/tutorial.md:{i + 1}: name the file in backticks on the line before"
            found.append(Block("file", i + 2, body, names[-1]))
        elif info == "text":
            found.append(Block("output", i + 2, body))
        else:
            assert info == "", f"docs/tutorial.md:{i + 1}: unknown block kind {info!r}"
            found.append(Block("commands", i + 2, body))
        i = end + 1
    return found


BLOCKS = blocks(TUTORIAL.read_text(encoding="utf-8"))


def commands() -> list[tuple[int, str, int]]:
    """(line, command, expected exit status) of every command line of the tutorial."""
    found = []
    for block in BLOCKS:
        if block.kind == "commands":
            for offset, line in enumerate(block.text.splitlines()):
                if line.strip():
                    status = EXIT.search(" " + line)
                    command = re.sub(r"(^|\s)#\s.*$", "", line).strip()
                    found.append((block.line + offset, command, int(status[1]) if status else 0))
    return found


def argv(command: str) -> list[str]:
    """`fuzzyc ...` as this interpreter's installed package (`python -m fuzzyc`)."""
    words = shlex.split(command)
    assert words[0] == "fuzzyc", command
    return [sys.executable, "-m", "fuzzyc", *words[1:]]


def env() -> dict[str, str]:
    """This environment without the running pytest's variables; unbuffered, so that standard
    output and error interleave as on a terminal."""
    keep = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
    keep.update(MPLBACKEND="Agg", PYTHONUNBUFFERED="1")
    return keep


def line_matches(shown: str, printed: str) -> bool:
    if "..." not in shown:
        return shown == printed
    pattern = ".*".join(re.escape(part) for part in shown.split("..."))
    return re.fullmatch(pattern, printed) is not None


def mismatch(shown: str, printed: str) -> str | None:
    """None when the printed text holds the shown lines as the tutorial's rules say, else
    what differs."""
    want = [line.rstrip() for line in shown.splitlines()]
    got = [line.rstrip() for line in printed.splitlines()]
    at, skipping = 0, False
    for line in want:
        if line == "...":
            skipping = True
            continue
        if skipping:
            while at < len(got) and not line_matches(line, got[at]):
                at += 1
        if at >= len(got):
            return f"shown line {line!r} is not printed (after the lines before it)"
        if not line_matches(line, got[at]):
            return f"shown line {line!r} is not the next line printed, {got[at]!r}"
        at, skipping = at + 1, False
    if at < len(got) and not skipping:
        return f"printed lines not shown and no `...` at the end: {got[at:at + 3]!r}"
    return None


def test_tutorial_runs_as_written(tmp_path):
    home = tmp_path / "home"
    home.mkdir()
    cwd, last = home, None
    statuses = {line: status for line, _, status in commands()}
    for block in BLOCKS:
        where = f"docs/tutorial.md:{block.line}"
        if block.kind == "file":
            (cwd / block.name).write_text(block.text, encoding="utf-8")
            continue
        if block.kind == "output":
            assert last is not None, f"{where}: an output block with no command before it"
            command, done = last
            problem = mismatch(block.text, done.stdout)
            assert problem is None, f"{where}: `{command}`: {problem}\n--- printed:\n{done.stdout}"
            last = None
            continue
        for offset, line in enumerate(block.text.splitlines()):
            command = re.sub(r"(^|\s)#\s.*$", "", line).strip()
            if not command:
                continue
            where = f"docs/tutorial.md:{block.line + offset}"
            if command == "pip install fuzzyc":
                last = None
                continue
            if command.startswith("cd "):
                assert command == f"cd {PROJECT}", where
                cwd = cwd / PROJECT
                assert cwd.is_dir(), where
                last = None
                continue
            done = subprocess.run(argv(command), cwd=cwd, env=env(), stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=TIMEOUT)
            assert "Traceback" not in done.stdout, f"{where}: `{command}`\n{done.stdout}"
            assert done.returncode == statuses[block.line + offset], \
                f"{where}: `{command}` exited {done.returncode}\n{done.stdout}"
            last = (command, done)


def test_every_output_follows_a_command_and_is_not_empty():
    previous = None
    for block in BLOCKS:
        if block.kind == "output":
            assert previous == "commands", f"docs/tutorial.md:{block.line}: output after {previous}"
            assert block.text.strip(), f"docs/tutorial.md:{block.line}: an empty output block"
        previous = block.kind


def test_tutorial_covers_the_first_hour():
    """Issue 30's steps: write, check, rule viewer and surface, closed loop against the
    baseline, properties (proved, held, broken), C in the loop, FIS, tune."""
    run = [command for _, command, _ in commands()]
    files = [block.name for block in BLOCKS if block.kind == "file"]
    assert files == ["my_pi.fz"]
    wanted = [r"^fuzzyc check my_pi\.fz$", r"^fuzzyc eval my_pi\.fz .*--plot ",
              r"^fuzzyc plot my_pi\.fz ", r"^fuzzyc simulate my_pi\.fz .*--compare",
              r"^fuzzyc verify my_pi\.fz .*--max-examples", r"^fuzzyc compile my_pi\.fz --target c",
              r"^fuzzyc simulate my_pi\.fz .*--backend c", r"^fuzzyc convert my_pi\.fz my_pi\.fis$",
              r"^fuzzyc tune my_pi\.fz --scenario fopdt_step .*--limit"]
    for pattern in wanted:
        assert any(re.search(pattern, command) for command in run), pattern
    assert [status for _, _, status in commands() if status] == [1]     # the broken property


def test_matching_rules():
    assert mismatch("a\n...\nc\n", "a\nb\nc\n") is None
    assert mismatch("a\nc\n", "a\nb\nc\n") is not None          # trimmed without `...`
    assert mismatch("a\n", "a\nb\n") is not None                # the end left out silently
    assert mismatch("a\n...\n", "a\nb\n") is None
    assert mismatch("x: .../p.fz\n", "x: /tmp/q/p.fz\n") is None
    assert mismatch("x = 1.5\n", "x = 1.50\n") is not None      # numbers as printed


# ---- the notebook: docs/tutorial.ipynb, built from the page by tests/tutorial_notebook.py

PROGRESS = re.compile(r"^simulating \[[# ]*\]")


def terminal_text(outputs: list) -> str:
    """What a terminal shows of a cell's stream outputs (`!` commands run on a pty): each line
    as its last carriage return left it, erase codes dropped, and without the progress bars
    `simulate` and `verify` draw on a terminal (the page leaves them out)."""
    raw = "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")
    shown = []
    for line in raw.replace("\r\n", "\n").split("\n"):
        line = re.sub(r"\x1b\[[0-9;]*[A-Za-z]", "", line.rstrip("\r").split("\r")[-1])
        if not PROGRESS.match(line):
            shown.append(line)
    return "\n".join(shown).strip("\n") + "\n"


def test_notebook_is_built_from_the_tutorial():
    from tutorial_notebook import NOTEBOOK, build, dumps
    assert NOTEBOOK.read_text(encoding="utf-8") == dumps(build(TUTORIAL.read_text(encoding="utf-8"))), \
        "docs/tutorial.ipynb is not what docs/tutorial.md gives: python tests/tutorial_notebook.py"


def test_terminal_text():
    progress = [{"output_type": "stream", "name": "stdout",
                 "text": "\r\x1b[K[1] a property\rsimulating [   ]   0.0%\rsimulating [###] 100.0%\r\n"},
                {"output_type": "stream", "name": "stdout", "text": "\r\x1b[KHELD  x\r\nnext\r\n"}]
    assert terminal_text(progress) == "HELD  x\nnext\n"


def test_notebook_runs_as_stored(tmp_path, monkeypatch):
    """docs/tutorial.ipynb executed with nbclient in a fresh folder: every code cell prints what
    the notebook stores (the page's outputs, trimmed the same way), with no error."""
    nbformat = pytest.importorskip("nbformat", reason="the notebook needs `fuzzyc[test]`")
    nbclient = pytest.importorskip("nbclient", reason="the notebook needs `fuzzyc[test]`")
    pytest.importorskip("ipykernel", reason="the notebook needs `fuzzyc[test]`")
    script = Path(sys.executable).parent / "fuzzyc"
    assert script.exists(), f"no console script beside {sys.executable}"
    # `!fuzzyc` finds this venv's console script, as it would in the user's environment
    monkeypatch.setenv("PATH", f"{script.parent}{os.pathsep}{os.environ.get('PATH', '')}")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    for name in [k for k in os.environ if k.startswith("PYTEST_")]:
        monkeypatch.delenv(name)
    notebook = nbformat.reads((ROOT / "docs" / "tutorial.ipynb").read_text(encoding="utf-8"),
                              as_version=4)
    nbformat.validate(notebook)
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    stored = ["".join(o.get("text", "") for o in cell.outputs) for cell in code]
    nbclient.NotebookClient(notebook, timeout=TIMEOUT, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    for cell, shown in zip(code, stored):
        first = cell.source.splitlines()[0]
        assert not [o for o in cell.outputs if o.output_type == "error"], (first, cell.outputs)
        problem = mismatch(shown, terminal_text(cell.outputs))
        assert problem is None, f"notebook cell `{first}`: {problem}\n--- printed:\n" \
                                f"{terminal_text(cell.outputs)}"
