"""A toy EDM gap plant with known answers for the closed-loop checker's tests: first order, the
gap voltage is 1 V per um of gap around 50 um, the servo's velocity closes the gap and erosion
opens it. Fixtures put it (and a 2-s scenario `toy` at 1 ms) where the checker finds them."""
import dataclasses
import sys
import types

import numpy as np
import pytest

from fuzzyc.language.parser import parse
from conftest import ROOT

SERVO = open(f"{ROOT}/rulebases/edm_sink_gap.fz").read()


@dataclasses.dataclass
class ToyGapParams:
    gap0: float = 80.0        # um at the start: voltage 50 + (80 - 50) = 80 V
    erosion: float = 5.0      # um/s the gap opens by itself
    gain: float = 1000.0      # um per mm of electrode advance


def _voltage(gap):
    return np.clip(50.0 + (gap - 50.0), 0.0, 120.0)   # 1 V per um around 50 um


def initial_state(params, batch, rng=None):
    return {"gap": np.full(batch, params.gap0, dtype=float)}


def step(params, state, inputs, t, dt, rng=None):
    # advancing (velocity > 0, mm/s) closes the gap; erosion opens it
    gap = state["gap"] + (params.erosion - params.gain * inputs["velocity"]) * dt
    return {"gap": gap}, {"gap_voltage": _voltage(gap), "gap": gap}


@pytest.fixture
def toy_plant(monkeypatch):
    import fuzzyc.plants
    module = types.ModuleType("fuzzyc.plants.toy_gap")
    ToyGapParams.__module__ = module.__name__
    module.ToyGapParams, module.initial_state, module.step = ToyGapParams, initial_state, step
    module.INPUTS, module.OUTPUTS = ("velocity",), ("gap_voltage", "gap")
    monkeypatch.setitem(sys.modules, module.__name__, module)
    monkeypatch.setattr(fuzzyc.plants, "toy_gap", module, raising=False)
    # a scenario names only registered plants (plants/registry.py): register the toy one
    from fuzzyc.plants import registry
    monkeypatch.setattr(registry, "PLANTS", (*registry.PLANTS, "toy_gap"))
    return module


@pytest.fixture
def scenario(tmp_path, monkeypatch):
    from fuzzyc.plants import scenario as scenarios
    monkeypatch.setattr(scenarios, "SCENARIO_DIR", tmp_path)
    path = tmp_path / "toy.yaml"
    path.write_text("title: toy gap\nplant:\n  model: toy_gap\n  params: {erosion: 5}\n"
                    "duration: 2\nperiod: 0.001\n")
    return "toy"


def toy_servo(scenario_name, vmax="2 mm/s", checks=None):
    checks = checks or ("always gap_voltage < 100\n"
                        "      settles gap_voltage to Vset within 5 by 1.5 s\n")
    loop = (f"  verify {{\n    closed_loop {scenario_name} for 2 s {{\n"
            f"      vary plant.erosion in [0, 20]\n      {checks}    }}\n  }}\n}}\n")
    text = SERVO.split("  # Findings")[0].replace("param Vmax = 2 mm/s", f"param Vmax = {vmax}")
    return parse(text.rstrip().rstrip("}") + loop, "servo.fz")
