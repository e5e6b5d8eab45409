"""Issue 13, files: names from input files cannot leave the output folder; written files honour
the umask; the cache of compiled C libraries loads only files its user wrote."""
from __future__ import annotations

import contextlib
import os
import shutil
import stat
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.atomic import save_figure, write_text
from fuzzyc.cli import main as cli_main
from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.escape import OutputFolder
from fuzzyc.formats import load_any
from hostile_fis import sugeno_fis

FIS = sugeno_fis("../../up", [("a/../../../x", "lo", "hi"), ("a_.._.._.._x", "lo", "hi"),
                               ("$\\frac{$", "lo", "hi")], ("/tmp/u", "small", "big"))
# The same with names that do not meet as C names.
C_FIS = sugeno_fis("../../up", [("a/../../../x", "lo", "hi"), ("w", "lo", "hi"),
                                ("z", "lo", "hi")], ("/tmp/u", "small", "big"))


def every_file(folder: Path) -> set[Path]:
    return {p for p in folder.rglob("*")}


def test_plot_writes_only_inside_its_folder(tmp_path, capsys):
    work = tmp_path / "deep" / "er"
    work.mkdir(parents=True)
    source = work / "m.fis"
    source.write_text(FIS)
    out = work / "plots"
    assert cli_main(["plot", str(source), "-o", str(out)]) == 0
    # 3 inputs and 1 output -> 4 term pictures (the two inputs that meet as file names: _2)
    # and 1 surface; the FIS reader made the model's name `../../up` ______up
    printed = [Path(p) for p in capsys.readouterr().out.split()]
    assert [p.name for p in printed] == [
        "______up_a_.._.._.._x_terms.png", "______up_a_.._.._.._x_terms_2.png",
        "______up___frac___terms.png", "______up__tmp_u_terms.png",
        "______up__tmp_u_surface.png"]
    assert every_file(tmp_path) == {tmp_path / "deep", work, source, out,
                                    *(out / p.name for p in printed)}


@pytest.mark.parametrize("stem, name", [
    ("..", "unnamed.png"), ("../../etc/passwd", "_.._etc_passwd.png"), (".hidden", "hidden.png"),
    ("", "unnamed.png"), ("a\nb", "a_b.png"), ("é", "_.png")])
def test_output_folder_names(tmp_path, stem, name):
    assert OutputFolder(tmp_path).file(stem, ".png") == tmp_path / name


@contextlib.contextmanager
def umask(mask: int):
    old = os.umask(mask)
    try:
        yield
    finally:
        os.umask(old)


def mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.mark.parametrize("mask, expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_written_files_honour_the_umask(tmp_path, mask, expected):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from fuzzyc.runtime.trace import Trace
    with umask(mask):
        write_text(tmp_path / "a.txt", "x\n")
        write_text(tmp_path / "a.txt", "y\n")          # replacing keeps the same rule
        save_figure(plt.figure(), tmp_path / "f.png")
        trace = Trace(np.arange(3.0), {"u": np.zeros((3, 1))}, period=1.0)
        trace.to_csv(tmp_path / "t.csv")
    assert {p.name: mode(p) for p in tmp_path.iterdir()} == \
        {"a.txt": expected, "f.png": expected, "t.csv": expected}


def test_compiled_header_is_0644_under_umask_022(tmp_path, capsys):
    source = tmp_path / "m.fis"
    source.write_text(C_FIS)
    with umask(0o022):
        assert cli_main(["compile", str(source), "-o", str(tmp_path / "c")]) == 0
    (header,) = (tmp_path / "c").iterdir()
    assert header.name == "______up.h" and mode(header) == 0o644


# -- the cache of compiled libraries ----------------------------------------------------------

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
PLANT = """\
#include <stdio.h>
__attribute__((constructor)) static void planted(void) {
    FILE *f = fopen("MARKER", "w");
    if (f) { fputs("planted code ran", f); fclose(f); }
}
"""


def plant(path: Path, marker: Path) -> None:
    """A shared library at `path` that writes `marker` when it is loaded."""
    c = path.with_suffix(".c")
    c.write_text(PLANT.replace("MARKER", str(marker)))
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(path), str(c)], check=True)
    c.unlink()


def small_model(tmp_path):
    source = tmp_path / "m.fis"
    source.write_text(C_FIS)
    return load_any(source)


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv("FUZZYC_CACHE", str(folder))
    return folder


@needs_gcc
@pytest.mark.parametrize("why", ["writable by others", "another owner"])
def test_a_planted_library_is_never_loaded(tmp_path, cache, why):
    from fuzzyc.backends.c.load import CController, controller_sources, library_path
    model = small_model(tmp_path)
    target = library_path(controller_sources(model, "float"), "shim.c")
    assert target.parent == cache and mode(cache) == 0o700
    marker = tmp_path / "marker"
    plant(target, marker)
    if why == "writable by others":
        os.chmod(target, 0o666)
    else:
        if os.getuid() != 0:
            pytest.skip("giving a file to another user needs root")
        os.chown(target, 65534, 65534)
    planted = target.read_bytes()
    c = CController(model)
    assert not marker.exists()                        # its constructor never ran
    assert target.read_bytes() != planted             # compiled anew over it
    assert target.stat().st_uid == os.getuid() and mode(target) == 0o700
    x = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    assert np.allclose(c.evaluate(x), evaluate(model.rulebase, x))   # 2 and 8


@needs_gcc
def test_the_users_own_library_is_reused(tmp_path, cache):
    # The other side of the check: a private file of the user's is what the cache returns.
    from fuzzyc.backends.c.load import compile_shared, controller_sources, library_path
    sources = controller_sources(small_model(tmp_path), "float")
    target = library_path(sources, "shim.c")
    plant(target, tmp_path / "marker")
    os.chmod(target, 0o700)
    planted = target.read_bytes()
    assert compile_shared(sources, "shim.c") == target and target.read_bytes() == planted


def test_a_shared_cache_folder_is_refused(tmp_path, cache):
    from fuzzyc.backends.c.load import cache_dir
    cache.mkdir()
    os.chmod(cache, 0o777)
    with pytest.raises(FuzzycError, match=r"is writable by others \(mode 0777\)"):
        cache_dir()
    os.chmod(cache, 0o700)
    if os.getuid() == 0:
        os.chown(cache, 65534, 65534)
        with pytest.raises(FuzzycError, match="belongs to user id 65534"):
            cache_dir()


def test_the_default_cache_is_per_user(tmp_path, monkeypatch):
    from fuzzyc.backends.c.load import cache_dir
    monkeypatch.delenv("FUZZYC_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "fuzzyc" and mode(cache_dir()) == 0o700
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert cache_dir() == tmp_path / "home" / ".cache" / "fuzzyc"
