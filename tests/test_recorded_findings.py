"""Findings quoted in the shipped files are what the command prints now.

Each test runs `fuzzyc verify`'s check (its defaults: 100 examples, seed 0; the suite
derandomizes hypothesis) and asserts that the numbers the rule file's note, docs/verification.md,
the README and the demo quote are the ones the run gives."""
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.language.parser import load
from fuzzyc.verifier import Options, Status, verify_model

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
VERIFICATION = " ".join((ROOT / "docs" / "verification.md").read_text(encoding="utf-8").split())


def _note(model, text):
    return next(n for n in model.notes if n.startswith(f"finding: {text} --"))


@pytest.fixture(scope="module")
def wedm():
    """wedm_three_region.fz, every property as `fuzzyc verify` runs it (one closed-loop batch
    of 100 loops for its three checks)."""
    model = load(ROOT / "rulebases" / "wedm_three_region.fz")
    return model, verify_model(model, Options())


def test_wedm_height_step_finding_is_the_run(wedm):
    model, results = wedm
    by = {r.prop.text: r for r in results}
    spark = by["always spark_freq < Yr1 + 4"]
    assert spark.status == Status.VIOLATED and spark.finding is not None
    assert "--seed 0 --max-examples 100" in spark.reproduce
    detail = spark.violation.detail
    assert detail == ("1 of 100 loops break it; shrunk case: plant.height=30, "
                      "plant.tension=800; step of plant.height to 46.6515 at t=244.379 s; "
                      "replayed alone: violated at t=245.92 s")
    note = _note(model, "always spark_freq < Yr1 + 4")
    assert "`fuzzyc verify --seed 0 --max-examples 100`: " + detail in note
    trace = spark.violation.trace
    step_at = trace["step"][1]
    # 245.92 - 244.379 = 1.54: "1.5 s after the step"
    assert round(trace["violated_at"] - step_at, 1) == 1.5 and "1.5 s after the step" in note
    # no wire breaks on the same loops
    assert by["always ruptures < 1"].status == Status.HELD
    assert by["always ruptures < 1"].evidence[-1].cases == 100
    assert "`always ruptures < 1` holds on the same 100 loops" in note
    # docs/verification.md: the counts of the replayed case over Yr1 + 4 = 34 kHz
    t = np.asarray(trace["t"])
    f = np.asarray(trace["signals"]["spark_freq"])
    over = f >= 34.0
    first, last = t[over].min() - step_at, t[over].max() - step_at
    assert (over.sum(), round(first, 1), round(last, 1), round(f.max(), 1)) == \
        (133, 1.5, 12.7, 36.8)
    assert ("in 1 of the 100 loops `fuzzyc verify` draws at seed 0, a step from 30 to 47 mm at "
            "244 s puts 133 of the 40-ms counts over it between 1.5 and 12.7 s after the step "
            "(peak 36.8 kHz); no wire breaks") in VERIFICATION
    # the README's proof table: VIOLATED, the step 30 -> 46.6515 mm rounded
    assert "| WEDM finish: `always spark_freq < Yr1 + 4` | VIOLATED | height step 30 → 46.7 mm, " \
           "replayed |" in README


def test_the_demo_prints_the_verdict_the_command_gives(wedm, monkeypatch):
    """The demo verifies with the command's defaults, so it finds what `fuzzyc verify` finds
    (with 50 examples it printed HELD for the height step while the README said VIOLATED)."""
    from fuzzyc.demo import job
    model, results = wedm
    seen = []

    def replay(m, options):
        seen.append(options)
        return results

    monkeypatch.setattr(job, "verify_model", replay)
    lines = job.verify_lines(model)
    assert seen == [Options()]
    spark = next(i for i, line in enumerate(lines) if "always spark_freq < Yr1 + 4" in line)
    assert lines[spark].startswith("FINDING  wedm_three_region.fz::closed_loop wedm_finish")
    assert lines[spark + 1].strip().startswith("finding: always spark_freq < Yr1 + 4")


def test_edm_stuck_sensor_finding_is_the_run():
    model = load(ROOT / "rulebases" / "edm_sink_gap.fz")
    (r,) = verify_model(model, Options(only="always gap > 0"))
    assert r.status == Status.VIOLATED and r.finding is not None
    detail = r.violation.detail
    assert detail == ("15 of 100 loops break it; shrunk case: nominal plant; measured_voltage "
                      "sensor stuck from t=0 s for 0.3 s; replayed alone: violated at t=0.145 s")
    assert detail in _note(model, "always gap > 0")
    assert ("in 15 of the 100 loops `fuzzyc verify` draws at seed 0 (the shipped block, which "
            "also draws NaN outages; shrunk to a sensor stuck from t = 0, violated at 0.145 s"
            ) in VERIFICATION
