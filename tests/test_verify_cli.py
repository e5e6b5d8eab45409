"""`fuzzyc verify`: exit status, terminal report, JSON and JUnit XML."""
import json
import xml.etree.ElementTree as ET

from fuzzyc.cli import main

SERVO = open("rulebases/edm_sink_gap.fz").read()


def _run(capsys, *args):
    status = main(["verify", *args, "--max-examples", "5"])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_shipped_file_holds_with_findings_as_expected_failures(capsys, tmp_path):
    status, out, _ = _run(capsys, "rulebases/edm_sink_gap.fz", "--report", str(tmp_path))
    assert status == 0
    assert "PROVED   edm_sink_gap.fz::covers e, ce at least 0.5" in out
    assert "FINDING  edm_sink_gap.fz::monotone dv increasing in e" in out
    assert "8 properties: 6 proved, 0 held, 0 violated, 2 known findings, 0 undecided" in out
    report = json.loads((tmp_path / "verify.json").read_text())
    by_text = {p["text"]: p for p in report["properties"]}
    assert by_text["continuous dv"]["status"] == "proved"
    assert by_text["monotone dv increasing in ce"]["finding"].startswith("finding:")
    suite = ET.parse(tmp_path / "verify.junit.xml").getroot().find("testsuite")
    assert suite.get("tests") == "8" and suite.get("failures") == "0"
    assert suite.get("skipped") == "2"


def test_a_flipped_cell_exits_1_and_names_the_cell_and_the_command(capsys, tmp_path):
    # row e = NS of the table: NB NB NS ZO PS -> NB PB NS ZO PS (a cell flipped to PB)
    bad = SERVO.replace("    NB NB NS ZO PS\n", "    NB PB NS ZO PS\n", 1)
    assert bad != SERVO
    path = tmp_path / "servo.fz"
    path.write_text(bad)
    status, out, _ = _run(capsys, str(path), "--report", str(tmp_path / "r"))
    assert status == 1
    assert "VIOLATED servo.fz::continuous dv" in out
    assert "[table dv row e=NS, col ce=NS]" in out
    assert f"reproduce: fuzzyc verify {path} --only 'continuous dv'" in out
    suite = ET.parse(tmp_path / "r" / "verify.junit.xml").getroot().find("testsuite")
    failed = [c.get("name") for c in suite.iter("testcase") if c.find("failure") is not None]
    assert "continuous dv" in failed


def test_only_selects_properties(capsys):
    status, out, _ = _run(capsys, "rulebases/wedm_corner.fz", "--only", "complete")
    assert status == 0 and "1 properties: 1 proved" in out


def test_bad_input_exits_2_with_the_diagnostic(capsys, tmp_path):
    path = tmp_path / "bad.fz"
    path.write_text(SERVO.replace("continuous dv", "continuous nothere"))
    status, _, err = _run(capsys, str(path), "rulebases/wedm_corner.fz")
    assert status == 2
    assert "bad.fz:" in err and "nothere" in err
