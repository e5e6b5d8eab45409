"""Every shipped rule base's header built for the Cortex-M it targets (float: Cortex-M4F,
q15/q31: Cortex-M0) by arm-none-eabi-gcc at -Os with -Werror (`fuzzyc.backends.c.arm`); the
figures are benchmarks/bench_arm.py's.  Skipped with the reason without the cross compiler
(Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi)."""
from __future__ import annotations

import pathlib

import pytest

from fuzzyc.backends.c.arm import CORTEX_M, arm_toolchain, measure
from fuzzyc.backends.c.proof import header_for
from fuzzyc.language.parser import load

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHIPPED = sorted(p.name for p in (ROOT / "rulebases").glob("*.fz"))


@pytest.mark.skipif(arm_toolchain() is None,
                    reason="needs arm-none-eabi-gcc (Debian: gcc-arm-none-eabi)")
@pytest.mark.parametrize("numeric", sorted(CORTEX_M))
@pytest.mark.parametrize("name", SHIPPED)
def test_header_builds_for_its_cortex_m(name, numeric):
    model = load(ROOT / "rulebases" / name)
    header = header_for(model, numeric)
    arm, host = measure(model, numeric, header), measure(model, numeric, header, on_arm=False)
    # One state takes the same bytes on the 32-bit CPU as on x86-64: the headers keep their
    # state in fixed-width types (a `long` would be 4 bytes there, 8 here) and float.
    assert arm.ram == host.ram > 0
    # The smallest parts of either family (Cortex-M0 16 kB flash / 4 kB RAM) hold the whole
    # controller with room for the firmware: under 4 kB of flash and 1 kB of stack.
    assert 0 < arm.flash < 4096 and 0 < arm.stack < 1024
