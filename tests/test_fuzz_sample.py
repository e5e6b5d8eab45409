"""A sample of the fuzzing harness (`make fuzz` runs 10,000 inputs): about 400 hostile inputs
over every target must give no traceback, no rejection without file:line:col, no timeout and
the same exit status from the console script -- except the classes listed in
tests/fuzz/known.py, which other branches are fixing. A few inputs of each generator, the
inputs the generators found failing (tests/fuzz/regressions/), and the harness's own
classification, so that it can fail."""
import random
from pathlib import Path

import pytest

from tests.fuzz.known import known_owner
from tests.fuzz.runner import Run, classify, fuzz_target, run_in_process
from tests.fuzz.targets import SHARES, TARGETS, snapshot

SAMPLE = 400
SEED = 20261124
GENERATED_SAMPLE = 6      # per generator: a simulated scenario is about 0.4 s
REGRESSIONS = Path(__file__).parent / "fuzz" / "regressions"


@pytest.mark.drawn_inputs
@pytest.mark.parametrize("name", sorted(TARGETS))
def test_hostile_inputs_get_a_located_message(name, tmp_path):
    count = GENERATED_SAMPLE if TARGETS[name].generated else max(20, round(SAMPLE * SHARES[name]))
    before = snapshot()
    # one input of the sample (the first) also through the `fuzzyc` console script
    tally = fuzz_target(TARGETS[name], count, SEED, tmp_path, subprocess_every=count)
    assert tally.inputs >= count // 2, "hypothesis gave up on most inputs"
    assert tally.subprocess_runs >= (TARGETS[name].run is None)   # the API has no script
    assert snapshot() == before, "the harness wrote over a shipped file"
    new = {f"{kind}: {signature}": tally.examples[(kind, signature)]
           for (kind, signature) in tally.failures if known_owner(signature) is None}
    assert not new, "\n".join(f"{k}\n    {v[0]}/REPRODUCE.txt" for k, v in new.items())


@pytest.mark.parametrize("name", sorted(n for n, t in TARGETS.items()
                                         if n != "cmdline" and not t.generated))
def test_every_seed_passes_as_it_is(name, tmp_path):
    # a seed that fails unmutated is a shipped file the program rejects (the scenario schema
    # once refused three shipped scenarios), and its mutations test nothing past the failure
    target = TARGETS[name]
    good = [i for i, (text, source) in enumerate(target.seeds) if should_pass(text, source)]
    tally = fuzz_target(target, 2 * len(good), SEED, tmp_path, unmutated=good)
    assert set(tally.outcomes) <= {"ok", "refused"}, dict(tally.failures) or tally.outcomes
    assert tally.outcomes["ok"] >= len(good) > 0


def should_pass(text: str, source) -> bool:
    """Not a corpus file of errors (bad_*), not an FCL file of several blocks (which needs
    FILE::NAME); exported rule bases (no source file) and every scenario and CSV pass."""
    return not (isinstance(source, Path) and source.name.startswith("bad_")
                or text.count("END_FUNCTION_BLOCK") > 1)


@pytest.mark.parametrize("argv, where", [
    # a gauss2mf (dsigmf, psigmf) with 3 parameters: IndexError reordering them
    (["check", str(REGRESSIONS / "fis_gauss2mf_three_params.fis")], ":11:5: error: "),
    # `!!bool maybe`, `!!int 1.5`: PyYAML's constructors raised KeyError, ValueError
    (["simulate", "--scenario", str(REGRESSIONS / "scenario_tag_cannot_read.yaml")],
     ":1:8: error: not valid YAML: cannot read 'maybe'"),
])
def test_what_the_generators_found_is_a_located_message(argv, where, tmp_path):
    run = run_in_process(argv + (["-o", str(tmp_path / "o")] if argv[0] == "simulate" else []),
                         60.0)
    assert (run.code, run.error) == (2, None)
    assert where in run.stderr and "Traceback" not in run.stderr


def test_a_name_with_a_carriage_return_is_one_quoted_csv_field(tmp_path):
    # found by gen-fis (make fuzz on 453b376): csv.writer with "\n" as its line end left a
    # bare "\r" in a FIS output's name unquoted, and a CSV reader split the header there
    import csv
    import io
    (tmp_path / "p.csv").write_text("x\n0.5\n")
    run = run_in_process(["eval", str(REGRESSIONS / "fis_output_name_with_carriage_return.fis"),
                          "--csv", str(tmp_path / "p.csv")], 60.0)
    assert run.code == 0
    # x = 0.5: low(0.5) = 0.5 clips the symmetric triangle small (0, 5, 10): centroid 5
    assert list(csv.reader(io.StringIO(run.stdout, newline=""))) == [
        ["x", "a\rb", "a\rb_out"], ["0.5", "5.0", "5.0"]]


def test_a_rule_file_past_the_size_limit_is_refused_at_a_place(tmp_path):
    from fuzzyc.language.limits import MAX_SOURCE_BYTES
    path = tmp_path / "big.fll"
    path.write_text("Engine: x\n#" + "x" * MAX_SOURCE_BYTES)
    run = run_in_process(["check", str(path)], 60.0)
    assert run.code == 2
    assert f"big.fll:2:{MAX_SOURCE_BYTES - 9}: error: " in run.stderr     # the byte past it


def test_a_huge_worker_count_is_a_usage_error(capsys):
    # found by gen-cli: a cluster of 99999999999 workers ran out of memory; now argparse
    # refuses it (fuzzyc.language.limits.MAX_WORKERS = 64) before anything starts
    from fuzzyc.cli import build_parser
    with pytest.raises(SystemExit):
        build_parser().parse_args(["simulate", "rulebases/wedm_corner.fz", "--scenario",
                                   "corner_path", "--workers", "99999999999"])
    assert "--workers: must be at most 64, got 99,999,999,999" in capsys.readouterr().err


@pytest.mark.parametrize("call, values, message", [
    ("evaluate", None, "the inputs must be a mapping of the rule base's inputs (service, food)"),
    ("evaluate", {"service": [1.0, 2.0], "food": [1.0, 2.0, 3.0]},
     "do not broadcast together: service (2,), food (3,)"),
    ("evaluate", {"service": 1.0, "food": 2.0, None: 1.0}, "unknown: None"),
    ("explain", {"service": [1.0, 2.0], "food": 2.0}, "not arrays (given for service)"),
])
def test_api_rejections_name_the_inputs(call, values, message):
    import fuzzyc
    model = fuzzyc.load(Path(__file__).parent / "format_corpus" / "tipper.fll")
    with pytest.raises((TypeError, ValueError, KeyError)) as caught:
        getattr(fuzzyc, call)(model, values)
    assert message in str(caught.value)


def test_the_api_target_judges_by_the_named_input(tmp_path):
    from tests.fuzz.api import run
    model = str(Path(__file__).parent / "format_corpus" / "tipper.fll")
    outcomes = {classify(run(["evaluate", model, str(seed)], 30.0), TARGETS["gen-api"],
                         tmp_path)[0] for seed in range(40)}
    assert outcomes == {"ok", "rejected"}


def test_a_generated_condition_1000_deep_is_text_with_balanced_brackets():
    from tests.fuzz import generate
    rnd = random.Random(1)
    rb = generate.rulebase(rnd)
    rb["rules"][0]["if"] = generate._condition(rnd, rb["inputs"], 1000)
    line = next(ln for ln in generate.fll_text(rb, rnd).splitlines() if "rule:" in ln)
    assert line.count("(") == line.count(")") >= 1000


TARGET = TARGETS["fll"]


@pytest.mark.parametrize("run, kind", [
    (Run(["check", "x.fll"], 0, ""), "ok"),
    (Run(["check", "x.fll"], 2, "x.fll:3:7: error: no term `hot`\n1 error\n"), "rejected"),
    # the place may be inside the message (eval --csv names the CSV cell)
    (Run(["eval", "x.fll"], 2, "error: t.csv:2:1: `a` is not a number\n1 error\n"), "rejected"),
    (Run(["check", "x.fll"], 2, "error: cannot read x.fll: bad byte\n1 error\n"), "unlocated"),
    (Run(["check"], 2, "usage: fuzzyc check ...", usage=True), "usage"),
    (Run(["convert", "x.fll", "y.fis"], 2, "error: cannot export `x` to FIS: hedge\n"),
     "refused"),
    (Run(["verify", "x.fz"], 1, ""), "exit 1"),
    # past a bound: the CPU or wall timer, the worker's address space
    (Run(["check", "x.fll"], None, "", error="Traceback ...\ntests.fuzz.runner.InputTimeout: "
         "more than 60 s of wall time\n"), "over-bound"),
    (Run(["eval", "x.fll"], None, "", error="Traceback ...\nnumpy.core._exceptions."
         "_ArrayMemoryError: Unable to allocate 8.0 GiB\n"), "over-bound"),
    # what main() catches as a bug: exit 70 and the traceback on stderr
    (Run(["check", "x.fll"], 70, "fuzzyc: internal error, please report it ...:\n"
         "Traceback (most recent call last):\n  File \"/w/fuzzyc/x.py\", line 1, in f\n"
         "ValueError: bad\n"), "traceback"),
])
def test_classify(run, kind, tmp_path):
    assert classify(run, TARGET, tmp_path)[0] == kind


@pytest.mark.parametrize("argv, stdout, kind", [
    (["eval", "x.fis", "--json", "x=1"], '{"outputs": {"z": NaN}, "fired": []}', "nonfinite"),
    (["eval", "x.fis", "--json", "x=1"], '{"outputs": {"z": 2.5}, "fired": []}', "ok"),
    (["eval", "x.fis", "x=nan"], "x.fis: ...\noutputs: z = nan, z_out = -20\n", "nonfinite"),
    (["eval", "x.fis", "x=1"], "x.fis: ...\noutputs: z = 10, z_out = -inf\n", "nonfinite"),
    (["eval", "x.fis", "x=1"], "x.fis: ...\noutputs: z = 10, z_out = -20\n", "ok"),
    # the CSV echoes its inputs (x and w, the header of in.csv): a NaN there is the input's
    (["eval", "x.fis", "--csv", "in.csv"], "x,w,z\n1.0,nan,2.0\n", "ok"),
    (["eval", "x.fis", "--csv", "in.csv"], "x,w,z\n1.0,0.5,inf\n", "nonfinite"),
])
def test_a_successful_eval_must_print_numbers(argv, stdout, kind, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in.csv").write_text("x,w\n1,nan\n")
    assert classify(Run(argv, 0, "", stdout=stdout), TARGET, tmp_path)[0] == kind


def test_classify_names_the_deepest_project_frame_of_a_traceback(tmp_path):
    text = ('Traceback (most recent call last):\n'
            '  File "/w/fuzzyc/cli/main.py", line 30, in main\n'
            '  File "/w/fuzzyc/formats/fll.py", line 99, in _term\n'
            '  File "/w/.venv/lib/python3.11/site-packages/numpy/core/x.py", line 5, in f\n'
            'ValueError: bad\n')
    kind, signature = classify(Run(["check"], None, "", error=text), TARGET, tmp_path)
    assert (kind, signature) == ("traceback", "check: ValueError at fuzzyc/formats/fll.py:_term")


def test_the_summary_gives_inputs_exit_codes_tracebacks_and_unlocated():
    from collections import Counter
    from tests.fuzz.__main__ import summary
    from tests.fuzz.runner import Tally
    a = Tally("fz", inputs=3, commands=Counter(check=3, eval=1),
              exit_codes=Counter({"0": 1, "2": 2, "exception": 1}),
              failures=Counter({("traceback", "check: ValueError at x"): 1}), cpu=2.0)
    b = Tally("csv", inputs=2, commands=Counter(eval=2), exit_codes=Counter({"2": 1, "70": 1}),
              failures=Counter({("unlocated", "eval: error"): 1}), cpu=1.5)
    assert summary({"fz": a, "csv": b}, 12.3).splitlines() == [
        "inputs tried: 5 (6 commands, 0 also through the console script; 12 s wall, 4 CPU s)",
        "exit codes: 0: 1, 2: 3, 70: 1, exception: 1",     # 2: two of fz's and one of csv's
        "tracebacks: 1",
        "rejections without file:line:col: 1",
        "other failures: nonfinite 0, over-bound 0, subprocess 0"]


def test_the_console_script_runs_on_the_folder_as_it_was(tmp_path):
    # `examples DIR` refuses to overwrite: run again after the in-process run, in the same
    # folder, it exited 2 where the in-process run gave 0 (a false `subprocess` failure)
    from tests.fuzz.runner import Tally, _compare_with_console_script, _copy_of, run_in_process
    work = tmp_path / "work"
    work.mkdir()
    before = _copy_of(work)
    run = run_in_process(["examples", str(work / "o")], 60.0)
    assert run.code == 0 and (work / "o" / "rulebases").is_dir()
    tally = Tally("cmdline")
    _compare_with_console_script(tally, run, "ok", work, before, tmp_path / "out", 60.0)
    assert (tally.subprocess_runs, dict(tally.failures)) == (1, {})
    assert not before.exists()          # the copy is removed
