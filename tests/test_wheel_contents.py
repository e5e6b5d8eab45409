"""Every file of the package folders reaches the wheel, under its installed name, and nothing
else does: a subpackage left out of the build (fuzzyc/verifier/reach/ once was, and
`verify --prove` crashed for every pip user) fails here, not on a user's machine."""
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import fuzzyc
import pytest
from conftest import ROOT

# setup.py's mapping: source folder -> installed folder
INSTALLED_AS = {"fuzzyc": "fuzzyc", "runtime": "fuzzyc/runtime", "plants": "fuzzyc/plants",
                "rulebases": "fuzzyc/rulebases", "examples": "fuzzyc/examples"}


def source_files() -> set[str]:
    """The files of the package folders that git does not ignore (tracked, or new and not yet
    added), named as the wheel names them."""
    listed = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard",
                             *INSTALLED_AS], cwd=ROOT, capture_output=True, text=True)
    if listed.returncode != 0:
        pytest.skip("not a git checkout: the tracked files are unknown")
    names = set()
    for path in listed.stdout.split():
        if not (ROOT / path).is_file():      # deleted in the working tree, not yet in git
            continue
        top, rest = path.split("/", 1)
        names.add(f"{INSTALLED_AS[top]}/{rest}")
    return names


def test_every_source_file_is_in_the_wheel_and_nothing_else(built_wheel):
    wheel, _ = built_wheel
    packed = {n for n in zipfile.ZipFile(wheel).namelist() if ".dist-info/" not in n}
    expected = source_files()
    assert sorted(expected - packed) == [], "missing from the wheel"
    assert sorted(packed - expected) == [], "in the wheel but not in the source tree"


def test_the_proof_engine_is_in_the_wheel(built_wheel):
    # the regression itself, by name: the reachability package and its modules
    wheel, _ = built_wheel
    packed = set(zipfile.ZipFile(wheel).namelist())
    reach = {p.relative_to(ROOT).as_posix() for p in (ROOT / "fuzzyc/verifier/reach").glob("*.py")}
    assert "fuzzyc/verifier/reach/__init__.py" in reach and reach <= packed


def test_the_suite_runs_against_what_it_claims(tmp_path):
    # under `make test` (FUZZYC_WHEEL set) fuzzyc is the installed wheel, in this process (the
    # conftest refuses the source tree) and in a child started from a test's folder
    if not os.environ.get("FUZZYC_WHEEL"):
        pytest.skip("a development run (no FUZZYC_WHEEL): the source tree is installed editable")
    child = subprocess.run([sys.executable, "-c", "import fuzzyc; print(fuzzyc.__file__)"],
                           cwd=tmp_path, capture_output=True, text=True, check=True)
    assert Path(child.stdout.strip()).parent != ROOT / "fuzzyc", child.stdout
    assert "site-packages" in child.stdout, child.stdout
    wheel = Path(os.environ["FUZZYC_WHEEL"]).name
    assert wheel.startswith(f"fuzzyc-{fuzzyc.__version__}-"), wheel
