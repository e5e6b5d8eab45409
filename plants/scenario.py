"""Scenarios: the papers' experiments as YAML files in `plants/scenarios/NAME.yaml`.

Format (every key but `plant` optional):

    title: "WEDM finish cut (Yan & Liao 1998, Table 3 test 1)"
    plant:
      model: wedm_gap                 # a module of fuzzyc.plants, or `gymnasium` with the
                                      # keys of plants/gym_env.py (env, observations, action)
      params: {height: 30, ...}       # fields of the module's params dataclass
      randomize: {tension: 0.05}      # relative std of each param across a batch (when asked)
    controller:
      rulebase: wedm_three_region.fz  # relative to the rulebases folder (or absolute)
      params: {Yr1: 30, GU1: 1.8e-4}  # rule-base params changed before the run
      initial: {feed: 0.3}            # u(-1) of controller outputs
      expose: [e1, e2]                # internal controller signals to record
    baseline:
      make: wedm_gap.VoltageP         # plants.<module>.<callable>(**params) -> a controller
      params: {...}
    observers:                        # blocks run after the plant, before the controller
      - {make: height_estimator.HeightEstimator, params: {...}}
    duration: 300                     # s
    period: 0.04                      # s
    initial: {feed: 0.3}              # signals on the bus before the first period
    schedules:                        # piecewise-constant bus signals: [[t, value], ...]
      Yr2: [[0, 0.40]]
    metrics:                          # see runtime.simulate.METRICS; target: number or signal
      - {name: settling_time, signal: abnormal_ratio, target: Yr2, band: 0.03, smooth: 2}
    plots: [spark_freq, abnormal_ratio, feed]

`load(name_or_path, overrides)` applies `KEY=VALUE` overrides with dotted keys first
(`plant.tension=800` reaches into `plant.params` when `plant` has no key `tension`); values are
read as YAML scalars (numbers, booleans, strings), never evaluated. Mistakes are FuzzycErrors
at the offending key or value (file:line:col); scenario_schema checks the shape on loading.

A scenario is data: the YAML is read within limits (scenario_yaml), and the plant, baseline and
observers it names come from plants/registry.py; a module of the user's (a Gymnasium
environment class) is imported only when `allow_import` (--allow-import) names it.
"""
from __future__ import annotations

import copy
import dataclasses
import inspect
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from fuzzyc.errors import Diagnostic, FuzzycError
from fuzzyc.semantics.model import SourceLoc

from . import gym_env, registry, scenario_yaml

SCENARIO_DIR = Path(__file__).resolve().parent / "scenarios"
RULEBASE_SETTING = "controller.rulebase"    # what FILE on the command line sets
YAML_BREAK = re.compile("\r\n|[\r\n\x85\u2028\u2029]")   # the line breaks YAML counts


def available() -> list[str]:
    """The names of the shipped scenarios."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.yaml"))


def resolve(name_or_path: str | Path) -> Path:
    path = Path(name_or_path)
    # os.path.isfile: False, not an OSError, for a name the system refuses (too long, a NUL)
    if path.suffix in (".yaml", ".yml") and os.path.isfile(path):
        return path
    if str(name_or_path) in available():
        return SCENARIO_DIR / f"{name_or_path}.yaml"
    if path.suffix in (".yaml", ".yml") or len(path.parts) > 1:    # a path, not a shipped name
        what = "not a file" if os.path.lexists(path) else "no such file"
        raise FuzzycError([Diagnostic(None, f"{what}: {name_or_path} (a scenario file; the "
                                            f"shipped scenarios are named without .yaml: "
                                            f"{' '.join(available())})")])
    from fuzzyc.errors import suggest
    raise FuzzycError([Diagnostic(None, f"no scenario `{name_or_path}` — "
                                        f"{suggest(str(name_or_path), available())}")])


class _Marks:
    """Dotted key -> where its key and its value start in the YAML file, (line, col) 1-based,
    from the composed node tree (for messages)."""

    def __init__(self, text: str):
        self.keys: dict[str, tuple[int, int]] = {}
        self.values: dict[str, tuple[int, int]] = {}
        try:
            root = scenario_yaml.compose(text)
        except yaml.YAMLError:
            root = None
        if root is not None:
            self._walk(root, "", set())

    def _walk(self, node, prefix: str, seen: set[int]) -> None:
        if id(node) in seen:     # an alias: walked once, so `&a [*a, *a, ...]` stays linear
            return
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            items = [(key, value, f"{prefix}{key.value}") for key, value in node.value]
        elif isinstance(node, yaml.SequenceNode):
            items = [(item, item, f"{prefix}{i}") for i, item in enumerate(node.value)]
        else:
            return
        for key, value, dotted in items:
            self.keys[dotted] = _position(key.start_mark)
            self.values[dotted] = _position(value.start_mark)
            self._walk(value, dotted + ".", seen)

    def at(self, dotted: str, of_value: bool) -> tuple[int, int]:
        """The place of `dotted`'s value (or key); the nearest enclosing key's if not in the
        file (an override, a default)."""
        table = self.values if of_value else self.keys
        if dotted in table:
            return table[dotted]
        while dotted and dotted not in self.keys:
            dotted = dotted.rpartition(".")[0]
        return self.keys.get(dotted, (1, 1))


def _position(mark) -> tuple[int, int]:
    return mark.line + 1, mark.column + 1


@dataclass
class Scenario:
    name: str
    path: Path
    data: dict
    marks: _Marks = field(repr=False)
    text: str = field(repr=False, default="")
    settings: dict[str, str] = field(default_factory=dict)   # the --set overrides applied
    # modules of the user's that may be imported (--allow-import): never from the file itself
    allow_import: tuple[str, ...] = ()
    # a plant object the user passed from Python (from_mapping): used in place of a module
    own_plant: Any = field(repr=False, default=None)

    # --- plain views of the data -------------------------------------------------------------
    @property
    def title(self) -> str:
        """The file's title, then the settings changed from the command line, so a plot or a
        summary of `--set plant.feed=100` does not pass for the file's own run. (The rule
        file chosen is not repeated here: the summary names the controller.)"""
        changed = [f"{k}={v}" for k, v in self.settings.items() if k != RULEBASE_SETTING]
        title = str(self.data.get("title", self.name))
        return title + (f" [--set {', '.join(changed)}]" if changed else "")

    @property
    def notes(self) -> list[str]:
        """What a reader of the comparison must know (where the baseline is better, say)."""
        notes = self.data.get("notes") or []
        return [notes] if isinstance(notes, str) else [str(n) for n in notes]

    @property
    def duration(self) -> float:
        return float(self.data.get("duration", 60.0))

    @property
    def period(self) -> float:
        return float(self.data.get("period", 0.04))

    @property
    def plant_name(self) -> str:
        return self.data["plant"]["model"]

    @property
    def controller(self) -> dict:
        return self.data.get("controller") or {}

    @property
    def baseline(self) -> dict | None:
        return self.data.get("baseline")

    @property
    def schedules(self) -> dict[str, list[tuple[float, float]]]:
        return {k: [(float(t), float(v)) for t, v in pts]
                for k, pts in (self.data.get("schedules") or {}).items()}

    @property
    def metrics(self) -> list[dict]:
        return list(self.data.get("metrics") or [])

    @property
    def plots(self) -> list[str]:
        return list(self.data.get("plots") or [])

    # --- construction ------------------------------------------------------------------------
    def error(self, dotted: str, message: str, of_value: bool = False) -> FuzzycError:
        """A FuzzycError at the key `dotted` (or, of_value, at its value)."""
        line, col = self.marks.at(dotted, of_value)
        lines = YAML_BREAK.split(self.text)
        source = lines[line - 1] if 1 <= line <= len(lines) else None
        from .scenario_schema import capped    # a key of the file's is any length
        return FuzzycError([Diagnostic(SourceLoc(str(self.path), line, col),
                                       f"`{capped(dotted)}`: {message}", source)])

    def plant_module(self):
        """The plant module of fuzzyc.plants the scenario names, or for `model: gymnasium` a
        GymPlant, which has what a plant module has (plants/gym_env.py); the user's own plant
        object when one was passed (from_mapping)."""
        if self.own_plant is not None:
            return self.own_plant
        if self.plant_name == gym_env.MODEL:
            return gym_env.from_scenario(self)
        try:
            return registry.plant_module(self.plant_name)
        except KeyError:
            raise self.error("plant.model", unknown_plant(self.plant_name)) from None

    def plant_params(self, batch: int = 1, rng: np.random.Generator | None = None,
                     randomize: bool = False):
        """The plant's params dataclass; with randomize, (N,) arrays drawn around each value."""
        module = self.plant_module()
        if isinstance(module, gym_env.GymPlant):
            return module.params
        if self.own_plant is not None:
            return _own_params(self)
        cls = _params_class(self, module)
        given = dict(self.data["plant"].get("params") or {})
        _check_fields(self, cls, given)
        _check_types(self, "plant.params", given,
                     {f.name: f.default for f in dataclasses.fields(cls)})
        try:
            params = cls(**given)
        except (TypeError, ValueError) as exc:
            raise self.error("plant.params", str(exc)) from None
        spread = dict(self.data["plant"].get("randomize") or {}) if randomize else {}
        rng = rng or np.random.default_rng(0)
        for key, rel in spread.items():
            if key not in {f.name for f in dataclasses.fields(cls)}:
                raise self.error(f"plant.randomize.{key}", f"{cls.__name__} has no field `{key}`")
            base = float(getattr(params, key))
            setattr(params, key, base * (1.0 + float(rel) * rng.standard_normal(batch)))
        return params

    def make(self, dotted: str, spec: dict):
        """Instantiate `plants.<module>.<callable>(**params)` named by spec["make"], one of
        registry.BASELINES (dotted "baseline") or registry.OBSERVERS ("observers.N")."""
        kind = "baseline" if dotted == "baseline" else "observer"
        try:
            factory = registry.factory(kind, spec.get("make"))
        except (KeyError, TypeError):        # TypeError: not a string (the API)
            raise self.error(f"{dotted}.make", unknown_factory(kind, spec.get("make")),
                             of_value=True) from None
        given = spec.get("params") or {}
        _check_types(self, f"{dotted}.params", given, _typical_values(factory))
        try:
            return factory(**given)
        except (TypeError, ValueError) as exc:
            raise self.error(f"{dotted}.params", str(exc)) from None

    def rulebase_ref(self) -> str | None:
        """The rule file as fuzzyc.formats.load_any takes it: `rulebase_path()`, with a
        `FILE.fcl::NAME` block choice kept."""
        ref = self.controller.get("rulebase")
        if ref is None:
            return None
        from fuzzyc.formats import split_block
        block = split_block(ref)[1]
        return f"{self.rulebase_path()}" + ("" if block is None else f"::{block}")

    def rulebase_path(self) -> Path | None:
        """The rule file (without a `::NAME` block choice), relative to rulebases/."""
        ref = self.controller.get("rulebase")
        if ref is None:
            return None
        from fuzzyc.formats import split_block
        path = split_block(ref)[0]
        if not path.is_absolute():
            path = Path(__file__).resolve().parents[1] / "rulebases" / path
        try:
            found = path.is_file()
        except OSError as exc:     # a name too long for the file system, ...
            raise self.error("controller.rulebase",
                             f"cannot read {path}: {exc.strerror or exc}") from None
        if not found:
            raise self.error("controller.rulebase", f"no rule base file {path}")
        return path


def _check_fields(scenario, params, given: dict) -> None:
    """Each `plant.params` key a field of the params dataclass (a class or an instance)."""
    names = {f.name for f in dataclasses.fields(params)}
    name = params.__name__ if isinstance(params, type) else type(params).__name__
    for key in given:
        if key not in names:
            from fuzzyc.errors import suggest
            raise scenario.error(f"plant.params.{key}", f"{name} has no field `{key}` — "
                                 f"{suggest(key, sorted(names))}")


def _own_params(scenario: Scenario):
    """The own plant's `params`, with the scenario's `plant.X` settings (`set plant.X = V` of a
    closed loop) put in by dataclasses.replace: the user's object is never changed."""
    params = scenario.own_plant.params
    given = dict(scenario.data["plant"].get("params") or {})
    if not given:
        return params
    if not dataclasses.is_dataclass(params):
        raise scenario.error("plant.params", f"the params of plant {scenario.plant_name} are "
                             f"no dataclass: a setting of {', '.join(given)} needs one")
    _check_fields(scenario, params, given)
    _check_types(scenario, "plant.params", given,
                 {f.name: getattr(params, f.name) for f in dataclasses.fields(params)})
    try:
        return dataclasses.replace(params, **given)
    except (TypeError, ValueError) as exc:
        raise scenario.error("plant.params", str(exc)) from None


def unknown_plant(name) -> str:
    """The message for a plant.model not in the registry."""
    from .scenario_schema import shown
    return (f"no plant module {shown(name, '`')}; a scenario names one of: "
            f"{', '.join((*registry.PLANTS, gym_env.MODEL))}")


def unknown_factory(kind: str, name) -> str:
    """The message for a baseline.make / observers.N.make not in the registry."""
    from .scenario_schema import shown
    article = "an" if kind[0] in "aeiou" else "a"
    return (f"{shown(name, '`')} is not {article} {kind} of fuzzyc.plants; a scenario names "
            f"one of: "
            f"{', '.join(registry.FACTORIES[kind])} (a scenario is data: it cannot name "
            f"other code)")


# a required param (no default) of these annotations is checked as if it had such a default
_ANNOTATED = {"float": 0.0, "int": 0, "bool": False, "str": "",
              float: 0.0, int: 0, bool: False, str: ""}


def _typical_values(factory) -> dict:
    """Per parameter of `factory`, its default, or for a required one a value of its annotated
    type (`gamma: float` of an observer was passed a string to its first step)."""
    return {name: (p.default if p.default is not inspect.Parameter.empty
                   else _ANNOTATED.get(p.annotation))
            for name, p in inspect.signature(factory).parameters.items()}


def _check_types(scenario: Scenario, dotted: str, given: dict, defaults: dict) -> None:
    """A param whose default is a number must be given a finite number, one whose default is a
    bool a bool (the plants compute with them: a string would fail deep inside a run)."""
    from .scenario_schema import NAME, finite_number, shown
    for key, value in given.items():
        default = defaults.get(key)
        if isinstance(default, bool):
            ok, what = isinstance(value, bool), "true or false"
        elif isinstance(default, (int, float)):
            # an array: one value per loop of a batch (the Python API, not YAML)
            ok, what = (np.all(np.isfinite(value)) if isinstance(value, np.ndarray) and
                        value.dtype.kind in "if" else finite_number(value)), "a finite number"
        elif isinstance(default, str):      # a signal name (input_name: 1.0e-300 was sorted)
            ok, what = isinstance(value, str) and NAME.fullmatch(value) is not None, "a name"
        else:
            continue
        if not ok:
            raise scenario.error(f"{dotted}.{key}", f"must be {what}, got {shown(value)}",
                                 of_value=True)


def _params_class(scenario: Scenario, module):
    classes = [v for k, v in vars(module).items()
               if k.endswith("Params") and dataclasses.is_dataclass(v)
               and v.__module__ == module.__name__]
    if len(classes) != 1:
        raise scenario.error("plant.model", f"{module.__name__} must define one *Params dataclass")
    return classes[0]


class _NotAMapping(Exception):
    """A --set path runs through a key of the file whose value is no mapping."""

    def __init__(self, dotted: str):
        self.dotted = dotted


def _apply_override(data: dict, key: str, value: Any) -> None:
    parts = key.split(".")
    node = data
    for i, part in enumerate(parts[:-1]):
        if isinstance(node, dict) and part not in node and isinstance(node.get("params"), dict):
            node = node["params"]
        if not isinstance(node, dict):
            raise KeyError(key)
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise _NotAMapping(".".join(parts[:i + 1]))
    last = parts[-1]
    if isinstance(node, dict) and last not in node and isinstance(node.get("params"), dict):
        node = node["params"]
    if not isinstance(node, dict):
        raise KeyError(key)
    node[last] = value


def load(name_or_path: str | Path, overrides: dict[str, str] | None = None,
         allow_import=()) -> Scenario:
    """The scenario, checked. allow_import: modules of the user's a Gymnasium plant may import
    (`env: module:Class`), given by the user (--allow-import), never by the file."""
    path = resolve(name_or_path)
    text = _read(path)
    try:
        data = scenario_yaml.load(text)
    except yaml.YAMLError as exc:
        raise _yaml_error(path, text, exc) from None
    if not isinstance(data, dict):
        raise FuzzycError([Diagnostic(SourceLoc(str(path), 1, 1),
                                      "a scenario file must be a YAML mapping")])
    allow = (allow_import,) if isinstance(allow_import, str) else tuple(allow_import or ())
    scenario = Scenario(path.stem, path, data, _Marks(text), text, dict(overrides or {}), allow)
    return _checked(scenario, overrides)


# what a plant object of the user's has (as a plant module or GymPlant does); for --prove also
# SET_VARIABLE, set_initial_state(params, **sets, noise) and set_step (docs/proofs.md)
OWN_PLANT = ("INPUTS", "OUTPUTS", "params", "initial_state", "step")


def from_mapping(name: str, given, overrides: dict[str, str] | None = None,
                 allow_import=()) -> Scenario:
    """A scenario given from Python as the mapping its YAML file would hold (the API's
    `verify(..., scenarios={NAME: {...}})`), checked as a file is. Its `plant` may be, instead
    of `{model: ...}`, a plant object of the user's with OWN_PLANT: an object the user passes,
    not a name in a file, so nothing is imported for it."""
    from collections.abc import Mapping
    if not isinstance(given, Mapping):
        raise TypeError(f"scenario `{name}`: a mapping of scenario keys (plant, period, "
                        f"schedules, ...), not {type(given).__name__}")
    data = {k: copy.deepcopy(v) for k, v in given.items() if k != "plant"}
    plant, own = given.get("plant"), None
    if plant is not None and not isinstance(plant, Mapping):
        own, plant = plant, {"model": type(plant).__name__, "params": {}}
        missing = [a for a in OWN_PLANT if not hasattr(own, a)]
        if missing:
            raise TypeError(f"scenario `{name}`: the plant {type(own).__name__} has no "
                            f"`{missing[0]}`; a plant object has {', '.join(OWN_PLANT)} "
                            f"(docs/verification.md)")
    if plant is not None:
        data["plant"] = copy.deepcopy(dict(plant))
    allow = (allow_import,) if isinstance(allow_import, str) else tuple(allow_import or ())
    scenario = Scenario(name, Path(f"<scenario {name}>"), data, _Marks(""), "",
                        dict(overrides or {}), allow, own)
    return _checked(scenario, overrides)


def _checked(scenario: Scenario, overrides: dict[str, str] | None) -> Scenario:
    """The scenario with its --set overrides applied, its shape checked (scenario_schema)."""
    data, path = scenario.data, scenario.path
    for key, raw in (overrides or {}).items():
        try:
            _apply_override(data, key, _override_value(key, str(raw)))
        except _NotAMapping as exc:    # e.g. `controller:` left empty, FILE sets its rule base
            raise scenario.error(exc.dotted, f"must be a mapping: `{key}` is set inside it "
                                             "(by FILE or --set)") from None
        except KeyError:
            from .scenario_schema import capped
            raise FuzzycError([Diagnostic(None, f"--set {capped(f'{key}={raw}')}: "
                                                f"`{capped(key)}` does not name a scenario "
                                                f"setting of {path}")]) from None
    from .scenario_schema import check
    check(scenario)
    return scenario


def _override_value(key: str, raw: str):
    """A --set value, read as YAML within the same limits as a file."""
    from .scenario_schema import capped
    where = f"--set {capped(f'{key}={raw}')}"
    problem = scenario_yaml.too_long(raw)
    if problem:
        raise FuzzycError([Diagnostic(None, f"{where}: {problem}")])
    try:
        return scenario_yaml.load(raw)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        at = "" if mark is None else f" (at character {mark.index + 1} of the value)"
        problem = getattr(exc, "problem", None) or exc
        raise FuzzycError([Diagnostic(None, f"{where}: the value is not valid YAML: "
                                            f"{problem}{at}")]) from None


def _read(path: Path) -> str:
    """The file as text; a byte that is not UTF-8 is an error at its line and column."""
    try:
        with open(path, "rb") as file:
            raw = file.read(scenario_yaml.MAX_BYTES + 1)   # no more than the limit is read
    except OSError as exc:
        raise FuzzycError([Diagnostic(None, f"cannot read {path}: {exc.strerror}")]) from None
    if len(raw) > scenario_yaml.MAX_BYTES:
        raise FuzzycError([Diagnostic(SourceLoc(str(path), 1, 1), f"the file is larger than "
                                      f"a scenario may be ({scenario_yaml.MAX_BYTES:,} bytes)")])
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        before = raw[:exc.start]
        line = before.count(b"\n") + 1
        col = len(before) - (before.rfind(b"\n") + 1) + 1
        raise FuzzycError([Diagnostic(SourceLoc(str(path), line, col),
                                      f"byte 0x{raw[exc.start]:02x} is not UTF-8 text; "
                                      "save the file as UTF-8")]) from None


def _yaml_error(path: Path, text: str, exc: yaml.YAMLError) -> FuzzycError:
    """The parser's complaint at its mark (a character it refuses: at that character)."""
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    if mark is not None:
        line, col = _position(mark)
    elif isinstance(exc, yaml.reader.ReaderError):
        before = text[:exc.position]
        line = len(YAML_BREAK.findall(before)) + 1
        col = len(YAML_BREAK.split(before)[-1]) + 1
    else:
        line, col = 1, 1
    lines = YAML_BREAK.split(text)
    source = lines[line - 1] if line <= len(lines) else None
    problem = getattr(exc, "problem", None) or getattr(exc, "reason", None) or exc
    return FuzzycError([Diagnostic(SourceLoc(str(path), line, col), f"not valid YAML: {problem}",
                                   source)])
