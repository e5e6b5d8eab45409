"""The suite tests the installed package, not the source tree.

`make test` builds the wheel, installs it with the newest dependencies pip resolves into a fresh
venv and runs pytest from a folder outside the source tree, with FUZZYC_WHEEL naming the wheel.
Then `fuzzyc` must come from that venv's site-packages: a module missing from the wheel fails
here as it would for a user. The repository root is appended to sys.path (after site-packages)
only so that the test helpers under tests/ (`tests.fuzz`) import.
"""
import importlib.util
import os
import pathlib
import shutil
import subprocess
import sys

import fuzzyc
import pytest
from hypothesis import settings

ROOT = pathlib.Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.append(str(ROOT))

# tests/bad_inputs/ holds rule files that must fail to load (test_error_messages.py reads them);
# the plugin's `fuzzyc_verify = true` would otherwise collect each one as a broken test file
collect_ignore = ["bad_inputs"]

# every error message fuzzyc gives during the run, collected and held to the reviewed list
# tests/error_messages_reviewed.txt (tests/message_log.py)
from tests import message_log  # noqa: E402 - after the root is on sys.path

message_log.install()


def pytest_configure(config):
    config.pluginmanager.register(message_log.Plugin(config), "fuzzyc-error-messages")

INSTALLED_FROM = pathlib.Path(fuzzyc.__file__).resolve().parent
if os.environ.get("FUZZYC_WHEEL") and INSTALLED_FROM == ROOT / "fuzzyc":
    raise SystemExit(f"FUZZYC_WHEEL is set but fuzzyc was imported from the source tree "
                     f"({INSTALLED_FROM}), not from the installed wheel")


def pytest_report_header(config):
    wheel = os.environ.get("FUZZYC_WHEEL")
    lines = [f"fuzzyc imported from {INSTALLED_FROM}"
             + (f" (wheel {pathlib.Path(wheel).name})" if wheel else " (no wheel: a development run)")]
    freeze = subprocess.run([sys.executable, "-m", "pip", "freeze", "--exclude-editable",
                             "--disable-pip-version-check"],
                            capture_output=True, text=True).stdout.split()
    lines.append("resolved: " + ", ".join(p for p in freeze if not p.startswith("fuzzyc")))
    return lines


# The suite is a gate, so its property tests draw the same examples on every run
# (derandomize): what passes here passes on CI's fresh clone.  `make explore` runs them with
# fresh random seeds to search further; what it finds becomes a test of its own.
settings.register_profile("gate", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile("explore" if os.environ.get("FUZZYC_EXPLORE") else "gate")


# the folders that become the package (setup.py's mapping) and the files that go with them
SHIPPED = ("pyproject.toml", "setup.py", "README.md", "LICENSE", "fuzzyc", "runtime", "plants",
           "rulebases", "examples")


@pytest.fixture(scope="session")
def built_wheel(tmp_path_factory):
    """(wheel path, build log): the wheel `make test` installed, or in a development run one
    built here from a copy of the shipped files (so nothing else of the tree can leak in)."""
    if os.environ.get("FUZZYC_WHEEL"):
        wheel = pathlib.Path(os.environ["FUZZYC_WHEEL"])
        return wheel, (wheel.parent / "build.log").read_text()
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    src.mkdir()
    for name in SHIPPED:
        if (ROOT / name).is_dir():
            shutil.copytree(ROOT / name, src / name,
                            ignore=shutil.ignore_patterns("__pycache__", "*.so", "build"))
        else:
            shutil.copy(ROOT / name, src / name)
    # the development venv's setuptools when it has them (no downloads), else pip's isolation
    offline = ["--no-build-isolation"] if importlib.util.find_spec("wheel") else []
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", *offline, "-v",
                            "-w", str(tmp / "dist"), str(src)],
                           cwd=tmp, capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stdout + build.stderr
    return next((tmp / "dist").glob("fuzzyc-*.whl")), build.stdout + build.stderr
