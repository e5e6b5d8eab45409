"""The public API's contract beyond the worked examples of docs/api.md (run as a doctest):
shapes, misnamed inputs, bad arguments, and agreement with the command line's answers."""
import importlib
import json
from pathlib import Path

import numpy as np
import pytest

import fuzzyc
from fuzzyc.cli import main

WEDM = fuzzyc.example("wedm_three_region.fz")


@pytest.fixture(scope="module")
def wedm():
    return fuzzyc.load(WEDM)


def test_public_names_are_exported_and_typed():
    assert set(fuzzyc.__all__) >= {"load", "parse", "save", "evaluate", "explain", "Controller",
                                   "compile_c", "compile_lut", "verify", "simulate", "examples",
                                   "example", "copy_examples", "VerifyReport", "Status"}
    for name in fuzzyc.__all__:
        assert getattr(fuzzyc, name) is not None
    assert callable(fuzzyc.verify)        # the function, not the verifier package
    importlib.import_module("fuzzyc.verifier.runner")   # importing internals does not shadow it
    assert callable(fuzzyc.verify)
    assert (Path(fuzzyc.__file__).parent / "py.typed").exists()


def test_evaluate_keeps_the_broadcast_shape(wedm):
    # a 2 x 3 grid of e2 against one e1 and ce2: every output has the grid's shape; the
    # centre row e2 = 0.25 is the hand-computed point of docs/api.md (du1 = 0.25)
    e2 = np.array([[0.0, 0.25, 0.5], [0.0, 0.25, 0.5]])
    out = fuzzyc.evaluate(wedm, {"e1": 1.0, "e2": e2, "ce2": 0.0})
    assert out["du1"].shape == (2, 3) and out["du1"][1, 1] == pytest.approx(0.25)
    assert out["du1"][0, 0] == pytest.approx(0.0)    # e2 = 0: only ZO-ZO-P fires: centre 0


def test_misnamed_and_missing_inputs_are_named(wedm):
    with pytest.raises(KeyError, match="unknown: e3; missing: ce2"):
        fuzzyc.evaluate(wedm, {"e1": 0.0, "e2": 0.0, "e3": 0.0})
    with pytest.raises(KeyError, match="missing: e2"):
        fuzzyc.explain(wedm, {"e1": 0.0, "ce2": 0.0})


def test_bad_arguments_raise_value_errors(wedm):
    with pytest.raises(ValueError, match="unknown format `yaml`"):
        fuzzyc.parse("", format="yaml")
    with pytest.raises(ValueError, match="numeric is one of"):
        fuzzyc.compile_c(wedm, "int8")
    with pytest.raises(KeyError, match="did you mean `wedm_corner.fz`"):
        fuzzyc.example("wedm_corners.fz")


def test_parse_reads_other_formats_and_save_round_trips(tmp_path, wedm):
    warnings = fuzzyc.save(wedm, tmp_path / "wedm.fll")
    assert warnings     # the signal chain and the verify block do not fit in FLL
    again = fuzzyc.parse((tmp_path / "wedm.fll").read_text(), format="fll", name="wedm.fll")
    x = {"e1": np.linspace(-1, 1, 7), "e2": 0.3, "ce2": -0.2}
    np.testing.assert_allclose(fuzzyc.evaluate(again, x)["du1"],
                               fuzzyc.evaluate(wedm, x)["du1"], atol=1e-12)


def test_verify_report_is_what_the_command_reports(tmp_path):
    report = fuzzyc.verify(WEDM, only="consistent")
    assert [r.status for r in report.results] == [fuzzyc.Status.PROVED] and report.passed
    assert main(["verify", str(WEDM), "--only", "consistent", "--report", str(tmp_path)]) == 0
    written = json.loads((tmp_path / "verify.json").read_text())
    assert [p["name"] for p in written["properties"]] == [r.name for r in report.results]
    assert report.to_json()["properties"][0]["status"] == "proved"


def test_compile_lut_reports_the_error_the_command_prints(wedm, capsys, tmp_path):
    header = fuzzyc.compile_lut(wedm, resolution=9)
    main(["compile", str(WEDM), "--target", "lut", "--resolution", "9", "-o", str(tmp_path)])
    printed = capsys.readouterr().out
    assert f"lookup table max error du1: {header.max_error['du1']:.4g}" in printed
    assert (tmp_path / header.filename).read_text() == header.text
