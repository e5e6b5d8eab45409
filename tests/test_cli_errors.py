"""The command line on hostile input and broken surroundings (issue 13): exit 2 with a located
message and no traceback; unwritable outputs refused before any work; options anywhere;
--version; 70 and a request to report for what is a bug."""

import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import fuzzyc
from fuzzyc import atomic
from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from test_hostile_rule_files import BASE

ROOT = Path(__file__).resolve().parents[1]
RULES = ROOT / "rulebases"


@pytest.fixture
def base(tmp_path) -> str:
    path = tmp_path / "base.fz"
    path.write_text(BASE)
    return str(path)


def no_traceback(err: str) -> str:
    assert "Traceback" not in err, err
    return err


# ---------------------------------------------------------------- options anywhere, --version

def test_options_after_the_file(base, capsys):
    # e = 0.5 is P 0.5, ce = 1 is P 1: the rule fires min(0.5, 1) = 0.5. du's P (a ramp from 0
    # to 1) clipped at 0.5: area 0.5*0.5/2 + 0.5*0.5 = 0.375, moment
    # 0.5^3/3 + 0.5*(1 - 0.25)/2 = 0.0416667 + 0.1875 = 0.2291667, centroid 0.6111111.
    assert main(["eval", base, "--json", "e=0.5", "ce=1"]) == 0
    assert json.loads(capsys.readouterr().out)["outputs"]["du"] == pytest.approx(0.2291667 / 0.375)


def test_the_issues_core_case_reads_as_with_options_first(capsys):
    wedm = str(RULES / "wedm_three_region.fz")
    assert main(["eval", wedm, "--core", "--json", "e1=0.5", "e2=0", "ce2=0"]) == 0
    after = json.loads(capsys.readouterr().out)
    assert main(["eval", "--core", "--json", wedm, "e1=0.5", "e2=0", "ce2=0"]) == 0
    assert json.loads(capsys.readouterr().out) == after
    assert set(after["outputs"]) == {"du1", "du2"}


def test_version(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out == f"fuzzyc {fuzzyc.__version__}\n"
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert f'\nversion = "{fuzzyc.__version__}"\n' in pyproject


@pytest.mark.parametrize("argv, words", [
    # found by the fuzzer: --batch 0 was a ValueError in runtime.loop, --batch -1 one in numpy,
    # a negative seed one in numpy's generator
    (["simulate", "--scenario", "wedm_rough", "--batch", "0"], "--batch: must be at least 1"),
    (["simulate", "--scenario", "wedm_rough", "--batch", "-1"], "--batch: must be at least 1"),
    (["simulate", "--scenario", "wedm_rough", "--seed", "-5"], "--seed: must be at least 0"),
    (["verify", str(RULES / "wedm_three_region.fz"), "--max-examples", "0"],
     "--max-examples: must be at least 1"),
    (["verify", str(RULES / "wedm_three_region.fz"), "--seed", "-1"],
     "--seed: must be at least 0"),
    # --noise-sigmas nan gave a PROVED that stated "covered to nan sigma"
    (["verify", str(RULES / "fopdt_pi.fz"), "--prove", "--noise-sigmas", "nan"],
     "--noise-sigmas: must be a finite number, got nan"),
    (["verify", str(RULES / "fopdt_pi.fz"), "--prove", "--noise-sigmas=-1"],
     "--noise-sigmas: must be at least 0, got -1"),
    (["verify", str(RULES / "fopdt_pi.fz"), "--prove", "--prove-boxes", "0"],
     "--prove-boxes: must be at least 1, got 0"),
    # --eta nan trained the whole run, then failed on writing a NaN table
    (["learn", str(RULES / "milling_neurofuzzy.fz"), "--scenario", "milling_step", "-o", "x.fz",
      "--eta", "nan"], "--eta: must be a finite number, got nan"),
    (["learn", str(RULES / "milling_neurofuzzy.fz"), "--scenario", "milling_step", "-o", "x.fz",
      "--rho=-inf"], "--rho: must be a finite number, got -inf"),
])
def test_counts_and_seeds_out_of_bounds_are_usage_errors(argv, words, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    assert words in no_traceback(capsys.readouterr().err)


@pytest.mark.parametrize("address, words", [
    # found by the fuzzer: a ValueError from inside Dask's address parser
    ("#", "cannot reach the Dask scheduler at #: missing port number"),
    ("tcp://a:x", "cannot reach the Dask scheduler at tcp://a:x"),
    # Dask's ucx connector raises a TypeError when its package is missing: refused before
    ("ucx://a:1",
     "a scheduler address must be tcp://HOST:PORT or tls://HOST:PORT, not ucx://a:1"),
])
def test_a_scheduler_address_dask_cannot_use_is_a_clean_error(address, words, tmp_path, capsys):
    pytest.importorskip("distributed", reason="Dask is the optional extra fuzzyc[dask]")
    assert main(["simulate", "--scenario", "wedm_rough", "--scheduler", address,
                 "-o", str(tmp_path)]) == 2
    assert f"error: {words}" in no_traceback(capsys.readouterr().err)


NAMED_INPUTS = [
    ["check", "IN.fz"], ["convert", "IN.fz", "OUT/x.fll"], ["compile", "IN.fz", "-o", "OUT"],
    ["eval", "IN.fz", "x=1"], ["eval", "{base}", "--csv", "IN.csv"],
    # found by the fuzzer: simulate FILE made the name absolute first (pathlib: ValueError)
    ["simulate", "IN.fz", "--scenario", "wedm_finish", "-o", "OUT"],
    ["learn", "IN.fz", "--scenario", "milling_step", "-o", "OUT/x.fz"],
]


@pytest.mark.parametrize("argv", NAMED_INPUTS, ids=lambda argv: " ".join(argv[:3]))
def test_an_input_name_with_a_nul_cannot_be_read(argv, base, tmp_path, capsys):
    argv = [a.format(base=base).replace("IN", "a\0b").replace("OUT", str(tmp_path))
            for a in argv]
    assert main(argv) == 2
    assert "error: cannot read a\0b." in no_traceback(capsys.readouterr().err)


@pytest.mark.parametrize("argv", NAMED_INPUTS, ids=lambda argv: " ".join(argv[:3]))
def test_an_input_name_too_long_for_the_file_system_is_a_clean_error(argv, base, tmp_path,
                                                                      capsys):
    # found by the fuzzer: simulate's Path.exists() raised ENAMETOOLONG (exists() only
    # swallows "not found")
    argv = [a.format(base=base).replace("IN", "9" * 400).replace("OUT", str(tmp_path))
            for a in argv]
    assert main(argv) == 2
    assert "File name too long" in no_traceback(capsys.readouterr().err)


# ---------------------------------------------------------------- eval --csv

def test_a_latin1_csv_is_located(base, tmp_path, capsys):
    table = tmp_path / "in.csv"
    table.write_bytes("e,ce\n0.1,0\n0.5,caf\xe9\n".encode("latin-1"))
    assert main(["eval", base, "--csv", str(table)]) == 2
    err = no_traceback(capsys.readouterr().err)
    assert f"{table}:3:8: error: byte 0xe9 is not UTF-8" in err    # `0.5,caf` is 7 characters


def test_a_csv_field_over_128_kib_is_located(base, tmp_path, capsys):
    table = tmp_path / "in.csv"
    table.write_text("e,ce\n0.1,0\n0.2," + "1" * 200_000 + "\n")
    assert main(["eval", base, "--csv", str(table)]) == 2
    err = no_traceback(capsys.readouterr().err)
    assert f"{table}:3:5: a field longer than 131072 characters" in err   # after `0.2,`


def test_an_empty_csv_is_located(base, tmp_path, capsys):
    table = tmp_path / "in.csv"
    table.write_text("")
    assert main(["eval", base, "--csv", str(table)]) == 2
    err = no_traceback(capsys.readouterr().err)
    assert f"{table}:1:1: the file is empty" in err


# ---------------------------------------------------------------- unwritable outputs

def forbid(monkeypatch, target: str) -> None:
    """Make the long work of a command fail the test if it is reached."""
    def reached(*args, **kwargs):
        raise AssertionError(f"{target} ran before the output was checked")
    module, name = target.rsplit(".", 1)
    monkeypatch.setattr(module + "." + name, reached)


# (argv with OUT for the unwritable path, the work that must not start)
WRITERS = [
    (["compile", "{base}", "-o", "OUT"], "fuzzyc.backends.c.header.generate_header"),
    (["plot", "{base}", "-o", "OUT"], "fuzzyc.plotting.plot_model"),
    (["simulate", "--scenario", "wedm_finish", "-o", "OUT"], "fuzzyc.runtime.simulate.simulate"),
    (["verify", "{base}", "--report", "OUT"], "fuzzyc.verifier.verify_model"),
    (["convert", "{base}", "OUT/x.fll"], "fuzzyc.formats.save"),
    (["learn", str(RULES / "milling_neurofuzzy.fz"), "--scenario", "milling_step", "-o",
      "OUT/trained.fz"], "fuzzyc.learning.learn_scenario"),
    (["examples", "OUT"], "fuzzyc.api.copy_examples"),
]


@pytest.mark.parametrize("out,reason", [("/proc/x", "cannot create anything in /proc"),
                                        ("/dev/full/x", "/dev/full is not a folder")])
@pytest.mark.parametrize("argv,work", WRITERS, ids=[w[0][0] for w in WRITERS])
def test_an_unwritable_output_is_refused_before_the_work(argv, work, out, reason, base,
                                                         monkeypatch, capsys):
    if not Path(out).parent.exists():
        pytest.skip(f"{Path(out).parent} does not exist on this system")
    forbid(monkeypatch, work)
    argv = [a.format(base=base).replace("OUT", out) for a in argv]
    assert main(argv) == 2
    err = no_traceback(capsys.readouterr().err)
    assert f"error: cannot write to {out}" in err and reason in err, err


@pytest.mark.parametrize("argv,work", WRITERS, ids=[w[0][0] for w in WRITERS])
def test_an_output_name_with_a_nul_is_refused(argv, work, base, tmp_path, monkeypatch, capsys):
    # found by the fuzzer: `fuzzyc examples` with a NUL in DIR was a ValueError from mkdir
    forbid(monkeypatch, work)
    out = str(tmp_path / "a\0b")
    assert main([a.format(base=base).replace("OUT", out) for a in argv]) == 2
    assert "a file name cannot hold a NUL character" in no_traceback(capsys.readouterr().err)


def test_learn_with_an_unwritable_plot_does_not_train(tmp_path, monkeypatch, capsys):
    forbid(monkeypatch, "fuzzyc.learning.learn_scenario")
    assert main(["learn", str(RULES / "milling_neurofuzzy.fz"), "--scenario", "milling_step",
                 "-o", str(tmp_path / "trained.fz"), "--plot", "/proc/pi.png"]) == 2
    assert "cannot write to /proc/pi.png" in no_traceback(capsys.readouterr().err)


def test_output_onto_a_folder_or_a_device_is_refused(base, tmp_path, capsys):
    # convert replaces OUT atomically: over a device (/dev/null) it would replace the device
    assert main(["convert", base, str(tmp_path)]) == 2
    assert f"cannot write to {tmp_path}: it is a folder" in capsys.readouterr().err
    assert main(["convert", base, os.devnull]) == 2
    assert "it is not a regular file" in capsys.readouterr().err
    assert main(["compile", base, "-o", base]) == 2
    assert "it is a file, not a folder" in capsys.readouterr().err


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0,
                    reason="root writes into a read-only folder")
def test_a_read_only_folder_is_refused(base, tmp_path, capsys):
    folder = tmp_path / "ro"
    folder.mkdir(mode=0o555)
    assert main(["compile", base, "-o", str(folder / "c")]) == 2
    assert f"cannot write to {folder / 'c'}: cannot create anything in {folder}" in \
        capsys.readouterr().err


def test_a_missing_output_folder_is_created(base, tmp_path, capsys):
    # the check makes and removes a probe folder; the command then makes the real ones
    out = tmp_path / "a" / "b"
    assert main(["convert", base, str(out / "x.fll")]) == 0
    assert [p.name for p in out.iterdir()] == ["x.fll"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "base.fz"]


def test_a_failing_write_is_a_clean_error(tmp_path, monkeypatch):
    def full(src, dst):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(atomic.os, "replace", full)
    with pytest.raises(FuzzycError) as info:
        atomic.write_text(tmp_path / "x.txt", "text")
    assert info.value.diagnostics[0].message == \
        f"cannot write to {tmp_path / 'x.txt'}: No space left on device"
    assert list(tmp_path.iterdir()) == []     # no temporary file left behind


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full (Linux)")
def test_standard_output_on_a_full_disk(base):
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "fuzzyc", "check", base], stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=120)
    assert done.returncode == 2
    assert no_traceback(done.stderr) == \
        "error: cannot write to standard output: No space left on device\n"


# ---------------------------------------------------------------- what is left: bugs

def test_a_bug_is_an_internal_error_with_status_70(base, monkeypatch, capsys):
    def bug(model):
        raise ZeroDivisionError("a bug")
    monkeypatch.setattr("fuzzyc.cli.check.summary", bug)
    assert main(["check", base]) == 70
    err = capsys.readouterr().err
    assert err.startswith("fuzzyc: internal error, please report it")
    assert "ZeroDivisionError: a bug" in err       # the traceback, for the report


def test_a_closed_pipe_ends_quietly_with_141(base, monkeypatch, capsys):
    # `fuzzyc eval --csv big.csv | head`: head exits, the next write gets EPIPE
    def closed(args):
        raise BrokenPipeError(errno.EPIPE, os.strerror(errno.EPIPE))
    monkeypatch.setattr("fuzzyc.cli.check.run", closed)
    assert main(["check", base]) == 141
    assert capsys.readouterr().err == ""
