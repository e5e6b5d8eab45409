"""The README's front page shows only what works: its commands run, its tour is the shipped
file, its error message is the one `fuzzyc check` prints, its links and reproduce commands
point at things that exist."""
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def blocks() -> list[str]:
    return re.findall(r"^```[a-z]*\n(.*?)^```", README, flags=re.S | re.M)


def block_after(phrase: str) -> str:
    start = README.index(phrase)
    return next(b for b in blocks() if README.index(b) > start)


def normalized(line: str) -> str:
    return " ".join(line.split("#", 1)[0].split())


def fuzzyc(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "fuzzyc", *args], cwd=cwd, text=True,
                          capture_output=True, timeout=600)


def test_front_page_is_short():
    # about 150 lines of prose and commands, plus the six tables it carries (rule bases, CLI,
    # closed loop, and the corner, conformance and proof tables issues 14, 15 and 17 ask for)
    tables = sum(1 for line in README.splitlines() if line.startswith("|"))
    assert len(README.splitlines()) - tables <= 140


def test_tour_is_an_excerpt_of_the_shipped_rule_base():
    shipped = {normalized(l) for l in (ROOT / "rulebases/wedm_three_region.fz").read_text()
               .splitlines()}
    tour = [normalized(l) for l in block_after("## A tour").splitlines()]
    missing = [l for l in tour if l and not l.startswith("...") and l not in shipped]
    assert missing == []


def test_check_message_is_what_check_prints(tmp_path):
    # the README's mistake: PM typed for PS in the first cell row of the first table
    source = (ROOT / "rulebases/wedm_three_region.fz").read_text()
    (tmp_path / "wedm.fz").write_text(source.replace("PB PB PB PS PS", "PB PM PB PS PS", 1))
    shown = block_after("`fuzzyc check wedm.fz` says").strip().splitlines()
    result = fuzzyc(["check", "wedm.fz"], tmp_path)
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == shown


QUICK_START = [shlex.split(line, comments=True)[1:] for line in block_after("Then call `.venv/bin/fuzzyc`")
               .splitlines() if line.startswith(".venv/bin/fuzzyc ")]


@pytest.mark.parametrize("args", QUICK_START, ids=[a[0] for a in QUICK_START])
def test_quick_start_command_runs(args, tmp_path):
    (tmp_path / "rulebases").symlink_to(ROOT / "rulebases")
    result = fuzzyc(args, tmp_path)
    assert result.returncode == 0, result.stderr
    if "-o" in args:
        assert any((tmp_path / args[args.index("-o") + 1]).iterdir())


def test_quick_start_shows_each_kind_of_command():
    assert [a[0] for a in QUICK_START] == ["eval", "compile", "simulate", "verify", "examples"]


def test_cli_table_lists_every_command(tmp_path):
    table = README[README.index("## The command line"):README.index("Options, exit codes")]
    listed = re.findall(r"^\| `fuzzyc (\w+)", table, flags=re.M)
    help_text = fuzzyc(["--help"], tmp_path).stdout
    commands = re.findall(r"^    ([a-z]+)  ", help_text, flags=re.M)
    assert len(commands) >= 9 and sorted(listed) == sorted(commands)


def test_links_point_at_files():
    for target in re.findall(r"\]\(([^)#]+)\)", README):
        assert (ROOT / target).exists(), target


def test_reproduce_commands_name_existing_things():
    makefile = (ROOT / "Makefile").read_text()
    inline = re.findall(r"`([^`\n]+)`", re.sub(r"^```.*?^```", "", README, flags=re.S | re.M))
    for line in [l for b in blocks() for l in b.splitlines()] + inline:
        try:
            words = shlex.split(line, comments=True)
        except ValueError:          # inline code that is not a command (an unmatched quote)
            continue
        if words[:1] == ["make"]:
            for target in words[1:]:
                assert re.search(rf"^{re.escape(target)}:", makefile, flags=re.M), target
        if len(words) > 1 and words[0].endswith("python") and words[1].endswith(".py"):
            assert (ROOT / words[1]).exists(), line
        if len(words) > 2 and words[0].endswith("python") and words[1] == "-m":
            module = words[2].replace("fuzzyc.plants", "plants").replace(".", "/")
            assert (ROOT / f"{module}.py").exists() or (ROOT / module).is_dir(), line
