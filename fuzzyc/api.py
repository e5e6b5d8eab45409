"""The public Python API (re-exported by `fuzzyc`; documented in docs/api.md).

Every function here is what a `fuzzyc` command does, without the printing: the command
modules in `fuzzyc.cli` call these. Bad input raises `FuzzycError` (its diagnostics carry
file:line:col); a misnamed or missing input raises `KeyError`, a bad argument `ValueError`.
"""
from __future__ import annotations

import os
import shutil
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .atomic import atomic_path, write_text
from .engine.chain import Controller
from .engine.inference import Explanation
from .errors import FuzzycError
from .language.model_builder import ModelBuilder
from .semantics.model import Model
from .language.numbers import real_array

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from fuzzyc.runtime.campaign import Cluster
    from fuzzyc.runtime.trace import Trace
    from .backends.c.load import CompiledEvaluator
    from .verifier.report import VerifyReport

__all__ = ["Controller", "Explanation", "FuzzycError", "Header", "Learning", "Model",
           "ModelBuilder", "Simulation", "compile_c", "compile_lut", "compiled_evaluator",
           "copy_examples", "evaluate", "example", "examples", "explain", "learn", "load",
           "parse", "plot", "save", "simulate", "tune", "verify"]

PathLike = str | os.PathLike


# -- reading and writing rule bases ---------------------------------------------------------

def load(path: PathLike) -> Model:
    """The model in a .fz, .fll, .fcl or .fis file (by extension); `FILE.fcl::NAME` reads the
    FUNCTION_BLOCK NAME of an FCL file that has several."""
    from .formats import load_any
    return load_any(os.fspath(path))


def parse(text: str, format: str = "fz", name: str = "<string>") -> Model:
    """The model in `text`, written in `format` (fz, fll, fcl or fis); `name` is the file name
    diagnostics show."""
    from .formats import READERS
    suffix = "." + format.lower().lstrip(".")
    if suffix == ".fz":
        from .language.parser import parse as parse_fz
        return parse_fz(text, name)
    if suffix not in READERS:
        raise ValueError(f"unknown format `{format}` (known: fz fll fcl fis)")
    return READERS[suffix](text, name)


def save(model: Model, path: PathLike) -> list[str]:
    """Write the model as .fz, .fll, .fcl or .fis (by extension), atomically. Returns warnings
    naming what the format cannot carry (the bare rule base is still written)."""
    from .formats import save as save_any
    return save_any(model, os.fspath(path))


# -- evaluation -------------------------------------------------------------------------------

def evaluate(model: Model, inputs: Mapping[str, Any]) -> dict[str, np.ndarray]:
    """The rule base alone (no signal chain, no state) on a batch: one array (or number) per
    rule-base input, broadcast together; one float array of that shape per rule-base output."""
    from .engine.inference import evaluate as engine_evaluate
    rb = model.rulebase
    names = [v.name for v in rb.inputs]
    _check_names(model, inputs, names)
    arrays = [real_array(n, inputs[n]) for n in names]
    try:
        columns = np.broadcast_arrays(*arrays)
    except ValueError:       # numpy's message names no input
        shapes = ", ".join(f"{n} {a.shape}" for n, a in zip(names, arrays))
        raise ValueError(f"the inputs' shapes do not broadcast together: {shapes}") from None
    shape = columns[0].shape if columns else ()
    x = np.column_stack([c.ravel() for c in columns]) if columns else np.empty((1, 0))
    y = engine_evaluate(rb, x)
    return {v.name: y[:, o].reshape(shape) for o, v in enumerate(rb.outputs)}


def explain(model: Model, point: Mapping[str, float]) -> Explanation:
    """Why the rule base gives its outputs at one point of its inputs: the memberships, the
    rules that fired (strongest first) and the outputs. `str()` of it is a readable table."""
    from .engine.inference import explain as engine_explain
    names = [v.name for v in model.rulebase.inputs]
    _check_names(model, point, names)
    values = [real_array(n, point[n]) for n in names]
    arrays = [n for n, v in zip(names, values) if v.ndim]
    if arrays:
        raise ValueError(f"explain takes one point: a number per input, not arrays "
                         f"(given for {', '.join(arrays)})")
    return engine_explain(model.rulebase, np.array([float(v) for v in values]))


def _check_names(model: Model, given: Mapping[str, Any], names: list[str]) -> None:
    if not isinstance(given, Mapping):
        raise TypeError(f"{model.name}: the inputs must be a mapping of the rule base's inputs "
                        f"({', '.join(names)}) to values, not {type(given).__name__}")
    unknown = [n for n in given if n not in names]
    missing = [n for n in names if n not in given]
    if unknown or missing:
        raise KeyError(f"{model.name}: the rule base's inputs are {', '.join(names)}"
                       + (f"; unknown: {', '.join(map(str, unknown))}" if unknown else "")
                       + (f"; missing: {', '.join(missing)}" if missing else ""))


# -- code generation --------------------------------------------------------------------------

@dataclass
class Header:
    """A generated C header: its file name, its text and, for a lookup table, the largest
    difference from the engine found per rule-base output."""
    filename: str
    text: str
    max_error: dict[str, float] | None = None

    def write(self, folder: PathLike = ".") -> Path:
        """Write it into folder (atomically); returns its path."""
        path = Path(folder) / self.filename
        write_text(path, self.text)
        return path


def compile_c(model: Model, numeric: str = "float") -> Header:
    """The whole controller (signal chain, rule base, outputs) as a self-contained C99 header:
    NAME.h for numeric float or double, NAME_q15.h / NAME_q31.h for fixed point."""
    from .backends.c.header import generate_header
    from .escape import c_identifier
    name = c_identifier(model.name)
    if numeric in ("q15", "q31"):
        from .backends.c_fixed.header import generate_fixed_header
        return Header(f"{name}_{numeric}.h", generate_fixed_header(model, numeric))
    if numeric not in ("float", "double"):
        raise ValueError(f"numeric is one of float, double, q15, q31, not `{numeric}`")
    return Header(f"{name}.h", generate_header(model, numeric))


def compiled_evaluator(model: Model, numeric: str = "double") -> "CompiledEvaluator":
    """The rule base alone at one point, as the generated C header (`numeric` float or double)
    computes it, called through ctypes: `f(values)` takes a float per rule-base input in order
    and returns a list of the outputs.  About a microsecond a call, where `evaluate` pays
    numpy's fixed cost (tens of microseconds) at batch 1.  Needs gcc on the PATH."""
    from .backends.c.load import CompiledEvaluator
    return CompiledEvaluator(model, numeric)


def compile_lut(model: Model, resolution: int = 33) -> Header:
    """The rule base (its rule blocks in order, as one function) sampled on `resolution`
    points per input, read by multilinear interpolation: NAME_lut.h, with the measured
    interpolation error."""
    from .escape import c_identifier
    from .backends.lut import LookupTable, generate_lut_header
    table = LookupTable(model, resolution)
    error = table.measure_error()
    return Header(f"{c_identifier(model.name)}_lut.h", generate_lut_header(model, table, error),
                  {v.name: float(e) for v, e in zip(table.outputs, error)})


# -- tuning -----------------------------------------------------------------------------------

def tune(model: Model | PathLike, data: PathLike | None = None, *,
         validate: PathLike | None = None, folds: int | None = None, seed: int = 0,
         passes: int = 20, max_nfev: int | None = None, **closed_loop: Any) -> Any:
    """Fit the numbers a .fz file's `tune` section frees to the CSV `data` (docs/tuning.md);
    `validate` (a CSV) or `folds` (K-fold cross-validation) measure the error elsewhere.
    Or against a closed loop: `scenario=NAME, minimize=METRIC` instead of data, with the
    options of fuzzyc.tune.tune (sets, limits, batch, randomize, method, max_evaluations,
    max_examples, prove, prove_boxes, scenarios, and `cluster`: a
    fuzzyc.runtime.campaign.Cluster that runs each cost's loops in chunks on Dask, with the
    same numbers). Returns a fuzzyc.tune.TuneResult: `.text` is the tuned file, `.fit` the
    numbers, errors (or costs) and properties before and after."""
    from .tune import tune as run
    return run(model, data, validate=validate, folds=folds, seed=seed, passes=passes,
               max_nfev=max_nfev, **closed_loop)


# -- verification and simulation -------------------------------------------------------------

def verify(model: Model | PathLike, *, max_examples: int = 100, seed: int = 0,
           backend: str = "numpy", only: str | None = None,
           report_dir: PathLike | None = None,
           progress: Callable[[str], None] | None = None,
           cluster: Cluster | None = None, prove: bool = False,
           prove_boxes: int = 64, noise_sigmas: float = 0.0,
           allow_import: Sequence[str] = (),
           scenarios: Mapping[str, PathLike | Mapping[str, Any]] | None = None
           ) -> VerifyReport:
    """Check every property of a model (or of the file at that path); a model that declares
    none gets the structural defaults. `only` keeps the properties whose text contains it;
    `report_dir` receives the plots of closed-loop counterexamples; `progress` is called with
    each property's text before it is checked; `cluster` (fuzzyc.runtime.campaign.Cluster) checks
    the closed-loop cases in chunks, on Dask with workers or a scheduler (docs/campaigns.md).
    `prove`: closed loops get sound reachable sets first (docs/proofs.md), split into at most
    `prove_boxes` boxes, Gaussian plant noise covered to `noise_sigmas` standard deviations
    (0: not at all). `allow_import`: modules of yours the closed loops' scenarios may import
    (a Gymnasium `env: module:Class`; docs/security.md): a scenario file alone imports none.
    `scenarios`: your own loops, by the name a `closed_loop` gives: a scenario YAML path, or
    the mapping such a file holds, whose `plant` may be your plant object (INPUTS, OUTPUTS,
    params, initial_state, step; with set_step the proof runs too: docs/verification.md)."""
    from .verifier import Options, verify_model
    from .verifier.report import VerifyReport
    if not isinstance(model, Model):
        model = load(model)
    _check_loop_names(model, scenarios or {})
    options = Options(backend=backend, max_examples=max_examples, seed=seed,
                      report_dir=None if report_dir is None else str(report_dir), only=only,
                      progress=progress, cluster=cluster, prove=prove,
                      prove_boxes=prove_boxes, noise_sigmas=noise_sigmas,
                      allow_import=tuple(_modules(allow_import)),
                      scenarios=dict(scenarios or {}))
    return VerifyReport(verify_model(model, options))


def _check_loop_names(model: Model, scenarios: Mapping[str, Any]) -> None:
    """Each name of `scenarios` is one a closed_loop of the model uses: a misspelt one would
    leave that loop on the shipped scenario of its name, unnoticed."""
    if not isinstance(scenarios, Mapping):
        raise TypeError(f"scenarios maps a closed_loop's scenario name to a scenario, not "
                        f"{type(scenarios).__name__}")
    used = sorted({p.args["scenario"] for p in model.properties if p.kind == "closed_loop"})
    unknown = [name for name in scenarios if name not in used]
    if unknown:
        raise KeyError(f"{model.name}: no closed_loop names the scenario `{unknown[0]}`; "
                       f"its closed loops name: {', '.join(used) or 'none'}")


@dataclass
class Simulation:
    """A closed-loop run: the trace (`trace.time` (T,), `trace[signal]` (T, batch)) and the
    scenario's metrics, label -> {mean, min, max, unit} over the batch."""
    scenario: Any
    trace: Trace
    metrics: dict[str, dict[str, Any]]

    def __repr__(self) -> str:          # the run and its metrics, not 28,000 characters of arrays
        from .display import simulation_text
        return simulation_text(self)

    def _repr_html_(self) -> str:       # Jupyter: a table of the metrics
        from .display import simulation_html
        return simulation_html(self)


def simulate(scenario: PathLike, rulebase: PathLike | None = None, *, batch: int = 1,
             settings: Mapping[str, Any] | None = None, baseline: bool = False,
             randomize: bool = False, backend: str = "numpy", seed: int = 0,
             pace: str = "sim", progress: bool | None = False,
             cluster: Cluster | None = None, semantics: str = "exact",
             allow_import: Sequence[str] = ()) -> Simulation:
    """Run a scenario (a shipped name such as "wedm_rough" or a YAML path) with its own rule
    base or the rule file `rulebase` (any format `load` reads); `settings` overrides scenario keys, dotted as in
    `fuzzyc simulate --set` ({"duration": 2, "plant.tension": 800}); `baseline` runs the
    scenario's baseline controller instead; `randomize` draws each loop's plant params;
    `pace="wall"` runs in real time (one period per period); `progress` shows a progress line
    on stderr (None: when it is a terminal). `cluster` (fuzzyc.runtime.campaign.Cluster) runs
    the loops in chunks, on Dask with workers or a scheduler, with the same numbers; then
    `trace` holds the first 20 loops and `metrics` are over all of them (docs/campaigns.md).
    `semantics`: a source tool's arithmetic (docs/formats.md). `allow_import`: modules of
    yours the scenario may import (a Gymnasium `env: module:Class`, docs/security.md); the
    plants, baselines and observers a scenario names otherwise come from
    fuzzyc.plants.registry, and a scenario file alone imports nothing."""
    from fuzzyc.plants.scenario import load as load_scenario
    from fuzzyc.runtime.simulate import simulate as run_scenario, summarize
    from .language.limits import MAX_BATCH
    # before the scenario allocates anything (--batch 3e7 took 2 GB before failing)
    if isinstance(batch, bool) or not isinstance(batch, (int, np.integer)) \
            or not 1 <= batch <= MAX_BATCH:
        raise ValueError(f"batch must be a whole number of loops from 1 to {MAX_BATCH:,} "
                         f"(fuzzyc.language.limits.MAX_BATCH), not {batch!r}")
    overrides = dict(settings or {})
    if rulebase is not None:
        from .formats import absolute_ref
        overrides["controller.rulebase"] = absolute_ref(os.fspath(rulebase))
    loaded = load_scenario(scenario, overrides, allow_import=_modules(allow_import))
    if cluster is not None:
        from fuzzyc.runtime.campaign import simulate_campaign
        campaign = simulate_campaign(loaded, batch, cluster, baseline=baseline, backend=backend,
                                     seed=seed, randomize=randomize, pace=pace)
        return Simulation(loaded, campaign.trace, campaign.summary)
    trace = run_scenario(loaded, batch=batch, baseline=baseline, backend=backend, seed=seed,
                         randomize=randomize, progress=progress, pace=pace,
                         semantics=semantics)
    return Simulation(loaded, trace, summarize(loaded, trace))


def _modules(allow_import: Sequence[str] | str) -> list[str]:
    """allow_import as a list (one name given as a string is one module, not its letters)."""
    return [allow_import] if isinstance(allow_import, str) else list(allow_import or ())


# -- learning and pictures ------------------------------------------------------------------

@dataclass
class Learning:
    """What `learn` gives: the model with the learned table, its .fz text (the first line says
    how it was learned), the performance index per cycle and each cycle's run
    (`fuzzyc.learning.CycleResult`: pi, time, finished, trace)."""
    model: Model
    text: str
    table: str
    pi: np.ndarray
    cycles: list[Any]
    scenario: str

    def write(self, path: PathLike) -> Path:
        """The learned rule file at path (atomically); returns the path."""
        write_text(path, self.text)
        return Path(path)

    def __repr__(self) -> str:
        from .display import learning_text
        return learning_text(self)


def learn(rulebase: PathLike, scenario: PathLike, *, cycles: int = 15, eta: float = 0.25,
          rho: float = 6.0, table: str = "du",
          settings: Mapping[str, Any] | None = None) -> Learning:
    """What `fuzzyc learn` does, without writing: the weights of the rule file's `learnable`
    table (output `table`) learned on line over `cycles` runs of the scenario's cutting cycle
    (a shipped name or a YAML path; `settings` overrides its keys as in `simulate`), with
    learning rate `eta` and `rho` the weight of cf^2 in the performance index (fuzzyc/learning.py
    gives the rule). `Learning.write(path)` writes the learned file."""
    from fuzzyc.plants.scenario import load as load_scenario
    from .cli.learn import check_learnable
    from .formats import absolute_ref
    from .learning import learn_scenario, provenance, trained_text
    from .language.parser import parse as parse_fz
    if isinstance(cycles, bool) or not isinstance(cycles, (int, np.integer)) or cycles < 1:
        raise ValueError(f"cycles is a whole number of at least 1, not {cycles!r}")
    path = os.fspath(rulebase)
    check_learnable(path, table)
    loaded = load_scenario(scenario, dict(settings or {}))
    loaded.data.setdefault("controller", {})["rulebase"] = absolute_ref(path)
    controller, result = learn_scenario(loaded, cycles, eta, rho, table)
    text = trained_text(controller.model, result.weights, table, provenance(
        Path(path).name, loaded.name, cycles, eta, rho, result.pi))
    return Learning(parse_fz(text, path), text, table, result.pi, result.cycles, loaded.name)


def plot(subject: Model | PathLike | Simulation | Learning | VerifyReport, *,
         point: Mapping[str, float] | None = None, inputs: Sequence[str] | None = None,
         at: Mapping[str, float] | None = None, compare: Simulation | None = None,
         out_dir: PathLike | None = None) -> dict[str, Figure]:
    """The pictures of a model (or of the rule file at that path), a simulation, a learning
    run or a verify report, as matplotlib Figures by name; with `out_dir` also written there as
    NAME.png (atomically). docs/plots.md says what each shows.

    - a model: what `fuzzyc plot` draws (MODEL_VAR_terms per variable, MODEL_OUT_surface over
      the two rule-base `inputs` (default the last two), MODEL_OUT_surface_raw over the raw
      inputs), `at` holding the other inputs by name; with `point` (a value per rule-base
      input) the rule viewer of `fuzzyc eval --plot` instead, MODEL_rules;
    - a Simulation: `trace`, the scenario's panels (`fuzzyc simulate`); `compare` draws a
      second run (e.g. `simulate(..., baseline=True)`) on the same panels;
    - a Learning: `pi`, the performance index per cycle (`fuzzyc learn`);
    - a VerifyReport: one figure per closed-loop counterexample, by property name.
    The figures are closed to pyplot (no window, no pile-up); `fig.savefig` still works."""
    from . import plotting
    from .verifier.report import VerifyReport
    if isinstance(subject, Simulation):
        figures = {"trace": _trace_figure(subject, compare)}
    elif isinstance(subject, Learning):
        figures = {"pi": plotting.draw_learning(
            subject.pi, f"{subject.model.name} on {subject.scenario}")}
    elif isinstance(subject, VerifyReport):
        from .verifier.report import counterexample_figures
        figures = counterexample_figures(subject.results)
    else:
        model = subject if isinstance(subject, Model) else load(subject)
        figures = (_rule_view(model, point) if point is not None else plotting.draw_model(
            model, None if inputs is None else _two_inputs(model, inputs), dict(at or {})))
    plotting.release(figures.values())
    if out_dir is not None:
        from .escape import OutputFolder
        folder = OutputFolder(out_dir)
        for name, fig in figures.items():
            plotting.save(fig, folder.file(name, ".png"))
    return figures


def _two_inputs(model: Model, inputs: Sequence[str]) -> tuple[str, str]:
    names = [v.name for v in model.rulebase.inputs]
    chosen = tuple(inputs)
    if len(chosen) != 2 or any(n not in names for n in chosen):
        raise ValueError(f"inputs are two of {', '.join(names)}, not {chosen!r}")
    return chosen  # type: ignore[return-value]


def _rule_view(model: Model, point: Mapping[str, float]) -> dict[str, Figure]:
    from .ruleview import draw_rule_view
    names = [v.name for v in model.rulebase.inputs]
    _check_names(model, point, names)
    return {f"{model.name}_rules": draw_rule_view(
        model, {n: float(real_array(n, point[n])) for n in names})}


def _trace_figure(sim: Simulation, compare: Simulation | None) -> Figure:
    from fuzzyc.runtime.plots import draw_runs
    from fuzzyc.runtime.simulate import references, signal_units
    scenario = sim.scenario
    runs = {sim.trace.meta.get("controller", "run"): sim.trace}
    if compare is not None:
        label = compare.trace.meta.get("controller", "compared")
        runs[label if label not in runs else f"{label} (2)"] = compare.trace
    panels = [name for name in scenario.plots if name in sim.trace] or None
    return draw_runs(runs, panels, references(scenario), scenario.title,
                     signal_units(scenario))


# -- the shipped examples ---------------------------------------------------------------------

def _shipped() -> dict[str, list[Path]]:
    """The shipped files by the folder `copy_examples` puts them in."""
    import fuzzyc.rulebases
    from fuzzyc.plants.scenario import SCENARIO_DIR
    rulebases = Path(fuzzyc.rulebases.__file__).resolve().parent
    # examples/ sits beside rulebases/, in the source tree and (as fuzzyc/examples) installed
    c_example = rulebases.parent / "examples" / "c"
    gym_example = rulebases.parent / "examples" / "gymnasium"
    return {"rulebases": sorted(rulebases.glob("*.fz")),
            "scenarios": sorted(SCENARIO_DIR.glob("*.yaml")),
            "c": [c_example / "Makefile", c_example / "main.c"],
            "gymnasium": sorted([*gym_example.glob("*.fz"), *gym_example.glob("*.yaml")])}


def examples() -> list[Path]:
    """Every shipped example file: rule bases, scenarios, the C and Gymnasium examples."""
    return [path for paths in _shipped().values() for path in paths]


def example(name: str) -> Path:
    """The path of one shipped example file by its name, e.g. "wedm_three_region.fz"."""
    found = [path for path in examples() if path.name == name]
    if not found:
        from .errors import suggest
        raise KeyError(f"no shipped example `{name}` — "
                       f"{suggest(name, [p.name for p in examples()])}")
    return found[0]


def copy_examples(destination: PathLike, force: bool = False) -> list[Path]:
    """Copy the shipped examples into destination/rulebases, /scenarios, /c and /gymnasium
    (made when missing); refuses (FuzzycError) to overwrite a file unless force, and a file
    where one of those folders goes. Returns the written paths.

    Each file is written atomically: a symbolic link in the way is replaced, never followed
    (shutil.copyfile followed a dangling one and created its target)."""
    from .errors import Diagnostic
    destination = Path(destination)
    shipped = _shipped()
    for folder in shipped:
        place = destination / folder
        if os.path.lexists(place) and not place.is_dir():
            raise FuzzycError([Diagnostic(None, f"cannot copy the examples into {place}: it is "
                                                "not a folder")])
    plan = [(source, destination / folder / source.name)
            for folder, sources in shipped.items() for source in sources]
    # lexists: a dangling link counts as a file there
    existing = [target for _, target in plan if os.path.lexists(target)]
    if existing and not force:
        raise FuzzycError([Diagnostic(None, f"not overwriting the {len(existing)} example files "
                                            f"already in {destination} (e.g. {existing[0]}): "
                                            "choose another folder, or give --force")])
    for source, target in plan:
        with atomic_path(target) as tmp:
            shutil.copyfile(source, tmp)    # tmp: a new regular file, not a link
    return [target for _, target in plan]
