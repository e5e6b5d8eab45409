"""No command overwrites an input, follows a link to create a file elsewhere, or replaces an
existing file without --force (docs/cli.md, docs/security.md).

`fuzzyc convert c.fz c.fz` replaced the rule file with a lossy rewrite (exit 0), also through a
symbolic link; `fuzzyc examples DIR` created the target of a dangling link in DIR and died
with a traceback (exit 70) on a file named DIR/rulebases."""
import os
import shutil

import pytest

from fuzzyc.cli import main
from conftest import ROOT

RULES = ROOT / "rulebases"
LOSSY = RULES / "fopdt_pi.fz"      # as .fll: its params, verify properties, ... are left out


@pytest.fixture
def rule_file(tmp_path):
    path = tmp_path / "c.fz"
    shutil.copyfile(LOSSY, path)
    return path


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


@pytest.mark.parametrize("force", [[], ["--force"]])
def test_convert_refuses_to_write_over_its_input(rule_file, capsys, force):
    before = rule_file.read_bytes()
    code, _, err = _run(["convert", rule_file, rule_file, *force], capsys)
    assert code == 2
    assert f"{rule_file} is the input file {rule_file}" in err
    assert rule_file.read_bytes() == before
    # the same file by another name
    code, _, err = _run(["convert", rule_file, rule_file.parent / "." / "c.fz", *force], capsys)
    assert code == 2 and "is the input file" in err
    assert rule_file.read_bytes() == before


@pytest.mark.parametrize("force", [[], ["--force"]])
def test_convert_refuses_its_input_through_a_link(tmp_path, capsys, force):
    target = tmp_path / "x.fll"
    assert _run(["convert", LOSSY, target], capsys)[0] == 0
    before = target.read_bytes()
    link = tmp_path / "y.fll"
    link.symlink_to("x.fll")
    for source, output in ((link, target), (target, link)):    # y -> x either way round
        code, _, err = _run(["convert", source, output, *force], capsys)
        assert code == 2 and f"{output} is the input file {source}" in err
        assert target.read_bytes() == before and link.is_symlink()
    hard = tmp_path / "hard.fll"
    os.link(target, hard)
    code, _, err = _run(["convert", hard, target, *force], capsys)
    assert code == 2 and "is the input file" in err and target.read_bytes() == before


def test_convert_of_an_fcl_block_refuses_its_own_file(tmp_path, capsys):
    fcl = tmp_path / "c.fcl"
    assert _run(["convert", RULES / "wedm_corner.fz", fcl], capsys)[0] == 0
    before = fcl.read_bytes()
    block = fcl.read_text().split("FUNCTION_BLOCK ")[1].split()[0]
    code, _, err = _run(["convert", f"{fcl}::{block}", fcl, "--force"], capsys)
    assert code == 2 and "is the input file" in err and fcl.read_bytes() == before


def test_a_lossy_conversion_over_an_existing_file_needs_force(rule_file, tmp_path, capsys):
    other = tmp_path / "other.fll"
    other.write_bytes(b"# my own file\n")
    code, _, err = _run(["convert", rule_file, other], capsys)
    assert code == 2
    assert f"not overwriting {other}, which exists: give --force to replace it" in err
    assert "warning" not in err                        # refused before any work
    assert other.read_bytes() == b"# my own file\n"
    code, out, err = _run(["convert", rule_file, other, "--force"], capsys)
    assert code == 0 and f"wrote {other}" in out
    assert "warning: 7 verify properties" in err       # what was left out, said so
    assert other.read_text().startswith("Engine:")


def test_a_lossless_overwrite_needs_force_too(tmp_path, capsys):
    fll = tmp_path / "x.fll"
    assert _run(["convert", LOSSY, fll], capsys)[0] == 0
    fz = tmp_path / "x.fz"
    assert _run(["convert", fll, fz], capsys)[0] == 0
    written = fz.read_bytes()
    code, _, err = _run(["convert", fll, fz], capsys)
    assert code == 2 and "not overwriting" in err and fz.read_bytes() == written
    assert _run(["convert", fll, fz, "--force"], capsys)[0] == 0
    assert fz.read_bytes() == written


def test_convert_force_replaces_a_link_and_leaves_its_target(rule_file, tmp_path, capsys):
    # the atomic writer renames over the link itself: what it pointed at is left alone
    elsewhere = tmp_path / "elsewhere.fll"
    elsewhere.write_bytes(b"# not mine to change\n")
    link = tmp_path / "out.fll"
    link.symlink_to(elsewhere)
    code, _, err = _run(["convert", rule_file, link], capsys)
    assert code == 2 and "not overwriting" in err
    assert _run(["convert", rule_file, link, "--force"], capsys)[0] == 0
    assert not link.is_symlink() and link.read_text().startswith("Engine:")
    assert elsewhere.read_bytes() == b"# not mine to change\n"


def test_examples_do_not_follow_a_dangling_link(tmp_path, capsys):
    folder = tmp_path / "project"
    (folder / "rulebases").mkdir(parents=True)
    link = folder / "rulebases" / "fopdt_pi.fz"
    target = tmp_path / "created-elsewhere.fz"
    link.symlink_to(target)
    code, _, err = _run(["examples", folder], capsys)
    assert code == 2
    assert f"not overwriting the 1 example files already in {folder} (e.g. {link})" in err
    assert "--force" in err
    assert not os.path.lexists(target) and link.is_symlink()
    assert sorted(p.name for p in folder.rglob("*")) == ["fopdt_pi.fz", "rulebases"]
    # --force replaces the link by the file, and still creates nothing where it pointed
    code, out, _ = _run(["examples", folder, "--force"], capsys)
    assert code == 0 and f"copied 22 files into {folder}" in out
    assert not link.is_symlink() and link.read_bytes() == LOSSY.read_bytes()
    assert not os.path.lexists(target)


@pytest.mark.parametrize("force", [[], ["--force"]])
@pytest.mark.parametrize("kind", ["file", "dangling link"])
def test_examples_with_a_file_where_a_folder_goes(tmp_path, capsys, force, kind):
    folder = tmp_path / "project"
    folder.mkdir()
    in_the_way = folder / "rulebases"
    if kind == "file":
        in_the_way.write_bytes(b"mine\n")
    else:
        in_the_way.symlink_to(tmp_path / "nowhere")
    code, _, err = _run(["examples", folder, *force], capsys)
    assert code == 2           # was 70: a FileExistsError traceback
    assert f"cannot copy the examples into {in_the_way}: it is not a folder" in err
    assert os.listdir(folder) == ["rulebases"]          # nothing copied beside it
    if kind == "file":
        assert in_the_way.read_bytes() == b"mine\n"
    else:
        assert in_the_way.is_symlink() and not os.path.lexists(tmp_path / "nowhere")


def test_examples_overwrite_an_existing_file_only_with_force(tmp_path, capsys):
    folder = tmp_path / "project"
    assert _run(["examples", folder], capsys)[0] == 0
    mine = folder / "rulebases" / "fopdt_pi.fz"
    mine.write_bytes(b"my edits\n")
    code, _, err = _run(["examples", folder], capsys)
    assert code == 2 and "not overwriting the 22 example files" in err
    assert mine.read_bytes() == b"my edits\n"
    assert _run(["examples", folder, "--force"], capsys)[0] == 0
    assert mine.read_bytes() == LOSSY.read_bytes()
    # written atomically: no temporary file is left beside them
    assert not [p for p in folder.rglob(".*")]
