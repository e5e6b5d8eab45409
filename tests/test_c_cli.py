"""`fuzzyc compile`: files written atomically where asked, the footprint printed (and within
the issue's targets for the WEDM controller), bad input reported as a diagnostic (exit 2)."""
from __future__ import annotations

import pathlib
import re

from fuzzyc.cli import main as cli_main

ROOT = pathlib.Path(__file__).resolve().parents[1]
WEDM = ROOT / "rulebases" / "wedm_three_region.fz"


def footprints(printed: str) -> dict[str, tuple[int, int]]:
    return {level: (int(code), int(stack)) for level, code, stack in re.findall(
        r"gcc (-O\w): (\d+) bytes code \+ constant data, (\d+) bytes stack", printed)}


def test_wedm_float_footprint_meets_the_targets(tmp_path, capsys):
    # Targets: at most 2 KiB code + constant data and 256 bytes of stack, at -Os (the usual
    # firmware setting) and at -O2 alike.
    assert cli_main(["compile", str(WEDM), "-o", str(tmp_path)]) == 0
    sizes = footprints(capsys.readouterr().out)
    assert set(sizes) == {"-O2", "-Os"}
    for code, stack in sizes.values():
        assert 0 < code <= 2048 and 0 < stack <= 256
    assert [p.name for p in tmp_path.iterdir()] == ["wedm_three_region.h"]   # no temp left


def test_fixed_point_header_names(tmp_path, capsys):
    for numeric in ("q15", "q31"):
        assert cli_main(["compile", str(WEDM), "--numeric", numeric, "-o", str(tmp_path)]) == 0
        # the derived bounds the header states are printed too (values: c_fixed's tests)
        printed = capsys.readouterr().out
        assert "derived worst case of the rule base: du1 " in printed
        assert re.search(r"derived worst case of the chain after 1 / 10,000 steps: feed "
                         r"[0-9.e-]+ / [0-9.e-]+, t_off ", printed)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["wedm_three_region_q15.h",
                                                          "wedm_three_region_q31.h"]


def test_bad_file_and_unsupported_choice_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.fz"
    bad.write_text("controller broken {\n  input x in [0, 1\n}\n")
    assert cli_main(["compile", str(bad), "-o", str(tmp_path)]) == 2
    # the corner controller with centroid: float C emits it, q15 does not
    corner = tmp_path / "corner.fz"
    corner.write_text((ROOT / "rulebases" / "wedm_corner.fz").read_text().replace(
        "defuzzify = center_of_area", "defuzzify = centroid"))
    assert cli_main(["compile", str(corner), "--numeric", "q15", "-o", str(tmp_path)]) == 2
    assert "`centroid` is not supported" in capsys.readouterr().err
    assert not list(tmp_path.glob("*.h"))
