"""What a scenario may name: a scenario is data, so it picks from these lists, and nothing is
imported because a file names it (docs/security.md, "Scenarios are data").

- `plant.model`: a plant module of fuzzyc.plants listed in PLANTS, or `gymnasium` (an
  environment id registered with Gymnasium, plants/gym_env.py);
- `baseline.make`: a controller factory listed in BASELINES;
- `observers[].make`: a block factory listed in OBSERVERS.

A name is checked against these lists before its module is imported; only then is
`fuzzyc.plants.<module>` imported (our own code) and the attribute taken. A new plant,
baseline or observer is added here.

Code of the user's own (a Gymnasium environment class, `env: my_package.envs:Heater`) is
imported only when the user allows its module outside the file: `--allow-import MODULE` on
`fuzzyc simulate` / `verify`, `allow_import=[...]` in the API (`allowed_module`).
"""
from __future__ import annotations

import importlib
import re

PLANTS = ("edm_sink", "fopdt", "milling", "wedm_corner", "wedm_gap")
BASELINES = ("edm_sink.PIGapServo", "fopdt.PI", "milling.ConstantFeed",
             "wedm_corner.NoCornerControl", "wedm_gap.VoltageP")
OBSERVERS = ("filters.bandstop", "filters.lowpass", "filters.lowpass_bandstop",
             "height_estimator.HeightEstimator")
FACTORIES = {"baseline": BASELINES, "observer": OBSERVERS}
MODULE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*")
ALLOW_HINT = ("to use a module of your own, allow it outside the file: "
              "--allow-import MODULE (API: allow_import=[\"MODULE\"])")


def plant_module(name: str):
    """The plant module `name` of PLANTS (KeyError for any other name: nothing imported)."""
    if name not in PLANTS:
        raise KeyError(name)
    return importlib.import_module(f"{__package__}.{name}")


def factory(kind: str, name: str):
    """The callable `module.Attr` of FACTORIES[kind] (KeyError for any other name)."""
    if name not in FACTORIES[kind]:
        raise KeyError(name)
    module, _, attr = name.partition(".")
    return getattr(importlib.import_module(f"{__package__}.{module}"), attr)


def allowed_module(module: str, allow_import) -> bool:
    """Whether the user allowed `module`: it, or a package it is in, is in allow_import."""
    return MODULE.fullmatch(module) is not None and any(
        module == a or module.startswith(a + ".") for a in allow_import or ())
