"""The wheel carries everything: installed non-editable into a fresh venv, `fuzzyc` works from
another folder (grammar and rule bases found as package data, runtime/plants under fuzzyc)."""
import importlib.util
import os
import shutil
import site
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ("pyproject.toml", "README.md", "fuzzyc", "runtime", "plants", "rulebases")


def run(cmd, cwd, **kw):
    result = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=300, **kw)
    assert result.returncode == 0, f"{cmd} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pkg")
    src = tmp / "src"
    for name in SHIPPED:
        source = ROOT / name
        if source.is_dir():
            shutil.copytree(source, src / name,
                            ignore=shutil.ignore_patterns("__pycache__", "*.so", "conftest.py"))
        else:
            src.mkdir(exist_ok=True)
            shutil.copy(source, src / name)
    # Build with the test environment's setuptools when it has them (no downloads); otherwise
    # let pip fetch the build backend into an isolated environment.
    offline = ["--no-build-isolation"] if importlib.util.find_spec("wheel") else []
    run([sys.executable, "-m", "pip", "wheel", "--no-deps", *offline, "-q",
         "-w", str(tmp / "dist"), str(src)], cwd=tmp)
    wheel = next((tmp / "dist").glob("fuzzyc-*.whl"))
    venv = tmp / "venv"
    run([sys.executable, "-m", "venv", str(venv)], cwd=tmp)
    vpy = venv / "bin" / "python"
    # Dependencies come from the test environment (no downloads); the package itself only
    # from the wheel, so nothing can leak in from the source tree.
    purelib = Path(run([str(vpy), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                       cwd=tmp).strip())
    deps = [p for p in site.getsitepackages() + [sysconfig.get_paths()["purelib"]] if Path(p).is_dir()]
    (purelib / "test_deps.pth").write_text("\n".join(dict.fromkeys(deps)) + "\n")
    run([str(vpy), "-m", "pip", "install", "--no-deps", "-q", "--disable-pip-version-check",
         str(wheel)], cwd=tmp)
    return venv, tmp


def test_console_script_and_rule_base_from_another_folder(installed):
    venv, tmp = installed
    elsewhere = tmp / "elsewhere"
    elsewhere.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    vpy = str(venv / "bin" / "python")
    help_text = run([str(venv / "bin" / "fuzzyc"), "--help"], cwd=elsewhere, env=env)
    assert "check" in help_text and "compile" in help_text
    where = run([vpy, "-c", "import fuzzyc, fuzzyc.rulebases, fuzzyc.runtime, fuzzyc.plants, os;"
                 "print(os.path.dirname(fuzzyc.rulebases.__file__)); print(fuzzyc.__file__)"],
                cwd=elsewhere, env=env).split()
    assert str(ROOT) not in where[1], "fuzzyc was imported from the source tree, not the wheel"
    rulebase = Path(where[0]) / "wedm_three_region.fz"
    out = run([str(venv / "bin" / "fuzzyc"), "check", str(rulebase)], cwd=elsewhere, env=env)
    assert "75 rules" in out
    scenarios = list((Path(where[0]).parent / "plants" / "scenarios").glob("*.yaml"))
    assert scenarios, "scenario files are missing from the wheel"


def test_no_generic_top_level_names_are_installed(installed):
    venv, tmp = installed
    purelib = next((venv / "lib").glob("python*/site-packages"))
    assert not (purelib / "runtime").exists() and not (purelib / "plants").exists()
