"""What the C back end proves, with figures: Frama-C EVA on every shipped rule base's header of
every kind (alarms, harness assertions valid, seconds of one analysis), and the fixed-point
chains' error bound derived from the rounding of every operation beside the error measured
over 10,000 steps against the engine (tests/test_c_fixed.chain_errors, the random walks the
test holds within the bound).  Writes benchmarks/results/c_proofs.md atomically.

    python3 benchmarks/bench_c_proofs.py
"""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))

from common import markdown_table, write_result  # noqa: E402
from fuzzyc.backends.c_fixed.header import CHAIN_STEPS, chain_error_bound  # noqa: E402
from fuzzyc.backends.c.proof import KINDS, frama_c, prove  # noqa: E402
from fuzzyc.language.parser import load  # noqa: E402
from test_c_backend import shipped  # noqa: E402
from test_c_fixed import chain_errors  # noqa: E402

CHAINS = ["wedm_three_region", "edm_sink_gap", "wedm_corner", "milling_neurofuzzy", "fopdt_pi"]


def eva_table() -> str:
    rows = []
    for path in sorted((ROOT / "rulebases").glob("*.fz")):
        for kind in KINDS:
            proof = prove(load(path), kind)
            rows.append([path.stem, kind, "PROVED" if proof.proved else "NOT PROVED",
                         len(proof.alarms), f"{proof.assertions[0]}/{proof.assertions[1]}",
                         f"{proof.seconds:.1f}"])
    return markdown_table(["rule base", "header", "EVA", "alarms", "assertions valid",
                           "seconds"], rows)


def chain_table() -> str:
    rows = []
    for name in CHAINS:
        model = shipped(name)
        for numeric, measured in chain_errors(model).items():
            one = chain_error_bound(model, numeric, 1)
            run = chain_error_bound(model, numeric, CHAIN_STEPS)
            rows += [[name, numeric, output, f"{one[output]:.2g}", f"{run[output]:.2g}",
                      f"{error:.2g}", f"{run[output] / error:.3g}" if error else "-"]
                     for output, error in zip(run, measured)]
    return markdown_table(["chain", "numeric", "output", "derived, 1 step",
                           f"derived, {CHAIN_STEPS:,} steps", f"measured, {CHAIN_STEPS:,} steps",
                           "derived / measured"], rows)


def main() -> None:
    text = "# What the C back end proves (benchmarks/bench_c_proofs.py)\n\n"
    if frama_c() is None:
        print("EVA table skipped: needs frama-c (Debian: frama-c-base)")
    else:
        text += ("## Frama-C EVA, every shipped rule base x header kind (one analysis each; "
                 "wall time, varies with the machine's load)\n\n" + eva_table() + "\n")
    text += ("## Fixed-point chain error, fraction of the output's range (milling with the "
             "tests' random weights)\n\n" + chain_table())
    print(text)
    write_result(ROOT / "benchmarks" / "results" / "c_proofs.md", text)


if __name__ == "__main__":
    main()
