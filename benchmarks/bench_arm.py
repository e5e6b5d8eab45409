"""Flash, RAM and worst stack of every shipped rule base's header on a controller's CPU.

Float headers for a Cortex-M4F (-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16),
q15/q31 headers for a Cortex-M0 without FPU (-mcpu=cortex-m0 -mthumb), both at -Os, compiled
by arm-none-eabi-gcc with the strict flags of the tests (-Werror), beside the x86-64 build
(gcc -Os).  Measured as `fuzzyc compile` measures: out-of-line init and step, `size`'s text
(code + constant tables) as flash, data + bss as RAM (one state instance; the headers have no
other writable data), the sum of every function's -fstack-usage as worst stack.  Compiled, not
linked: the run-time library's helpers are not counted (on the Cortex-M0 the 64-bit multiply
and divide, __aeabi_lmul / __aeabi_ldivmod from libgcc; libm's expf for smooth terms).  Writes
benchmarks/results/arm.md atomically.

    python3 benchmarks/bench_arm.py
"""
from __future__ import annotations

import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from common import markdown_table, write_result  # noqa: E402
from fuzzyc.backends.c_proof import header_for  # noqa: E402
from fuzzyc.backends.cload import footprint  # noqa: E402
from fuzzyc.cli.compile import measured_entry_points  # noqa: E402
from fuzzyc.escape import c_identifier  # noqa: E402
from fuzzyc.parser import load  # noqa: E402

CPU_FLAGS = {
    "float": ("Cortex-M4F", ("-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
                             "-mfpu=fpv4-sp-d16", "-Os")),
    "q15": ("Cortex-M0", ("-mcpu=cortex-m0", "-mthumb", "-Os")),
    "q31": ("Cortex-M0", ("-mcpu=cortex-m0", "-mthumb", "-Os")),
}
TOOLCHAIN = "arm-none-eabi-"


def measure(path: Path, numeric: str) -> list[object]:
    model = load(path)
    name = c_identifier(model.name)
    header_name, text = header_for(model, numeric)
    prefix = name if numeric == "float" else f"{name}_{numeric}"
    entries = measured_entry_points(name, numeric) + [f"{prefix}_state fz_state;"]
    cpu, flags = CPU_FLAGS[numeric]
    flash, ram, stack = footprint(header_name, text, entries, flags, toolchain=TOOLCHAIN)
    x86_flash, _, x86_stack = footprint(header_name, text, entries, ("-Os",))
    return [path.stem, numeric, cpu, flash, ram, stack, x86_flash, x86_stack]


def main() -> None:
    if shutil.which(f"{TOOLCHAIN}gcc") is None:
        sys.exit("bench_arm needs arm-none-eabi-gcc (Debian: gcc-arm-none-eabi)")
    rows = [measure(path, numeric) for path in sorted((ROOT / "rulebases").glob("*.fz"))
            for numeric in CPU_FLAGS]
    table = markdown_table(["rule base", "numeric", "CPU (-Os)", "flash B", "RAM B",
                            "worst stack B", "x86-64 -Os code B", "x86-64 stack B"], rows)
    print(table)
    write_result(ROOT / "benchmarks" / "results" / "arm.md",
                 "# Generated headers on ARM (benchmarks/bench_arm.py)\n\n" + table + "\n")


if __name__ == "__main__":
    main()
