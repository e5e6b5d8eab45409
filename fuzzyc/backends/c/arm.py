"""The generated headers on a controller's CPU: the footprint of every kind of header built for
the Cortex-M it targets by arm-none-eabi-gcc at -Os, with the strict flags of the tests
(-Werror), beside the host's build.

Float headers go to a Cortex-M4F (single-precision FPU), q15/q31 to a Cortex-M0 (no FPU, no
64-bit multiply: libgcc's helpers do it).  Measured like `fuzzyc compile` measures
(`cload.footprint`: out-of-line init and step, text incl. tables as flash, one state instance
as RAM, the sum of every function's -fstack-usage as worst stack), compiled but not linked: the
run-time library's helpers (__aeabi_lmul / __aeabi_ldivmod, libm's expf) are not counted.
"""
from __future__ import annotations

import shutil
from typing import NamedTuple

from ...escape import c_identifier
from ...semantics.model import Model
from .load import footprint, measured_entry_points

TOOLCHAIN = "arm-none-eabi-"
CORTEX_M = {
    "float": ("Cortex-M4F", ("-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
                             "-mfpu=fpv4-sp-d16", "-Os")),
    "q15": ("Cortex-M0", ("-mcpu=cortex-m0", "-mthumb", "-Os")),
    "q31": ("Cortex-M0", ("-mcpu=cortex-m0", "-mthumb", "-Os")),
}


class Footprint(NamedTuple):
    cpu: str
    flash: int
    ram: int
    stack: int


def arm_toolchain() -> str | None:
    return shutil.which(f"{TOOLCHAIN}gcc")


def measure(model: Model, numeric: str, header: tuple[str, str],
            on_arm: bool = True) -> Footprint:
    """The footprint of `header` (file name, text), of kind `numeric` (a key of CORTEX_M), on
    its Cortex-M, or with `on_arm` False on the host (gcc -Os)."""
    name = c_identifier(model.name)
    prefix = name if numeric == "float" else f"{name}_{numeric}"
    entries = measured_entry_points(name, numeric) + [f"{prefix}_state fz_state;"]
    cpu, flags = CORTEX_M[numeric] if on_arm else ("host", ("-Os",))
    return Footprint(cpu, *footprint(*header, entries, flags,
                                     toolchain=TOOLCHAIN if on_arm else ""))
