"""`fuzzyc simulate --batch N`: trace.csv keeps the loops the plot draws (20) unless told, says
so when it keeps fewer than the batch, and `--csv-loops all` writes every loop."""
import pytest

from fuzzyc.cli import main


def loops_in_csv(out) -> int:
    header = (out / "trace.csv").read_text().splitlines()[0].split(",")
    return sum(name.startswith("spark_freq[") for name in header)


@pytest.mark.parametrize("batch,option,written,said", [
    (20, [], 20, False),
    (23, [], 20, True),
    (23, ["--csv-loops", "all"], 23, False),
    (23, ["--csv-loops", "5"], 5, True),
])
def test_csv_loops(tmp_path, capsys, batch, option, written, said):
    out = tmp_path / "run"
    assert main(["simulate", "--scenario", "wedm_finish", "--set", "duration=0.4",
                 "--batch", str(batch), *option, "-o", str(out)]) == 0
    assert loops_in_csv(out) == written
    note = f"trace.csv holds the first {written} of {batch} loops: --csv-loops all"
    assert (note in capsys.readouterr().out) == said


@pytest.mark.parametrize("value", ["0", "-3", "some"])
def test_bad_csv_loops_refused(tmp_path, capsys, value):
    with pytest.raises(SystemExit):
        main(["simulate", "--scenario", "wedm_finish", "--csv-loops", value,
              "-o", str(tmp_path)])
    assert "is not a positive number or `all`" in capsys.readouterr().err


@pytest.mark.parametrize("loops,recorded,note", [
    (20, 10_000, "the first 20 of 10000 loops: --csv-loops all writes every one"),
    (None, 10_000, ""),
    # a campaign in chunks (--workers) records the first 20 loops only
    (None, 20, "the first 20 of 10000 loops: a campaign in chunks records the first 20 only"),
    (5, 20, "the first 5 of 10000 loops: a campaign in chunks records the first 20 only"),
])
def test_csv_note_says_why(loops, recorded, note):
    from fuzzyc.cli.simulate import csv_note
    assert csv_note(10_000, loops, recorded) == (f" (trace.csv holds {note})" if note else "")
