"""The shape of a scenario file, checked before anything runs: every key known, every value of
the type its reader expects (a number finite, a name a string, a list a list), each mistake a
FuzzycError at the key or value in the YAML file (file:line:col).

What only the run can tell (a metric's signal that is never recorded, a plant param the plant
rejects) is checked where it is used, with the same kind of message.
"""
from __future__ import annotations

import math
import re
import reprlib

from fuzzyc.errors import suggest

TOP_KEYS = {"title", "source", "plant", "controller", "baseline", "observers", "duration",
            "period", "initial", "schedules", "metrics", "plots", "notes"}
SECTION_KEYS = {"plant": {"model", "params", "randomize"},
                "controller": {"rulebase", "params", "initial", "expose"},
                "baseline": {"make", "params", "label"}}
OBSERVER_KEYS = {"make", "params"}
METRIC_KEYS = {"name", "signal", "target", "band", "smooth", "tail", "after", "unit", "label",
               "where", "scale"}
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
MAKE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\.[A-Za-z_][A-Za-z0-9_]*")   # module.callable
MAX_PERIODS = 10_000_000   # a longer run is a typo (a trace of T periods holds T rows)


def finite_number(value) -> bool:
    """An int or float (not a bool, which YAML reads from `yes`) that is finite as a float."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:          # an int with hundreds of digits
        return False


SHOWN = 80                  # characters of a user's value a message shows
_REPR = reprlib.Repr()      # bounded work: a few items, a few levels, short strings
_REPR.maxlevel, _REPR.maxlist, _REPR.maxdict, _REPR.maxtuple, _REPR.maxset = 3, 6, 6, 6, 6
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = SHOWN


def capped(text: str, limit: int = SHOWN) -> str:
    """`text` cut to `limit` characters, an ellipsis marking the cut."""
    return text if len(text) <= limit else text[:limit - 3] + "..."


def shown(value, quote: str = "") -> str:
    """A value of the user's for a message: repr (of a string: the string between `quote`s,
    when given), bounded in length and in the work it takes (never repr the whole of it)."""
    if quote and isinstance(value, str):
        return f"{quote}{capped(value)}{quote}"
    return capped(_REPR.repr(value))


def _is_text(value) -> bool:
    """What YAML reads from plain words: a string, or a number written where text goes."""
    return isinstance(value, (str, int, float))


class _Checker:
    def __init__(self, scenario):
        self.scenario = scenario

    def fail(self, dotted: str, message: str, of_value: bool = True):
        raise self.scenario.error(dotted, message, of_value)

    def expect(self, dotted: str, value, ok: bool, what: str) -> None:
        if not ok:
            self.fail(dotted, f"must be {what}, got {shown(value)}")

    def keys(self, dotted: str, mapping: dict, known: set[str]) -> None:
        for key in mapping:
            if key not in known:
                where = f"{dotted}.{key}" if dotted else str(key)
                self.fail(where, f"unknown key; {suggest(str(key), sorted(known))}",
                          of_value=False)

    def mapping(self, dotted: str, value, what: str = "a mapping") -> dict:
        """`value` (None: empty) as a dict, else the error."""
        if value is None:
            return {}
        self.expect(dotted, value, isinstance(value, dict), what)
        return value

    def sequence(self, dotted: str, value, what: str) -> list:
        if value is None:
            return []
        self.expect(dotted, value, isinstance(value, list), what)
        return value

    def numbers(self, dotted: str, value, what: str = "a finite number") -> dict:
        """A mapping of names to finite numbers (params, initial values)."""
        mapping = self.mapping(dotted, value, "a mapping of names to numbers")
        for key, item in mapping.items():
            self.expect(f"{dotted}.{key}", item, finite_number(item), what)
        return mapping

    def text(self, dotted: str, value, pattern: re.Pattern | None = None,
             what: str = "text") -> None:
        ok = isinstance(value, str) and (pattern is None or pattern.fullmatch(value))
        self.expect(dotted, value, bool(ok), what)


def check(scenario) -> None:
    """Raise a located FuzzycError at the first value of the wrong shape."""
    c = _Checker(scenario)
    data = scenario.data
    c.keys("", data, TOP_KEYS)
    for key in ("title", "source"):
        if key in data:
            c.expect(key, data[key], _is_text(data[key]), "text")
    notes = data.get("notes")
    for i, note in enumerate(notes if isinstance(notes, list) else []):
        c.expect(f"notes.{i}", note, _is_text(note), "text")
    c.expect("notes", notes, notes is None or isinstance(notes, list) or _is_text(notes),
             "text or a list of texts")
    from . import gym_env       # which imports finite_number from here
    for section, known in SECTION_KEYS.items():
        spec = c.mapping(section, data.get(section))
        if section == "plant" and spec.get("model") == gym_env.MODEL:
            gym_env.from_scenario(scenario)      # its own keys, checked there
        else:
            c.keys(section, spec, known)
    plant = data.get("plant")
    if not isinstance(plant, dict) or "model" not in plant:
        c.fail("plant", "a scenario needs `plant:` with `model:`", of_value=False)
    c.text("plant.model", plant["model"], NAME, "the name of a plant module")
    from . import registry
    from .scenario import unknown_plant
    own = getattr(scenario, "own_plant", None) is not None     # an object of the user's
    if not own and plant["model"] not in (*registry.PLANTS, gym_env.MODEL):
        c.fail("plant.model", unknown_plant(plant["model"]))
    c.mapping("plant.params", plant.get("params"))
    c.numbers("plant.randomize", plant.get("randomize"), "a relative spread (a finite number)")
    _controller(c, data.get("controller") or {})
    _make(c, "baseline", data.get("baseline"))
    for i, spec in enumerate(c.sequence("observers", data.get("observers"),
                                        "a list of {make: module.Callable, params: {...}}")):
        c.keys(f"observers.{i}", c.mapping(f"observers.{i}", spec), OBSERVER_KEYS)
        _make(c, f"observers.{i}", spec)
    _timing(c, data)
    c.numbers("initial", data.get("initial"))
    for name, points in c.mapping("schedules", data.get("schedules")).items():
        ok = isinstance(points, list) and points and all(
            isinstance(p, list) and len(p) == 2 and all(map(finite_number, p)) for p in points)
        c.expect(f"schedules.{name}", points, bool(ok), "a list of [time, value] pairs")
    for i, spec in enumerate(c.sequence("metrics", data.get("metrics"),
                                        "a list of {name: ..., signal: ...}")):
        _metric(c, f"metrics.{i}", spec)
    for i, name in enumerate(c.sequence("plots", data.get("plots"), "a list of signal names")):
        c.text(f"plots.{i}", name, None, "a signal name")


def _controller(c: _Checker, spec: dict) -> None:
    if "rulebase" in spec:
        c.text("controller.rulebase", spec["rulebase"], None, "a rule file name")
    c.numbers("controller.params", spec.get("params"))
    c.numbers("controller.initial", spec.get("initial"))
    for i, name in enumerate(c.sequence("controller.expose", spec.get("expose"),
                                        "a list of signal names")):
        c.text(f"controller.expose.{i}", name, NAME, "a signal name")


def _make(c: _Checker, dotted: str, spec) -> None:
    """A baseline or observer: `make` one of the registry's (plants/registry.py), checked by
    name before anything is imported."""
    if spec is None:
        return
    from . import registry
    from .scenario import unknown_factory
    c.text(f"{dotted}.make", spec.get("make"), MAKE, "module.Callable of fuzzyc.plants")
    kind = "baseline" if dotted == "baseline" else "observer"
    if spec["make"] not in registry.FACTORIES[kind]:
        c.fail(f"{dotted}.make", unknown_factory(kind, spec["make"]))
    c.mapping(f"{dotted}.params", spec.get("params"))


def _timing(c: _Checker, data: dict) -> None:
    for key in ("duration", "period"):
        if key in data:
            value = data[key]
            c.expect(key, value, finite_number(value) and value > 0,
                     "a positive number of seconds")
    duration, period = data.get("duration", 60.0), data.get("period", 0.04)
    if duration / period > MAX_PERIODS:
        c.fail("duration" if "duration" in data else "period",
               f"{duration:g} s of {period:g} s periods is more than {MAX_PERIODS:,} periods")


def _metric(c: _Checker, dotted: str, spec) -> None:
    from fuzzyc.runtime.simulate import METRICS
    spec = c.mapping(dotted, spec, "a mapping {name: ..., signal: ...}")
    c.keys(dotted, spec, METRIC_KEYS)
    name = spec.get("name")
    if not (isinstance(name, str) and name in METRICS):
        c.fail(f"{dotted}.name", f"unknown metric {shown(name)}; "
                                 f"{suggest(str(name), sorted(METRICS))}")
    c.text(f"{dotted}.signal", spec.get("signal"), None, "a signal name")
    target = spec.get("target")
    if target is not None:
        c.expect(f"{dotted}.target", target, isinstance(target, str) or finite_number(target),
                 "a signal name or a finite number")
    if "where" in spec:
        c.text(f"{dotted}.where", spec["where"], None, "the name of a 0/1 signal")
    if "scale" in spec:
        c.expect(f"{dotted}.scale", spec["scale"], finite_number(spec["scale"]),
                 "a finite number")
    if name == "settling_time" and "band" not in spec:
        c.fail(dotted, "settling_time needs `band:` (how close counts as settled)")
    bounds = {"band": (0, False), "smooth": (0, True), "after": (0, True), "tail": (0, False)}
    for key, (low, inclusive) in bounds.items():
        if key in spec:
            value = spec[key]
            ok = finite_number(value) and (value >= low if inclusive else value > low)
            if key == "tail":
                ok = ok and value <= 1
            what = "a fraction in (0, 1]" if key == "tail" else \
                f"a {'non-negative' if inclusive else 'positive'} number"
            c.expect(f"{dotted}.{key}", value, ok, what)
    for key in ("unit", "label"):
        if key in spec:
            c.expect(f"{dotted}.{key}", spec[key], isinstance(spec[key], (str, int, float)),
                     "text")
