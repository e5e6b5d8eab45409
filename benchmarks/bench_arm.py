"""Flash, RAM and worst stack of every shipped rule base's header on a controller's CPU.

Float headers for a Cortex-M4F (-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16),
q15/q31 headers for a Cortex-M0 without FPU (-mcpu=cortex-m0 -mthumb), both at -Os, compiled
by arm-none-eabi-gcc with the strict flags of the tests (-Werror), beside the x86-64 build
(gcc -Os); how it is measured: `fuzzyc.backends.c.arm`.  Writes benchmarks/results/arm.md
atomically.

    python3 benchmarks/bench_arm.py
"""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one
sys.path.insert(0, str(ROOT / "benchmarks"))

from common import markdown_table, write_result  # noqa: E402
from fuzzyc.backends.c.arm import CORTEX_M, arm_toolchain, measure  # noqa: E402
from fuzzyc.backends.c.proof import header_for  # noqa: E402
from fuzzyc.language.parser import load  # noqa: E402


def row(path: Path, numeric: str) -> list[object]:
    model = load(path)
    header = header_for(model, numeric)
    arm, host = measure(model, numeric, header), measure(model, numeric, header, on_arm=False)
    return [path.stem, numeric, arm.cpu, arm.flash, arm.ram, arm.stack, host.flash, host.stack]


def main() -> None:
    if arm_toolchain() is None:
        print("bench_arm skipped: needs arm-none-eabi-gcc (Debian: gcc-arm-none-eabi)")
        return
    rows = [row(path, numeric) for path in sorted((ROOT / "rulebases").glob("*.fz"))
            for numeric in CORTEX_M]
    table = markdown_table(["rule base", "numeric", "CPU (-Os)", "flash B", "RAM B",
                            "worst stack B", "x86-64 -Os code B", "x86-64 stack B"], rows)
    print(table)
    write_result(ROOT / "benchmarks" / "results" / "arm.md",
                 "# Generated headers on ARM (benchmarks/bench_arm.py)\n\n" + table + "\n")


if __name__ == "__main__":
    main()
