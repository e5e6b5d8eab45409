"""Every command the docs show in a code block works where a user types it: after
`pip install fuzzyc` and `fuzzyc examples my-project`, with no source checkout.

Each command line of the fenced blocks of docs/*.md (backslash continuations joined, comments
dropped) is one test. A doc reads as one shell session: its commands run in a fresh folder
(`home`) holding a fresh copy of the examples, `home/my-project`, and from its `cd my-project`
on inside that copy. Per command:

- `fuzzyc ...`, `python -m fuzzyc...`, `pytest ...`: run with this interpreter (the installed
  package), exit 0, and an `-o DIR` / `--report DIR` holds files afterwards; a command too slow
  for the suite runs as listed in SUBSTITUTED (the same command made cheap, with the reason);
- `make -C c ...` builds the copied C example with FUZZYC naming this venv's console script,
  and the `printf ... | c/build/controller` beside it runs the result;
- `make TARGET`: the target is in the repository's Makefile; `pip install 'fuzzyc[X]'`: the
  extra X is in pyproject.toml; `.venv/bin/python benchmarks/... | -m pytest tests/...`: the
  files exist (developer commands, from a source checkout);
- NOT_RUN and NOT_COMMANDS hold the rest, each with its reason.

A command in none of these fails its test: a new command in the docs cannot go untested. An
entry of a table that no doc shows any more fails too.
"""
from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from glob import glob
from pathlib import Path

import pytest

import fuzzyc
from conftest import ROOT

DOCS = ROOT / "docs"
# the lines of a code block that are commands (the rest: output, code, file contents)
COMMAND_STARTS = ("fuzzyc ", "python -m fuzzyc", "pytest ", "make ", "pip install", ".venv/bin/",
                  "cd ", "printf ", "python3 ", "dask ")
CODE_BLOCKS = ("python", "yaml", "toml")     # code, not commands
PROJECT = "my-project"
TIMEOUT = 300

# doc command -> (the command run instead, why): the options stay, only the size shrinks
SUBSTITUTED = {
    "fuzzyc simulate --scenario wedm_finish --set duration=1 --batch 1000000 --randomize --chunk 10000 -o out/campaign":
        ("fuzzyc simulate --scenario wedm_finish --set duration=1 --batch 1000 --randomize --chunk 200 -o out/campaign",
         "10^6 loops take minutes; 1000 loops in 5 chunks in this process take the same path"),
    "fuzzyc simulate rulebases/wedm_corner.fz --scenario corner_path --set plant.feed=160 --set plant.thickness=50":
        ("fuzzyc simulate rulebases/wedm_corner.fz --scenario corner_path --set plant.feed=160 --set plant.thickness=50 --set duration=100",
         "the whole path is 3400 s of cutting (20 s here); its numbers are corner_table's first "
         "row, which test_docs_commands checks against the doc"),
    "fuzzyc verify rulebases/edm_sink_gap.fz --prove":
        ("fuzzyc verify rulebases/edm_sink_gap.fz --prove --only \"gap > 5\" --prove-boxes 4 --max-examples 10",
         "the proof over 3 s takes 75 s (edm_sink_gap's second loop 10 minutes): one check, "
         "4 boxes, on the copy's loops cut to 0.2 s (EDITS)"),
    "fuzzyc verify rulebases/*.fz --report out/verify":
        ("fuzzyc verify rulebases/fopdt_pi.fz --report out/verify",
         "the six shipped files take 140 s (`make test` verifies them all through the plugin); "
         "fopdt_pi has table, proof, grid and closed-loop properties"),
    "pytest --fuzzyc-verify rulebases/":
        ("pytest --fuzzyc-verify rulebases/fopdt_pi.fz",
         "the six shipped files take minutes (`make test` collects rulebases/ with the plugin)"),
    "python -m fuzzyc.tune.mackey_glass":
        ("python -m fuzzyc.tune.mackey_glass --epochs 5",
         "500 epochs take 15 s of CPU; 5 take the same path "
         "(tests/test_tune_mackey_glass.py pins 20 epochs' errors)"),
    "python -m fuzzyc.tune.mackey_glass --method least_squares":
        ("python -m fuzzyc.tune.mackey_glass --method least_squares --max-nfev 3",
         "the joint least squares to convergence; 3 evaluations take the same path"),
    "python -m fuzzyc.tune.mackey_glass --delay-steps 170":
        ("python -m fuzzyc.tune.mackey_glass --delay-steps 170 --epochs 5",
         "500 epochs on the other series; 5 take the same path"),
    "python -m fuzzyc.tune.mackey_glass --bounded -0.5 2.5":
        ("python -m fuzzyc.tune.mackey_glass --bounded -0.5 2.5 --epochs 5",
         "two fits of 500 epochs and the verifier's rounds; 5 epochs take the same path"),
    "fuzzyc tune rulebases/fopdt_pi.fz --scenario fopdt_step --minimize 'iae(y)' --limit 'overshoot(y)<=0.02' --seed 0 -o tuned.fz":
        ("fuzzyc tune rulebases/fopdt_pi.fz --scenario fopdt_step --minimize 'iae(y)' --limit 'overshoot(y)<=0.02' --seed 0 -o tuned.fz --max-evaluations 5 --max-examples 5",
         "the search takes 80 loops and the checks 30 each; 5 take the same path "
         "(tests/test_tune_loop.py checks the tuned results)"),
    "python -m fuzzyc.tune.fopdt_loop":
        ("python -m fuzzyc.tune.fopdt_loop --max-evaluations 5",
         "two searches of 80 loops; 5 take the same path (tests/test_tune_loop.py checks the "
         "fuzzy PI's result)"),
    "python -m fuzzyc.conformance [--details] [--no-live]":
        ("python -m fuzzyc.conformance --details --no-live",
         "[...] marks optional flags; --no-live: no fuzzylite/octave runs (`make conformance`)"),
}
# edits of the copied project before a (substituted) command, (file, old, new)
EDITS = {
    "fuzzyc verify rulebases/edm_sink_gap.fz --prove":
        [("rulebases/edm_sink_gap.fz", "closed_loop edm_sink for 3 s", "closed_loop edm_sink for 0.2 s")],
}
# doc command -> why it is not run here
NOT_RUN = {
    "fuzzyc simulate --scenario wedm_finish --set duration=1 --batch 1000000 --randomize --workers 2 --chunk 10000 -o out/campaign":
        "a local Dask cluster inside the suite lost its worker processes now and then (a heartbeat's "
        "CommClosedError; the session note of 2026-11-28); tests/test_campaign.py runs --workers "
        "alone in make test's second step",
    "fuzzyc verify rulebases/edm_sink_gap.fz --only \"gap > 5\" --max-examples 10000 --workers 2 --chunk 2000":
        "a local Dask cluster inside the suite lost its worker processes now and then (a heartbeat's "
        "CommClosedError; the session note of 2026-11-28); tests/test_campaign.py runs --workers "
        "alone in make test's second step",
    "fuzzyc tune rulebases/fopdt_pi.fz --scenario fopdt_step --minimize 'iae(y)' --batch 2000 --randomize --workers 2 --chunk 1000 --max-evaluations 10 -o tuned.fz":
        "a local Dask cluster inside the suite lost its worker processes now and then (a heartbeat's "
        "CommClosedError; the session note of 2026-11-28); tests/test_tune_campaign.py runs "
        "`fuzzyc tune ... --workers 2 --chunk 8` alone in make test's second step",
    "fuzzyc simulate --scenario wedm_finish --set duration=1 --batch 1000000 --randomize --scheduler tcp://scheduler-host:8786 -o out/campaign":
        "needs a running Dask scheduler on that host; tests/test_campaign.py runs --scheduler "
        "against a cluster it starts",
    "fuzzyc verify rulebases/edm_sink_gap.fz --prove --prove-boxes 128":
        "the line above with a larger budget: minutes; the substituted run of the line above "
        "takes --prove-boxes",
    "fuzzyc tune mg/mackey_glass_anfis.fz --data mg/train.csv --validate mg/check.csv --seed 0 -o mg/tuned.fz":
        "its files are the ones the line above writes, and each doc command runs in a fresh "
        "copy; tests/test_tune_cli.py runs fuzzyc tune on files it writes",
    "python -m fuzzyc.tune.mackey_glass --monotone x0":
        "half an hour of CPU (six rounds of the verifier in the 4-input box); the substituted "
        "run of `python -m fuzzyc.tune.mackey_glass --bounded -0.5 2.5` takes the same path "
        "to the kept-property row",
    "python -m fuzzyc.tune.corner_identify":
        "about four minutes of CPU (two closed loops of 12,600 periods and the closed-loop "
        "property's checks); tests/test_tune_loop.py checks its data and how its cost reads "
        "the controller",
    "python -m fuzzyc.plants.corner_table --against table4.csv":
        "table4.csv is the user's measurements (held out of the project); "
        "tests/test_corner_validation.py runs --against on files it writes",
}
# docs whose commands build on each other's files: a test of their own runs them in order
SESSIONS = {
    "tutorial.md": "tests/test_tutorial.py runs the tutorial in order in one folder (its steps "
                   "use the files the steps before wrote) and compares every output it shows",
}
# lines that look like commands but hold a placeholder, or start a service
NOT_COMMANDS = {
    "fuzzyc verify FILE --prove --noise-sigmas 3": "FILE is a placeholder for any rule file",
    "fuzzyc simulate ... --scheduler tcp://HOST:8786": "`...` and HOST are placeholders",
    "dask scheduler": "starts a Dask scheduler service (runs until stopped), Dask's own command",
    "dask worker tcp://HOST:8786 --nworkers 4 --nthreads 1": "HOST is a placeholder; a service",
    "fuzzyc simulate ... --scheduler tls://HOST:8786":
        "`...` and HOST are placeholders; tests/test_campaign_security.py runs --scheduler "
        "tls://... with the DASK_DISTRIBUTED__COMM__TLS__ variables against a cluster it starts",
    "dask scheduler --tls-ca-file ca.pem --tls-cert scheduler.pem --tls-key scheduler-key.pem":
        "starts a Dask scheduler service, Dask's own command; the certificates are the user's",
    "dask worker tls://HOST:8786 --tls-ca-file ca.pem --tls-cert worker.pem --tls-key "
    "worker-key.pem --nworkers 4 --nthreads 1": "HOST is a placeholder; a service",
}


def doc_commands() -> list[tuple[str, int, str, str]]:
    """(doc name, line, command, folder it runs in: "home" or PROJECT) for every command line
    of the docs' fenced code blocks."""
    found = []
    for doc in sorted(DOCS.glob("*.md")):
        folder, fence, pending = "home", None, ""
        for number, line in enumerate(doc.read_text(encoding="utf-8").splitlines(), 1):
            if line.lstrip().startswith("```"):
                fence = None if fence is not None else line.strip()[3:].strip()
                continue
            if fence is None or fence in CODE_BLOCKS:
                continue
            line = pending + line.strip()
            if line.endswith("\\"):
                pending = line[:-1] + " "
                continue
            pending = ""
            command = " ".join(re.sub(r"(^|\s)#\s.*$", "", line).split())
            if not command.startswith(COMMAND_STARTS):
                continue
            found.append((doc.name, number, command, folder))
            if command == f"cd {PROJECT}":
                folder = PROJECT
    return found


COMMANDS = doc_commands()


def is_run(command: str) -> bool:
    return command.startswith(("fuzzyc ", "python -m fuzzyc", "pytest "))


def argv(command: str) -> list[str]:
    """The command with this interpreter: `fuzzyc` is `python -m fuzzyc` of the installed package."""
    words = shlex.split(command)
    if words[0] == "fuzzyc":
        return [sys.executable, "-m", "fuzzyc", *words[1:]]
    if words[0] == "pytest":
        return [sys.executable, "-m", "pytest", *words[1:]]
    assert words[0] == "python", command
    return [sys.executable, *words[1:]]


def clean_env(**extra: str) -> dict[str, str]:
    """This environment without the running pytest's own variables (xdist's, the current test)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
    env.update(MPLBACKEND="Agg", **extra)
    return env


def session(tmp_path: Path, command: str, folder: str) -> Path:
    """A fresh home with a fresh copy of the examples (unless the command makes it); the
    folder the command runs in."""
    home = tmp_path / "home"
    home.mkdir()
    if command != f"fuzzyc examples {PROJECT}":
        fuzzyc.copy_examples(home / PROJECT)
    for name, old, new in EDITS.get(command, []):
        path = home / PROJECT / name
        text = path.read_text(encoding="utf-8")
        assert old in text, (name, old)
        path.write_text(text.replace(old, new), encoding="utf-8")
    cwd = home if folder == "home" else home / PROJECT
    if "controllers/" in command:       # docs/pytest-plugin.md: the user's own rule files
        write_heater(cwd / "controllers")
    return cwd


HEATER = """controller heater {
  input temp : degC in [0, 100]
  terms temp : cold = lshoulder(20, 60), hot = rshoulder(20, 60)
  var power in [0, 1]
  terms power : singletons low = 0 high = 1
  rule if temp is cold then power is high
  rule if temp is hot then power is low
  output heating : W in [0, 2000] = 2000 * power
  verify {
    complete
    covers temp at least 0.5
  }
}
"""


def write_heater(folder: Path) -> None:
    """controllers/heater.fz, the file docs/pytest-plugin.md names (docs/api.md's heater, its
    terms crossing at 0.5 so that it covers temp at least 0.5)."""
    folder.mkdir()
    (folder / "heater.fz").write_text(HEATER, encoding="utf-8")


def run(args: list[str], cwd: Path, env: dict[str, str] | None = None,
        **options) -> subprocess.CompletedProcess:
    done = subprocess.run(args, cwd=cwd, env=env or clean_env(), capture_output=True, text=True,
                          timeout=TIMEOUT, **options)
    assert "Traceback" not in done.stderr, done.stderr
    return done


def needs(command: str) -> None:
    """Skip a command whose optional tool is missing."""
    if "gymnasium/" in command:
        pytest.importorskip("gymnasium", reason="the Gymnasium examples need `fuzzyc[gym]`")
    if re.search(r"--workers|--scheduler", command):
        pytest.importorskip("distributed", reason="--workers needs `fuzzyc[dask]`")
    if "compile" in command and "--prove" in command and not shutil.which("frama-c"):
        pytest.skip("--prove of `fuzzyc compile` needs frama-c (Debian frama-c-base)")


def check_run(command: str, cwd: Path) -> subprocess.CompletedProcess:
    run_command = SUBSTITUTED.get(command, (command, ""))[0]
    needs(run_command)
    args = argv(run_command)
    # a shell expands globs; the files are relative to the folder the command runs in
    args = [a for arg in args
            for a in (sorted(glob(arg, root_dir=cwd)) if "*" in arg else [arg])]
    env = clean_env(PYTEST_ADDOPTS="-v -p no:cacheprovider") if args[2:3] == ["pytest"] else None
    done = run(args, cwd, env)
    assert done.returncode == 0, (run_command, done.stdout[-3000:], done.stderr[-3000:])
    words = shlex.split(run_command)
    for option in ("-o", "--report"):
        if option in words:
            written = cwd / words[words.index(option) + 1]
            # a folder of files, or the one file it names (`fuzzyc tune ... -o tuned.fz`)
            assert written.is_file() or written.is_dir() and any(written.iterdir()), \
                (run_command, written)
    return done


def c_example(command: str, cwd: Path) -> subprocess.CompletedProcess:
    """`make -C c ...` with FUZZYC naming this venv's console script."""
    if not (shutil.which("make") and shutil.which("cc")):
        pytest.skip("make and a C compiler are needed to build the C example")
    fuzzyc_script = Path(sys.executable).parent / "fuzzyc"
    assert fuzzyc_script.exists(), fuzzyc_script
    done = run([*shlex.split(command), f"FUZZYC={fuzzyc_script}"], cwd)
    assert done.returncode == 0, (command, done.stdout, done.stderr)
    return done


@pytest.mark.parametrize("doc, line, command, folder", COMMANDS,
                         ids=[f"{doc}:{line}" for doc, line, _, _ in COMMANDS])
def test_doc_command(doc, line, command, folder, tmp_path):
    where = f"docs/{doc}:{line}: `{command}`"
    if doc in SESSIONS:
        pytest.skip(f"{where}: {SESSIONS[doc]}")
    if command in NOT_COMMANDS:
        assert NOT_COMMANDS[command]
        return
    if command in NOT_RUN:
        pytest.skip(f"{where}: not run: {NOT_RUN[command]}")
    if command.startswith("cd "):
        assert command == f"cd {PROJECT}", f"{where}: the docs' sessions know only `cd {PROJECT}`"
        assert f"fuzzyc examples {PROJECT}" in (DOCS / doc).read_text(encoding="utf-8"), \
            f"{where}: say where {PROJECT} comes from (`fuzzyc examples {PROJECT}`)"
        return
    if is_run(command):
        cwd = session(tmp_path, command, folder)
        done = check_run(command, cwd)
        check_figures(command, cwd, done)
        return
    words = shlex.split(command)
    if words[:2] == ["make", "-C"]:
        assert folder == PROJECT and words[2] == "c", f"{where}: the C example is c/ of {PROJECT}"
        cwd = session(tmp_path, command, folder)
        c_example(command, cwd)
        assert (cwd / "c" / "build" / "controller").exists()
        return
    if words[0] == "make":
        targets = re.findall(r"^([\w.-]+):", (ROOT / "Makefile").read_text(), re.M)
        assert len(words) == 2 and words[1] in targets, f"{where}: no such target in Makefile"
        return
    if words[0] == "printf" and command.endswith("| c/build/controller"):
        cwd = session(tmp_path, command, folder)
        c_example("make -C c", cwd)
        done = run(["bash", "-c", command], cwd)
        assert done.returncode == 0, done.stderr
        header, *rows = done.stdout.splitlines()
        assert header.startswith("#") and len(rows) == 2, done.stdout
        for row in rows:     # feed mm/min in [0, 3], t_off us in [1.6, 48]
            feed, t_off = (float(v) for v in row.split(","))
            assert 0 <= feed <= 3 and 1.6 <= t_off <= 48, row
        return
    if words[:2] == ["pip", "install"]:
        # (no tomllib before Python 3.11) the keys of the optional-dependencies table
        table = (ROOT / "pyproject.toml").read_text().split("[project.optional-dependencies]")[1]
        extras = re.findall(r"^([\w-]+)\s*=", table.split("\n[")[0], re.M)
        for spec in words[2:]:
            name = re.fullmatch(r"fuzzyc\[(\w+)\]", spec)
            assert name and name[1] in extras, f"{where}: no extra {spec} in pyproject.toml"
        return
    if words[0] == ".venv/bin/python":
        files = [w for w in words[1:] if w.endswith(".py")]
        assert files and all((ROOT / f).is_file() for f in files), \
            f"{where}: a developer command names files of the source checkout that do not exist"
        return
    pytest.fail(f"{where}: a command in no category of {__name__}: run it, substitute it, "
                "or list it with a reason")


def check_figures(command: str, cwd: Path, done: subprocess.CompletedProcess) -> None:
    """Where cheap, the figures the doc quotes for the command."""
    if command.endswith("--batch 100 -o out/cartpole100"):
        # docs/gymnasium.md: the pole stays up for all 500 steps, 100 of 100 seeds
        metrics = json.loads((cwd / "out/cartpole100/summary.json").read_text())["metrics"]
        assert metrics["fell (1) or survived (0)"]["max"] == 0
        assert metrics["episode return (500: every step survived)"]["min"] == 500
    if command == "python -m fuzzyc.plants.corner_table":
        # docs/plants.md prints the table this command writes, row for row
        doc = (DOCS / "plants.md").read_text(encoding="utf-8").splitlines()
        printed = [line for line in done.stdout.splitlines() if re.match(r"\| (50|21) \| ", line)]
        assert len(printed) == 8 and all(row in doc for row in printed), done.stdout
    if command == "pytest --fuzzyc-verify controllers/":
        # docs/pytest-plugin.md: a test per property, named by its text
        assert "controllers/heater.fz::covers temp at least 0.5 PASSED" in done.stdout, done.stdout
        assert "2 passed" in done.stdout, done.stdout
    if command == "pytest --fuzzyc-verify rulebases/":
        assert "rulebases/fopdt_pi.fz::covers e, ce at least 0.25 PASSED" in done.stdout, done.stdout
    if command.startswith("fuzzyc compile") and "--prove" in command:
        assert "PROVED by Frama-C EVA" in done.stdout, done.stdout


def test_every_listed_command_is_in_the_docs():
    shown = {command for _, _, command, _ in COMMANDS}
    for table in (SUBSTITUTED, EDITS, NOT_RUN, NOT_COMMANDS):
        stale = set(table) - shown
        assert not stale, f"listed, but no doc shows it any more: {stale}"
    assert all(reason for _, reason in SUBSTITUTED.values())
    assert all((DOCS / doc).is_file() for doc in SESSIONS), "a session doc that no longer exists"
    assert len(COMMANDS) > 30 and {doc for doc, *_ in COMMANDS} >= {"gymnasium.md", "campaigns.md"}
