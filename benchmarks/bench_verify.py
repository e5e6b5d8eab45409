"""Verifier speed.

1. The exact checks (coverage proof, consistency, completeness, continuity, monotone tables)
   for the three paper rule bases: median of repeated runs, against the dense-grid coverage
   search (20,000 engine evaluations) as the baseline in the same run.
2. The closed-loop search for WEDM properties on the finish cut: 200 hypothesis examples of
   300 s at 40 ms run as one batch, against one loop (batch 1) times 200 as the baseline.
3. The closed-loop proofs (fuzzyc verify --prove) of every closed loop the shipped rule bases
   declare, beside the search of the same loop (100 cases): CPU seconds of this process
   (time.process_time), so other load on the machine does not swing them.
Writes benchmarks/results/verify.md (atomically).

    python3 benchmarks/bench_verify.py [--quick]
"""
from __future__ import annotations

import argparse
import dataclasses
import pathlib
import platform
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one

from common import markdown_table, median_seconds, write_result  # noqa: E402

PAPERS = {"wedm_three_region": ("e1", "e2", "ce2"), "wedm_corner": ("feedrate", "thickness", "angle"),
          "milling_neurofuzzy": ("e", "cf")}



def exact_checks(rb, inputs) -> None:
    from fuzzyc.verifier import coverage, tables
    level = 0.25 if len(inputs) == 2 else 0.5
    coverage.prove_covers(rb, list(inputs), level)
    tables.consistent(rb)
    tables.complete(rb, None)
    tables.continuous(rb, None)
    for name in inputs:
        tables.monotone(rb, rb.outputs[0].name, name, "increasing", [])


def bench_exact(repeats: int) -> str:
    from fuzzyc.language.parser import load
    from fuzzyc.verifier import search
    rows = []
    for name, inputs in PAPERS.items():
        rb = load(ROOT / "rulebases" / f"{name}.fz").rulebase
        level = 0.25 if len(inputs) == 2 else 0.5
        t_exact = median_seconds(lambda: exact_checks(rb, inputs), repeats)
        t_grid = median_seconds(lambda: search.covers(rb, list(inputs), level, 20000), repeats)
        rows.append([name, rb.n_rules, f"{t_exact * 1e3:.1f} ms", "yes" if t_exact < 5 else "NO",
                     f"{t_grid * 1e3:.1f} ms", f"{t_grid / t_exact:.2f}"])
    return markdown_table(["rule base", "rules", "all exact checks (median)", "< 5 s",
                           "grid coverage search, 20k points (baseline)", "baseline / exact"],
                          rows)


LOOP_TEXT = """
  verify {
    closed_loop wedm_finish for DURATION s {
      vary plant.height in [20, 50]
      vary plant.tension in [600, 1000]
      always ruptures < 1
      always spark_freq < Yr1 + 4
    }
  }
}
"""


def bench_closed_loop(examples: int, duration: float) -> str:
    from fuzzyc.language.parser import parse
    from fuzzyc.verifier import Options, verify_model
    path = ROOT / "rulebases" / "wedm_three_region.fz"
    text = path.read_text().rstrip()[:-1] + LOOP_TEXT.replace("DURATION", f"{duration:g}")
    model = parse(text, str(path))
    model = dataclasses.replace(model, properties=model.properties[-1:])

    def search(n, shrink_rounds):
        start = time.perf_counter()
        results = verify_model(model, Options(max_examples=n, seed=0,
                                              shrink_rounds=shrink_rounds))
        return time.perf_counter() - start, results

    single, _ = search(1, shrink_rounds=0)      # the baseline: one loop, nothing else
    batched, results = search(examples, shrink_rounds=4)
    verdicts = "; ".join(f"{r.prop.text}: {r.summary()}" for r in results)
    rows = [[examples, f"{duration:g} s", f"{batched:.1f} s", "yes" if batched < 60 else "NO",
             f"{single:.1f} s", f"{single * examples:.0f} s",
             f"{single * examples / batched:.1f}"]]
    return (markdown_table(["examples", "simulated", "batched search incl. shrinking",
                            "< 60 s", "one loop (batch 1, no shrinking)", "200 loops one by one (est.)",
                            "speed-up"], rows)
            + f"\nVerdicts: {verdicts}\n")


SHIPPED_LOOPS = ["edm_sink_gap", "milling_neurofuzzy_learned", "wedm_three_region",
                 "wedm_corner"]


def bench_proofs(names: list[str], max_boxes: int, horizon_scale: float) -> str:
    """Per shipped closed loop: the proof's answer and bound per check, its CPU time, and the
    search's CPU time and verdict (100 cases)."""
    from fuzzyc.language.parser import load
    from fuzzyc.plants import scenario as scenarios
    from fuzzyc.verifier import Options
    from fuzzyc.verifier import closed_loop
    from fuzzyc.verifier.reach.decide import Settings, prove
    rows = []
    for name in names:
        model = load(ROOT / "rulebases" / f"{name}.fz")
        loops = [p for p in model.properties if p.kind == "closed_loop"]
        for k, prop in enumerate(loops):
            prop.args["duration"] *= horizon_scale
            checks = prop.args["checks"]
            scen = scenarios.load(prop.args["scenario"], {})
            start = time.process_time()
            proofs = prove(model, prop, checks, scen, Settings(max_boxes=max_boxes, sigmas=0.0))
            proof_s = time.process_time() - start
            start = time.process_time()
            found = closed_loop.check(model, prop, checks, Options(max_examples=100))
            search_s = time.process_time() - start
            for check, proof, searched in zip(checks, proofs, found):
                answer, said = _answer(proof, searched[-1])
                search = f"{searched[-1].status.value} ({search_s:.1f} s)"
                cut = _window_past(check, prop.args["duration"])
                if horizon_scale < 1 and cut:      # a smoke run's answers would be artefacts
                    answer, said, search = "-", f"not decided at this horizon: {cut}", "-"
                rows.append([f"{name}.fz #{k + 1}", f"`{check.text}`", answer,
                             said.replace("|", "/"), f"{prop.args['duration']:g} s",
                             f"{proof_s:.1f} s", search])
    return markdown_table(["loop", "check", "answer", "bound / trace / where the sets stopped",
                           "horizon",
                           "proof CPU (all checks of the loop)", "search, 100 cases (CPU)"],
                          rows)


def _window_past(check, horizon: float) -> str | None:
    """Why a check cannot be decided over a shortened run: its window ends past the horizon
    (`eventually within W`, `settles ... by b`), or None."""
    end = {"eventually": "within", "settles": "by"}.get(check.kind)
    when = check.args.get(end) if end else None
    if when is None or when <= horizon:
        return None
    return f"its window ends at {when:g} s, past the {horizon:g} s of the run"


def _answer(proof, searched) -> tuple[str, str]:
    """PROVED from the sets; VIOLATED from the search's shrunk trace replayed alone; UNKNOWN
    with where the sets stopped."""
    if proof.status.value == "proved":
        return "PROVED", proof.detail
    if searched.status.value == "violated":
        return "VIOLATED", f"{searched.detail} (sets: {proof.detail})"
    return "UNKNOWN", proof.detail


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="fewer repeats, shorter loops")
    parser.add_argument("--proofs-only", action="store_true",
                        help="only the closed-loop proofs (writes benchmarks/results/proofs.md)")
    parser.add_argument("--loops", nargs="+", choices=SHIPPED_LOOPS, default=SHIPPED_LOOPS,
                        help="with --proofs-only: these rule files' closed loops "
                             "(results/proofs-NAME.md for a subset)")
    parser.add_argument("--boxes", type=int, metavar="N",
                        help="with --proofs-only: the box budget (64; 8 with --quick)")
    args = parser.parse_args()
    if args.proofs_only:
        boxes, scale = (8, 0.1) if args.quick else (64, 1.0)
        boxes = args.boxes or boxes
        command = " ".join(["python3 benchmarks/bench_verify.py --proofs-only"]
                           + (["--quick"] if args.quick else [])
                           + (["--loops"] + args.loops if args.loops != SHIPPED_LOOPS else [])
                           + ([f"--boxes {args.boxes}"] if args.boxes else []))
        text = (f"# Closed-loop proofs beside the search\n\n`{command}` (box budget {boxes}, "
                f"horizons x {scale:g}; spark noise not covered: --noise-sigmas 0)\n\n"
                f"{bench_proofs(args.loops, boxes, scale)}")
        stem = "proofs" if args.loops == SHIPPED_LOOPS else "proofs-" + "-".join(args.loops)
        stem += "-quick" if args.quick else ""     # never over the full run's table
        stem += f"-boxes{args.boxes}" if args.boxes else ""
        write_result(ROOT / "benchmarks" / "results" / f"{stem}.md", text)
        print(text)
        return
    repeats = 3 if args.quick else 7
    examples, duration = (50, 60.0) if args.quick else (200, 300.0)
    text = (f"# Verifier speed\n\n{platform.python_implementation()} "
            f"{platform.python_version()}, {platform.machine()}; "
            f"`python3 benchmarks/bench_verify.py{' --quick' if args.quick else ''}`\n\n"
            f"## Exact checks on the paper rule bases\n\n"
            f"Coverage proof, consistency, completeness, continuity and a monotone-table check "
            f"per input, median of {repeats} runs.\n\n{bench_exact(repeats)}\n"
            f"## Closed-loop search, WEDM finish cut\n\n"
            f"Hypothesis draws plant height (with steps) and tension; all examples run as one "
            f"batch; failures are shrunk in batched rounds.\n\n"
            f"{bench_closed_loop(examples, duration)}")
    write_result(ROOT / "benchmarks" / "results" / "verify.md", text)
    print(text)


if __name__ == "__main__":
    main()
