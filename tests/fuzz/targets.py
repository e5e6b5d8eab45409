"""What is fuzzed: each target is a set of seed files, a file suffix and the command lines
that read a mutated file.

- fz, fll, fcl, fis: every shipped rule base and format-corpus file (plus the shipped rule
  bases exported to the other formats), through `check`; a file that passes goes on to `eval
  --csv` over its inputs' ranges and `convert` to another format, now and then `compile`.
- scenario: the shipped scenario YAML files (duration cut to a few periods) through
  `simulate --scenario FILE`, with its rule base or its baseline.
- csv: `eval FILE --csv` with a CSV over the inputs of a shipped or corpus rule file.
- cmdline: argument vectors built from the parser's own options with hostile values.

Generators (tests/fuzz/generate.py: inputs built from the grammars and schemas):
- gen-scenario: a shipped scenario with keys of the schema given hostile YAML values;
- gen-fll, gen-fcl, gen-fis: random rule bases, through the rule targets' commands;
- gen-names: FLL rule bases whose every name is hostile, checked, converted and compiled;
- gen-cli: the cmdline target's argument vectors with numbers spelled every way;
- gen-api: `fuzzyc.evaluate` with values of every numpy dtype and shape (tests/fuzz/api.py).
"""
from __future__ import annotations

import argparse
import contextlib
import importlib.util
import re
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Callable

from hypothesis import strategies as st

from . import generate as gen
from .mutate import HOSTILE, mutated

ROOT = Path(__file__).resolve().parents[2]
RULEBASES = sorted((ROOT / "rulebases").glob("*.fz"))
CORPUS = sorted((ROOT / "tests" / "format_corpus").iterdir())
SHIPPED_SCENARIOS = sorted((ROOT / "plants" / "scenarios").glob("*.yaml"))
# the Gymnasium examples (each run with the rule file beside it) when the extra is installed
GYM_SCENARIOS = sorted((ROOT / "examples" / "gymnasium").glob("*.yaml")) \
    if importlib.util.find_spec("gymnasium") else []
SCENARIOS = SHIPPED_SCENARIOS + GYM_SCENARIOS
RULE_SUFFIXES = (".fz", ".fll", ".fcl", ".fis")
SHORT_RUN = "duration: 0.6\n"   # a handful of periods: the loop and metrics run, quickly


def snapshot() -> dict[Path, bytes]:
    """The shipped files the harness reads: a run must leave them as they were."""
    return {p: p.read_bytes() for p in RULEBASES + CORPUS + SCENARIOS}


def _load(path):
    from fuzzyc.formats import load_any
    return load_any(path)


def _good_rule_files() -> list[Path]:
    return [p for p in RULEBASES + CORPUS
            if p.suffix in RULE_SUFFIXES and not p.name.startswith("bad_")]


def _exports(suffix: str) -> list[str]:
    """The shipped rule bases written in another format (where that format can say them)."""
    from fuzzyc.errors import FuzzycError
    from fuzzyc.formats import WRITERS
    texts = []
    for path in RULEBASES:
        try:
            texts.append(WRITERS[suffix](_load(path), []))
        except FuzzycError:
            pass
    return texts


def _csv_over_range(model, core: bool = False) -> str:
    """A CSV whose columns are the model's inputs (the rule base's with `core`, as `eval
    --core` reads), at the low end, middle and high end of their ranges."""
    inputs = model.rulebase.inputs if core else model.signals
    names = [s.name for s in inputs]
    # lo*(1-f) + hi*f: finite for any finite range (hi - lo may overflow)
    rows = [[s.lo * (1 - f) + s.hi * f for s in inputs] for f in (0.0, 0.5, 1.0)]
    return "\n".join([",".join(names)] + [",".join(f"{v:g}" for v in row) for row in rows]) + "\n"


@dataclass
class Target:
    """name; seeds (texts); suffix of the mutated file; commands(draw, file, tmp, seed index)
    -> argument vectors, each run only while the previous ones exit 0."""
    name: str
    suffix: str
    make_seeds: Callable[[], list[tuple[str, object]]]
    commands: Callable
    located: bool = True     # an exit-2 message must carry file:line:col
    # (seed text, all seed texts) -> strategy of the input's bytes: a mutation, or a generator
    strategy: Callable = mutated
    run: Callable | None = None      # (argv, seconds) -> Run; None: `fuzzyc` in-process
    reproduce: str = "fuzzyc"

    @cached_property
    def seeds(self) -> list[tuple[str, object]]:
        return self.make_seeds()

    @property
    def generated(self) -> bool:
        return self.strategy is not mutated

    def input_strategy(self):
        """(index of the seed, the input file's bytes)."""
        texts = tuple(text for text, _ in self.seeds)
        return st.integers(0, len(texts) - 1).flatmap(
            lambda i: st.tuples(st.just(i), self.strategy(texts[i], texts)))


def _rule_seeds(suffix: str):
    def make():
        own = [(p.read_text(encoding="utf-8"), p) for p in RULEBASES + CORPUS
               if p.suffix == suffix]
        return own + ([] if suffix == ".fz" else [(t, None) for t in _exports(suffix)])
    return make


def _rule_commands(draw, path: Path, tmp: Path, _context) -> list[list[str]]:
    def more():
        from fuzzyc.errors import FuzzycError
        try:
            model = _load(path)   # `check` passed, so this loads
        except FuzzycError:
            if path.suffix != ".fcl":
                raise
            # `check` reads an .fcl whole: several FUNCTION_BLOCKs, blocks without outputs
            # (jFuzzyLogic's files); the other commands take one block with outputs and
            # refuse the file with a located message
            return [["eval", str(path)], ["convert", str(path), str(tmp / "converted.fz")]]
        table = tmp / "points.csv"
        table.write_text(_csv_over_range(model), encoding="utf-8")
        other = draw(st.sampled_from(RULE_SUFFIXES))
        argvs = [["eval", str(path), "--csv", str(table)],
                 ["convert", str(path), str(tmp / f"converted{other}")]]
        if draw(st.integers(0, 7)) == 0:
            argvs.append(["compile", str(path), "-o", str(tmp / "c"),
                          "--numeric", draw(st.sampled_from(("float", "q15")))])
        return argvs
    return [["check", str(path)], more]


def _scenario_seeds():
    # a metric judged `after: T` seconds needs a run that long: judged from the start instead
    return [(re.sub(r"(?m)^duration:.*\n", SHORT_RUN,
                    re.sub(r"\bafter: [0-9.]+, ", "", p.read_text(encoding="utf-8"))), p)
            for p in SCENARIOS]


def _scenario_commands(draw, path: Path, tmp: Path, context: Path) -> list[list[str]]:
    beside = context.with_suffix(".fz")      # a scenario that names no rule base has one there
    argv = ["simulate", *([str(beside)] if beside.exists() else []),
            "--scenario", str(path), "-o", str(tmp / "sim")]
    has_baseline = re.search(r"(?m)^baseline:", context.read_text(encoding="utf-8"))
    return [argv + (["--baseline"] if has_baseline and draw(st.booleans()) else [])]


def _csv_seeds():
    from fuzzyc.errors import FuzzycError
    seeds = []
    for path in _good_rule_files():
        for core in (False, True):
            # a several-block FCL needs ::NAME; --core reads a one-block model only
            with contextlib.suppress(FuzzycError):
                seeds.append((_csv_over_range(_load(path), core), (path, core)))
    return seeds


def _csv_commands(_draw, path: Path, tmp: Path, context) -> list[list[str]]:
    rule_file, core = context
    return [["eval", str(rule_file), "--csv", str(path)] + (["--core"] if core else [])]


# Options whose value is a path the command writes: always a name inside the run's folder.
OUTPUT_DESTS = {"out", "output", "report", "plot", "folder"}
# Options that set how much work a run does: bounded, a huge batch would exhaust the memory.
# --workers only below 1 (refused): a local Dask cluster is processes outside the CPU limit
# (tests/test_campaign.py runs them); --chunk in-process is fuzzed.
WORK_BOUNDS = {"batch": 64, "cycles": 2, "max_examples": 5, "resolution": 200, "chunk": 64,
               "workers": 0}
# Not fuzzed: a scheduler address connects to the network; --prove computes reachable sets
# over a shipped loop's whole horizon, minutes by design (EDM gap: 531 s; `make proofs` and
# tests/test_verify_reach.py run it, its bad values are usage errors in tests/test_cli_errors.py).
NOT_FUZZED = {"scheduler", "prove"}
# Put first, so a fuzzed value of the same option overrides them: the defaults run for minutes
# (a 3400 s closed loop per verify example, a long scenario).
SHORT_WORK = {"simulate": ["--set", "duration=0.6"], "learn": ["--set", "duration=0.6"],
              "verify": ["--max-examples", "2"]}


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    from fuzzyc.cli import build_parser
    parser = build_parser()
    # argparse keeps the subparsers in a private action; this harness reads them to fuzz
    # every option the CLI has, including ones added later.
    return next(a for a in parser._actions
                if isinstance(a, argparse._SubParsersAction)).choices


def _learns_first(path: Path) -> bool:
    """A rule base whose closed-loop properties train it first (`set learn.cycles = 15`):
    25 CPU s whatever --max-examples says, by design (tested in tests/, not fuzzed)."""
    return re.search(r"(?m)^\s*set learn\.", path.read_text(encoding="utf-8")) is not None


@st.composite
def _option_value(draw, action: argparse.Action, tmp: Path, generated: bool = False):
    if generated and action.dest not in OUTPUT_DESTS:
        value = _generated_value(draw(gen.rng()), action)
        if value is not None:
            return value
    if action.dest in OUTPUT_DESTS:
        name = draw(st.sampled_from(("o", "o.png", "o.fll", "o.fz", "o.txt", "", ".", "a/b",
                                     "é.fis", "x" * 300)))
        return str(tmp / name)
    if action.dest in WORK_BOUNDS:
        return str(draw(st.integers(-2, WORK_BOUNDS[action.dest])))
    if action.choices:
        valid = st.sampled_from(list(action.choices))
    elif action.type is int:
        valid = st.integers(-3, 100).map(str)
    elif action.type is float:
        valid = st.sampled_from(("0.1", "1", "0", "-1", "1e9", "nan", "inf"))
    elif action.dest == "scenario":
        valid = st.sampled_from([p.stem for p in SHIPPED_SCENARIOS] + [str(p) for p in SCENARIOS])
    elif action.dest == "files":        # verify's
        valid = st.sampled_from([str(p) for p in RULEBASES + CORPUS if not _learns_first(p)])
    elif action.dest in ("file", "input"):
        valid = st.sampled_from([str(p) for p in RULEBASES + CORPUS])
    else:                                   # NAME=VALUE pairs (eval values, --set, --at)
        valid = st.from_regex(r"[a-zA-Z_.]{1,12}=-?[0-9.e]{0,6}", fullmatch=True)
    hostile = st.one_of(st.sampled_from(HOSTILE), st.text(max_size=10))
    return draw(st.one_of(valid, valid, valid, valid, hostile))


# the dotted keys `--set` reaches (plants/scenario.py: `plant.X` falls through to plant.params)
SET_KEYS = ("title", "duration", "period", "plant", "plant.model", "plant.params",
            "plant.gain", "plant.dead_time", "plant.params.gain", "plant.randomize.gain",
            "controller", "controller.rulebase", "controller.params.GU", "controller.expose",
            "baseline", "baseline.make", "baseline.params.Kp", "observers", "observers.0.make",
            "schedules", "schedules.r", "schedules.disturbance", "metrics", "metrics.0.band",
            "metrics.0.name", "plots", "notes", "initial.y", "x", "plant..gain", ".", "",
            "plant.params.gain.x", "metrics.99.band", "metrics.-1.band", "a" * 300)
INTEGER_TYPES = ("int", "integer", "at_least", "batch_size")


def _generated_value(rnd, action: argparse.Action) -> str | None:
    """A hostile value of the option's kind; None: let the cmdline target's choice stand."""
    kind = getattr(action.type, "__name__", "")
    if action.dest in WORK_BOUNDS or kind in INTEGER_TYPES or action.type is int:
        # in range only up to the work bound: a valid big value is work, not a bug
        return gen.integer_spelling(rnd, WORK_BOUNDS.get(action.dest, 100))
    if action.type is float or kind in ("finite", "non_negative"):
        return rnd.choice(gen.HOSTILE_NUMBERS + ("0.5", "1", "1e-300", "-1"))
    if action.dest in ("set", "sets"):
        return f"{rnd.choice(SET_KEYS)}={gen.yaml_value(rnd)}"
    if action.dest in ("values", "at", "inputs") and not action.choices:
        return f"{gen.name(rnd)}={gen.number(rnd, -100, 100)}"
    if action.dest == "allow_import":
        return rnd.choice(gen.MAKES + gen.HOSTILE_NAMES)
    return None


@st.composite
def _argv(draw, tmp: Path, generated: bool = False) -> list[str]:
    """A subcommand with its positionals, its required options and up to three others, in a
    random order; one value in five hostile (more and nearly every line is a usage error)."""
    commands = _subcommands()
    name = draw(st.sampled_from(sorted(commands)))
    actions = [a for a in commands[name]._actions
               if not isinstance(a, argparse._HelpAction) and a.dest not in NOT_FUZZED]
    optional = [a for a in actions if a.option_strings and not a.required]
    chosen = [a for a in actions if a not in optional] + draw(
        st.lists(st.sampled_from(optional), max_size=3, unique_by=id) if optional else st.just([]))
    order = draw(st.permutations(chosen))
    # positionals keep their own order (argparse assigns them by position: `convert OUT IN`
    # would overwrite a shipped file), options go anywhere around them
    positionals = iter([a for a in chosen if not a.option_strings])
    words = []
    for action in (a if a.option_strings else next(positionals) for a in order):
        value = [] if action.nargs == 0 else [draw(_option_value(action, tmp, generated))]
        words.append(value if not action.option_strings else
                     [draw(st.sampled_from(action.option_strings)), *value])
    return [name, *SHORT_WORK.get(name, []), *(w for group in words for w in group)]


def _cmdline_commands(draw, _path: Path, tmp: Path, _context) -> list[list[str]]:
    return [draw(_argv(tmp))]


def _generated_cmdline(draw, _path: Path, tmp: Path, _context) -> list[list[str]]:
    return [draw(_argv(tmp, generated=True))]


def _generated_scenario(text: str, _texts):
    import yaml
    base = yaml.safe_load(text)
    return gen.rng().map(lambda rnd: gen.scenario_text(rnd, base).encode("utf-8"))


def _generated_scenario_commands(draw, path: Path, tmp: Path, _context) -> list[list[str]]:
    extra = draw(st.sampled_from(([], [], ["--baseline"], ["--batch", "2"])))
    return [["simulate", "--scenario", str(path), "-o", str(tmp / "sim"), *extra]]


def _generated_rules(suffix: str, names: bool = False):
    def strategy(_text, _texts):
        def build(rnd):
            rb = gen.rulebase(rnd, names=names or rnd.random() < 0.2)
            return gen.RULE_WRITERS[suffix](rb, rnd).encode("utf-8", "surrogatepass")
        return gen.rng().map(build)
    return strategy


def _names_commands(draw, path: Path, tmp: Path, _context) -> list[list[str]]:
    """`check`, then what writes the names elsewhere: every format, C (float, q15) and LUT."""
    def more():
        model = _load(path)
        table = tmp / "points.csv"
        table.write_text(_csv_over_range(model), encoding="utf-8")
        other = draw(st.sampled_from(RULE_SUFFIXES))
        target = draw(st.sampled_from((["--numeric", "float"], ["--numeric", "q15"],
                                       ["--target", "lut"])))
        return [["eval", str(path), "--csv", str(table)],
                ["convert", str(path), str(tmp / f"converted{other}")],
                ["compile", str(path), "-o", str(tmp / "c"), *target]]
    return [["check", str(path)], more]


API_MODELS = ("tests/format_corpus/tipper.fll", "tests/format_corpus/sugeno.fis",
              "tests/format_corpus/shapes_tsk.fll", "rulebases/fopdt_pi.fz")


def _api_commands(draw, _path: Path, _tmp: Path, _context) -> list[list[str]]:
    call = draw(st.sampled_from(("evaluate", "evaluate", "evaluate", "explain")))
    model = draw(st.sampled_from(API_MODELS))
    return [[call, str(ROOT / model), str(draw(st.integers(0, 2 ** 63 - 1)))]]


def _api_run(argv, seconds):
    from .api import run
    return run(argv, seconds)


TARGETS = {t.name: t for t in (
    Target("fz", ".fz", _rule_seeds(".fz"), _rule_commands),
    Target("fll", ".fll", _rule_seeds(".fll"), _rule_commands),
    Target("fcl", ".fcl", _rule_seeds(".fcl"), _rule_commands),
    Target("fis", ".fis", _rule_seeds(".fis"), _rule_commands),
    Target("scenario", ".yaml", _scenario_seeds, _scenario_commands),
    Target("csv", ".csv", _csv_seeds, _csv_commands),
    # command lines name valid files: a rejection is about an argument, which has no line
    Target("cmdline", ".txt", lambda: [("", None)], _cmdline_commands, located=False),
    Target("gen-scenario", ".yaml", lambda: [(text, None) for text, _ in _scenario_seeds()
                                             if "gymnasium" not in text],
           _generated_scenario_commands, strategy=_generated_scenario),
    Target("gen-fll", ".fll", lambda: [("", None)], _rule_commands,
           strategy=_generated_rules(".fll")),
    Target("gen-fcl", ".fcl", lambda: [("", None)], _rule_commands,
           strategy=_generated_rules(".fcl")),
    Target("gen-fis", ".fis", lambda: [("", None)], _rule_commands,
           strategy=_generated_rules(".fis")),
    Target("gen-names", ".fll", lambda: [("", None)], _names_commands,
           strategy=_generated_rules(".fll", names=True)),
    Target("gen-cli", ".txt", lambda: [("", None)], _generated_cmdline, located=False,
           strategy=lambda _t, _ts: st.just(b"")),
    # an API rejection names the input instead of a line (api.run judges it)
    Target("gen-api", ".txt", lambda: [("", None)], _api_commands,
           strategy=lambda _t, _ts: st.just(b""), run=_api_run,
           reproduce="python -m tests.fuzz.api"),
)}
# Share of the inputs per target (the .fz language has the most to break; a quarter goes to
# the generators, which cost more per input than most mutations: a generated
# scenario or command line runs a simulation more often).
SHARES = {"fz": 0.24, "fll": 0.09, "fcl": 0.09, "fis": 0.09, "scenario": 0.06, "csv": 0.08,
          "cmdline": 0.12, "gen-scenario": 0.04, "gen-fll": 0.04, "gen-fcl": 0.04,
          "gen-fis": 0.04, "gen-names": 0.03, "gen-cli": 0.03, "gen-api": 0.04}
