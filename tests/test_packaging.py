"""The wheel carries everything: installed non-editable into a fresh venv, `fuzzyc` works from
another folder (grammar and rule bases found as package data, runtime/plants under fuzzyc),
`fuzzyc examples` copies the shipped files out, and the pytest plugin registers itself."""
import os
import re
import shutil
import site
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def run(cmd, cwd, **kw):
    result = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=300, **kw)
    assert result.returncode == 0, f"{cmd} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


@pytest.fixture(scope="module")
def installed(built_wheel, tmp_path_factory):
    """A venv holding the wheel: under `make test` the suite's own (a fresh venv with the newest
    dependencies), in a development run a new venv borrowing the dependencies of this one."""
    tmp = tmp_path_factory.mktemp("pkg")
    wheel, _ = built_wheel
    if os.environ.get("FUZZYC_WHEEL"):
        return Path(sys.prefix), tmp
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


def clean_env() -> dict:
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


def test_the_build_gives_no_setuptools_warnings(built_wheel):
    _, log = built_wheel
    # setuptools warns with a *Warning class name (SetuptoolsDeprecationWarning...) in a !! box
    assert not re.search(r"\w+Warning\b", log), log


def test_examples_command_lists_and_copies_the_shipped_files(installed):
    venv, tmp = installed
    fuzzyc, env = str(venv / "bin" / "fuzzyc"), clean_env()
    listing = run([fuzzyc, "examples"], cwd=tmp, env=env)
    assert "wedm_three_region.fz" in listing and "wedm_rough.yaml" in listing
    assert "main.c" in listing and str(ROOT / "examples") not in listing, listing   # the wheel's own files
    assert str(ROOT / "rulebases") not in listing, listing
    target = tmp / "mine"
    run([fuzzyc, "examples", str(target)], cwd=tmp, env=env)
    assert sorted(p.name for p in (target / "rulebases").iterdir()) == sorted(
        p.name for p in (ROOT / "rulebases").glob("*.fz"))
    assert sorted(p.name for p in (target / "scenarios").iterdir()) == sorted(
        p.name for p in (ROOT / "plants" / "scenarios").glob("*.yaml"))
    assert (target / "c" / "main.c").read_bytes() == (ROOT / "examples" / "c" / "main.c").read_bytes()
    assert sorted(p.name for p in (target / "gymnasium").iterdir()) == [
        "cartpole.fz", "cartpole.yaml", "pendulum.fz", "pendulum.yaml"]
    assert "75 rules" in run([fuzzyc, "check", str(target / "rulebases" / "wedm_three_region.fz")],
                             cwd=tmp, env=env)
    again = subprocess.run([fuzzyc, "examples", str(target)], cwd=tmp, env=env,
                           capture_output=True, text=True)
    assert again.returncode == 2 and "not overwriting" in again.stderr


def test_the_copied_c_example_builds_and_runs(installed):
    if not (shutil.which("make") and shutil.which("cc")):
        pytest.skip("make and a C compiler are needed to build the C example")
    venv, tmp = installed
    target = tmp / "c_example"
    run([str(venv / "bin" / "fuzzyc"), "examples", str(target)], cwd=tmp, env=clean_env())
    run(["make", "-C", str(target / "c"), f"PYTHON={venv / 'bin' / 'python'}"], cwd=tmp,
        env=clean_env())
    # spark_freq 26 kHz, abnormal ratio 0.375 on the first sample: e1 = (30-26)*0.25 = 1,
    # e2 = (0.4-0.375)*10 = 0.25, ce2 = 0 -> du1 = du2 = 0.25 (docs/api.md works it out);
    # feed = 0.3 + 0.25*1.8e-4 = 0.300045, t_off = 1/(1/32 + 0.25*0.8e-4) = 31.97953
    out = subprocess.run([str(target / "c" / "build" / "controller")], input="26,0.375\n",
                         capture_output=True, text=True, check=True).stdout
    feed, t_off = (float(v) for v in out.split(","))
    assert abs(feed - 0.300045) < 1e-6 and abs(t_off - 31.97953) < 1e-4


def test_pytest_plugin_is_registered_by_the_wheel(installed):
    from test_pytest_plugin import check_passing_and_failing, make_project
    venv, tmp = installed
    # the wheel's own metadata declares it (the test environment's, also on the path, would too)
    purelib = next((venv / "lib").glob("python*/site-packages"))
    entry_points = (purelib / "fuzzyc-0.1.0.dist-info" / "entry_points.txt").read_text()
    assert "[pytest11]\nfuzzyc = fuzzyc.pytest_plugin" in entry_points, entry_points
    check_passing_and_failing(str(venv / "bin" / "python"), make_project(tmp / "project"),
                              env=clean_env())


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
    assert Path(where[1]).parent != ROOT / "fuzzyc", "fuzzyc was imported from the source tree, not the wheel"
    rulebase = Path(where[0]) / "wedm_three_region.fz"
    out = run([str(venv / "bin" / "fuzzyc"), "check", str(rulebase)], cwd=elsewhere, env=env)
    assert "75 rules" in out
    scenarios = list((Path(where[0]).parent / "plants" / "scenarios").glob("*.yaml"))
    assert scenarios, "scenario files are missing from the wheel"


def test_no_generic_top_level_names_are_installed(installed):
    venv, tmp = installed
    purelib = next((venv / "lib").glob("python*/site-packages"))
    assert not (purelib / "runtime").exists() and not (purelib / "plants").exists()
