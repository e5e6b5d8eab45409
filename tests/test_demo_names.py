"""`make demo` and `fuzzyc examples` tell the shipped rule bases apart (issue 30): every model
has its own name and title (two milling files once wrote one header, one set of plots and two
eval lines nobody could tell apart), every one has an eval line, the examples' titles stand in
one column, and a scenario's notes are printed only for the scenario's own rule base."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from fuzzyc.cli import main
from fuzzyc.cli.simulate import own_notes
from fuzzyc.demo.job import SAMPLES, eval_lines, shipped_rulebases
from fuzzyc.language.parser import load
from fuzzyc.plants.scenario import load as load_scenario

ROOT = Path(__file__).resolve().parents[1]
NOTE = "The fuzzy PI has the PI baseline's gains"     # fopdt_step's note begins so


@pytest.fixture(scope="module")
def models():
    return [load(path) for path in shipped_rulebases()]


def test_every_shipped_rule_base_has_its_own_name_and_title(models):
    names = [m.name for m in models]
    titles = [m.title for m in models]
    assert len(set(names)) == len(names) == 6, names
    assert len(set(titles)) == len(titles), titles
    # the model is named as its file, so out/c/NAME.h and out/plots/NAME_* follow the file
    assert all(m.name == Path(m.source_path).stem for m in models)


def test_the_demo_evaluates_every_rule_base_with_a_line_of_its_own(models):
    assert set(SAMPLES) == {m.name for m in models}
    lines = eval_lines(models)
    assert len(set(lines)) == len(lines) == len(models)
    by_name = {line.partition(":")[0]: line for line in lines}
    # fopdt_pi from its initial state: e = (r - y) / GE = (1 - 0.5) / 1 = 0.5 (Z 0.5, P 0.5),
    # ce = 0 (no change yet: Z 1); cells (Z, Z) = ZO = 0 and (P, Z) = PS = 0.5 fire 0.5 each:
    # du = (0.5 * 0 + 0.5 * 0.5) / (0.5 + 0.5) = 0.25; u = integrate(du * GU) = 0.025
    assert by_name["fopdt_pi"] == "fopdt_pi: y=0.5 -> du=0.25, u=0.025"
    # the untrained milling table is all 0; the learned one is not
    assert by_name["milling_neurofuzzy"].endswith("du=0, feed=0")
    assert "du=0," not in by_name["milling_neurofuzzy_learned"]


def test_the_two_milling_files_compile_to_two_headers(tmp_path, capsys):
    for name in ("milling_neurofuzzy", "milling_neurofuzzy_learned"):
        assert main(["compile", str(ROOT / "rulebases" / f"{name}.fz"), "--target", "c",
                     "-o", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.glob("*.h")) == [
        "milling_neurofuzzy.h", "milling_neurofuzzy_learned.h"]


def test_examples_titles_stand_in_one_column(capsys):
    assert main(["examples"]) == 0
    listed = [line for line in capsys.readouterr().out.splitlines() if line.startswith("  ")]
    starts = set()
    for line in listed:
        name, _, title = line[2:].partition(" ")
        if title.strip():
            starts.add(len(line) - len(title.lstrip()))
    assert len(starts) == 1, listed
    milling = [line for line in listed if "milling_neurofuzzy" in line and ".fz" in line]
    assert len(milling) == 2 and milling[1].endswith("learned weights"), milling


def test_a_scenarios_notes_belong_to_its_own_rule_base(tmp_path):
    own = load_scenario("fopdt_step")
    assert own_notes(own)[0].startswith(NOTE)
    # FILE naming the scenario's own rule base (another spelling of its path): still its own
    # (the scenario's own file is the installed package's copy, not the source tree's)
    path = own.rulebase_path()
    spelled = path.parent / ".." / path.parent.name / path.name
    same = load_scenario("fopdt_step", {"controller.rulebase": str(spelled)})
    assert own_notes(same) == own.notes
    # a copy of it is the user's file: the note says nothing about it
    mine = tmp_path / "my_pi.fz"
    shutil.copy(ROOT / "rulebases" / "fopdt_pi.fz", mine)
    assert own_notes(load_scenario("fopdt_step", {"controller.rulebase": str(mine)})) == []


def test_simulate_prints_the_note_only_for_the_scenarios_rule_base(tmp_path, capsys):
    mine = tmp_path / "my_pi.fz"
    shutil.copy(ROOT / "rulebases" / "fopdt_pi.fz", mine)
    common = ["--scenario", "fopdt_step"]
    assert main(["simulate", *common, "-o", str(tmp_path / "own")]) == 0
    assert f"note: {NOTE}" in capsys.readouterr().out
    assert main(["simulate", str(mine), *common, "-o", str(tmp_path / "mine")]) == 0
    out = capsys.readouterr().out
    assert "controller:" in out and NOTE not in out
    assert NOTE not in (tmp_path / "mine" / "summary.txt").read_text()


def test_fuzzyc_learn_names_the_learned_controller_apart():
    """The learned file `fuzzyc learn` writes is a controller of its own (NAME_learned, title
    ", learned weights"), once: learning a learned file again keeps the one suffix."""
    import numpy as np
    from fuzzyc.language.parser import parse
    from fuzzyc.learning import trained_text
    untrained = load(ROOT / "rulebases" / "milling_neurofuzzy.fz")
    weights = np.zeros(49)
    text = trained_text(untrained, weights, provenance="by hand, for the test")
    learned = parse(text)
    assert learned.name == "milling_neurofuzzy_learned"
    assert learned.title == untrained.title + ", learned weights"
    again = parse(trained_text(learned, weights, provenance="again"))
    assert (again.name, again.title) == (learned.name, learned.title)
