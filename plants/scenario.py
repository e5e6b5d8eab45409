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
naming the file and the line of the offending key.
"""
from __future__ import annotations

import dataclasses
import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from fuzzyc.errors import Diagnostic, FuzzycError
from fuzzyc.model import SourceLoc

from . import gym_env

SCENARIO_DIR = Path(__file__).resolve().parent / "scenarios"
RULEBASE_SETTING = "controller.rulebase"    # what FILE on the command line sets
TOP_KEYS = {"title", "source", "plant", "controller", "baseline", "observers", "duration",
            "period", "initial", "schedules", "metrics", "plots", "notes"}
SECTION_KEYS = {"plant": {"model", "params", "randomize"},
                "controller": {"rulebase", "params", "initial", "expose"},
                "baseline": {"make", "params", "label"}}


def available() -> list[str]:
    """The names of the shipped scenarios."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.yaml"))


def resolve(name_or_path: str | Path) -> Path:
    path = Path(name_or_path)
    if path.suffix in (".yaml", ".yml") and path.exists():
        return path
    shipped = SCENARIO_DIR / f"{name_or_path}.yaml"
    if shipped.exists():
        return shipped
    from fuzzyc.errors import suggest
    raise FuzzycError([Diagnostic(None, f"no scenario `{name_or_path}` — "
                                        f"{suggest(str(name_or_path), available())}")])


class _Lines:
    """Dotted key -> line in the YAML file, from the composed node tree (for messages)."""

    def __init__(self, text: str):
        self.lines: dict[str, int] = {}
        try:
            root = yaml.compose(text)
        except yaml.YAMLError:
            root = None
        if root is not None:
            self._walk(root, "")

    def _walk(self, node, prefix: str) -> None:
        if isinstance(node, yaml.MappingNode):
            for key, value in node.value:
                dotted = f"{prefix}{key.value}"
                self.lines[dotted] = key.start_mark.line + 1
                self._walk(value, dotted + ".")
        elif isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                self.lines[f"{prefix}{i}"] = item.start_mark.line + 1
                self._walk(item, f"{prefix}{i}.")

    def line(self, dotted: str) -> int:
        while dotted and dotted not in self.lines:
            dotted = dotted.rpartition(".")[0]
        return self.lines.get(dotted, 1)


@dataclass
class Scenario:
    name: str
    path: Path
    data: dict
    lines: _Lines = field(repr=False)
    text: str = field(repr=False, default="")
    settings: dict[str, str] = field(default_factory=dict)   # the --set overrides applied

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
    def error(self, dotted: str, message: str) -> FuzzycError:
        line = self.lines.line(dotted)
        lines = self.text.splitlines()
        source = lines[line - 1] if 1 <= line <= len(lines) else None
        col = 1 + (len(source) - len(source.lstrip())) if source else 1
        return FuzzycError([Diagnostic(SourceLoc(str(self.path), line, col),
                                       f"`{dotted}`: {message}", source)])

    def plant_module(self):
        """The plant module of fuzzyc.plants the scenario names, or for `model: gymnasium` a
        GymPlant, which has what a plant module has (plants/gym_env.py)."""
        if self.plant_name == gym_env.MODEL:
            return gym_env.from_scenario(self)
        return _plant_attr(self, "plant.model", self.plant_name, None)

    def plant_params(self, batch: int = 1, rng: np.random.Generator | None = None,
                     randomize: bool = False):
        """The plant's params dataclass; with randomize, (N,) arrays drawn around each value."""
        module = self.plant_module()
        if isinstance(module, gym_env.GymPlant):
            return module.params
        cls = _params_class(self, module)
        given = dict(self.data["plant"].get("params") or {})
        names = {f.name for f in dataclasses.fields(cls)}
        for key in given:
            if key not in names:
                from fuzzyc.errors import suggest
                raise self.error(f"plant.params.{key}", f"{cls.__name__} has no field `{key}` "
                                 f"— {suggest(key, sorted(names))}")
        try:
            params = cls(**given)
        except (TypeError, ValueError) as exc:
            raise self.error("plant.params", str(exc)) from None
        spread = dict(self.data["plant"].get("randomize") or {}) if randomize else {}
        rng = rng or np.random.default_rng(0)
        for key, rel in spread.items():
            if key not in names:
                raise self.error(f"plant.randomize.{key}", f"{cls.__name__} has no field `{key}`")
            base = float(getattr(params, key))
            setattr(params, key, base * (1.0 + float(rel) * rng.standard_normal(batch)))
        return params

    def make(self, dotted: str, spec: dict):
        """Instantiate `plants.<module>.<callable>(**params)` named by spec["make"]."""
        module_name, _, attr = str(spec.get("make", "")).rpartition(".")
        factory = _plant_attr(self, f"{dotted}.make", module_name, attr)
        try:
            return factory(**(spec.get("params") or {}))
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
        if not path.exists():
            raise self.error("controller.rulebase", f"no rule base file {path}")
        return path


def _plant_attr(scenario: Scenario, dotted: str, module_name: str, attr: str | None):
    package = __name__.rpartition(".")[0]
    try:
        module = importlib.import_module(f"{package}.{module_name}")
    except ModuleNotFoundError as exc:
        if not str(exc.name or "").endswith(module_name):
            raise
        raise scenario.error(dotted, f"no plant module `{module_name}`") from None
    if attr is None:
        return module
    if not hasattr(module, attr):
        raise scenario.error(dotted, f"plant module `{module_name}` has no `{attr}`")
    return getattr(module, attr)


def _params_class(scenario: Scenario, module):
    classes = [v for k, v in vars(module).items()
               if k.endswith("Params") and dataclasses.is_dataclass(v)
               and v.__module__ == module.__name__]
    if len(classes) != 1:
        raise scenario.error("plant.model", f"{module.__name__} must define one *Params dataclass")
    return classes[0]


def _apply_override(data: dict, key: str, value: Any) -> None:
    parts = key.split(".")
    node = data
    for part in parts[:-1]:
        if isinstance(node, dict) and part not in node and isinstance(node.get("params"), dict):
            node = node["params"]
        if not isinstance(node, dict):
            raise KeyError(key)
        node = node.setdefault(part, {})
    last = parts[-1]
    if isinstance(node, dict) and last not in node and isinstance(node.get("params"), dict):
        node = node["params"]
    if not isinstance(node, dict):
        raise KeyError(key)
    node[last] = value


def _check_keys(scenario: Scenario) -> None:
    data = scenario.data
    for key in data:
        if key not in TOP_KEYS:
            raise scenario.error(str(key), f"unknown key; known: {' '.join(sorted(TOP_KEYS))}")
    if not isinstance(data.get("plant"), dict) or "model" not in data["plant"]:
        raise scenario.error("plant", "a scenario needs `plant:` with `model:`")
    for section, known in SECTION_KEYS.items():
        value = data.get(section)
        if value is None:
            continue
        if not isinstance(value, dict):
            raise scenario.error(section, "must be a mapping")
        if section == "plant" and value.get("model") == gym_env.MODEL:
            gym_env.from_scenario(scenario)      # its own keys, checked there
            continue
        for key in value:
            if key not in known:
                raise scenario.error(f"{section}.{key}",
                                     f"unknown key; known: {' '.join(sorted(known))}")
    for key in ("duration", "period"):
        if key in data and not (isinstance(data[key], (int, float)) and data[key] > 0):
            raise scenario.error(key, f"must be a positive number of seconds, got {data[key]!r}")
    for name, points in (data.get("schedules") or {}).items():
        ok = isinstance(points, list) and points and all(
            isinstance(p, list) and len(p) == 2
            and all(isinstance(x, (int, float)) for x in p) for p in points)
        if not ok:
            raise scenario.error(f"schedules.{name}", "must be a list of [time, value] pairs")


def load(name_or_path: str | Path, overrides: dict[str, str] | None = None) -> Scenario:
    path = resolve(name_or_path)
    text = path.read_text(encoding="utf-8")
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        loc = SourceLoc(str(path), mark.line + 1, mark.column + 1) if mark else None
        line = text.splitlines()[mark.line] if mark and mark.line < len(text.splitlines()) else None
        raise FuzzycError([Diagnostic(loc, f"not valid YAML: {getattr(exc, 'problem', exc)}",
                                      line)]) from None
    if not isinstance(data, dict):
        raise FuzzycError([Diagnostic(SourceLoc(str(path), 1, 1),
                                      "a scenario file must be a YAML mapping")])
    scenario = Scenario(path.stem, path, data, _Lines(text), text, dict(overrides or {}))
    for key, raw in (overrides or {}).items():
        try:
            _apply_override(data, key, yaml.safe_load(str(raw)))
        except (KeyError, yaml.YAMLError):
            raise FuzzycError([Diagnostic(None, f"--set {key}={raw}: `{key}` does not name a "
                                                f"scenario setting of {path}")]) from None
    _check_keys(scenario)
    return scenario
