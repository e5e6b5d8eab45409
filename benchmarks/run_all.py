"""`make bench`: every figure of issue 29 beside its reference, each in a fresh process.

    python benchmarks/run_all.py [--quick] [--out PATH] [--only NAME ...]
    python benchmarks/run_all.py --docs [SUMMARY]      # copy a summary into docs/benchmarks.md
    python benchmarks/run_all.py --tables              # the per-benchmark tables (results/*.md)

Runs `benchmarks/figures.py NAME` once per figure, each in a new Python process (the engine's
figures once more with Dask's allocator setting, MALLOC_TRIM_THRESHOLD_=65536), prints every
row as it comes (value, reference, ratio, the issue's target, met or not, the load average
before and after that figure) and writes one table to benchmarks/results/summary.md
(summary-quick.md with --quick: few repeats and small sizes, a check that the harness works,
not figures to quote).  figures.py's docstring says how each is timed.

--docs puts a summary's table (and its header lines) between the markers in
docs/benchmarks.md: the doc's figures are the run's, never typed in.  --tables runs the older
per-benchmark scripts, which write their own tables to benchmarks/results/ (wide rule bases,
all generated C variants, verifier, ARM, C proofs).
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import pathlib
import platform
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "results"
DOC = ROOT / "docs" / "benchmarks.md"
BEGIN, END = "<!-- summary.md begins -->", "<!-- summary.md ends -->"
DASK_ALLOCATOR = {"MALLOC_TRIM_THRESHOLD_": "65536"}

# (figures.py name, extra environment)
FIGURES = [
    ("engine-coa-1e5", {}),
    ("engine-coa-1e5", DASK_ALLOCATOR),
    ("engine-coa-1e6", {}),
    ("engine-coa-1e6", DASK_ALLOCATOR),
    ("engine-centroid-1e6", {}),
    ("engine-centroid-1e6", DASK_ALLOCATOR),
    ("python-step", {}),
    ("threads", {}),
    ("alternation", {}),
    ("c-headers", {}),
    ("closed-loop", {}),
    ("dask", {}),
]
TABLE_SCRIPTS = ["bench_engine.py", "bench_wide.py", "bench_c.py", "bench_loop.py",
                 "bench_verify.py", "bench_arm.py", "bench_c_proofs.py"]


def fmt(value: float | None, unit: str) -> str:
    if value is None:
        return "-"
    if unit.startswith(("evals/s", "steps/s", "loops/s")):
        return f"{value / 1e6:.2f} M{unit[unit.index('/'):]}" if value >= 1e6 \
            else f"{value:,.0f} {unit}"
    return f"{value:,.1f} {unit}" if value < 1000 else f"{value:,.0f} {unit}"


def met_text(met: bool | None) -> str:
    return "-" if met is None else ("met" if met else "**not met**")


def run_figure(name: str, env_extra: dict, quick: bool) -> tuple[list[dict], str, float]:
    """(rows, load text, wall seconds) of one figure, in a fresh process."""
    env = dict(os.environ, **env_extra)
    load_before = os.getloadavg()
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, str(HERE / "figures.py"), name]
                          + (["--quick"] if quick else []),
                          env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    load_after = os.getloadavg()
    load = f"{load_before[0]:.1f} -> {load_after[0]:.1f}"
    if proc.returncode != 0:
        tail = (proc.stderr.strip().splitlines() or ["(no output)"])[-1]
        return [{"label": f"{name}: FAILED ({tail})", "value": None, "unit": "",
                 "reference": "", "ref_value": None, "ratio": None, "ratio_means": "",
                 "target": "", "met": False, "notes": "", "failed": True}], load, wall
    return json.loads(proc.stdout.strip().splitlines()[-1])["rows"], load, wall


def git_state() -> str:
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                              capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=ROOT, capture_output=True, text=True).stdout.strip()
        return head + (" with uncommitted changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def summary(quick: bool, only: list[str] | None, out: pathlib.Path) -> int:
    import numpy as np
    started = datetime.datetime.now(datetime.timezone.utc)
    figures = [f for f in FIGURES if not only or f[0] in only]
    table = ["| figure | value | reference | ratio | target | met | load avg (1 min) | "
             "run s | notes |", "|---|---|---|---|---|---|---|---|---|"]
    failed = 0
    for name, env_extra in figures:
        print(f"== {name}" + "".join(f" {k}={v}" for k, v in env_extra.items()), flush=True)
        rows, load, wall = run_figure(name, env_extra, quick)
        for r in rows:
            failed += bool(r.get("failed"))
            ratio = "-" if r["ratio"] is None else f"{r['ratio']:.2f}x"
            ref = r["reference"] + ("" if r["ref_value"] is None
                                    else f": {fmt(r['ref_value'], r['unit'])}")
            notes = "; ".join(n for n in (f"ratio = {r['ratio_means']}" if r["ratio_means"]
                                         else "", r["notes"]) if n)
            cells = [r["label"], fmt(r["value"], r["unit"]), ref, ratio, r["target"],
                     met_text(r["met"]), load, f"{wall:.0f}", notes]
            table.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
            print(f"   {cells[0]}: {cells[1]} | ref {cells[2]} | {cells[3]} | target "
                  f"{cells[4]}: {cells[5]} | load {load}", flush=True)
    finished = datetime.datetime.now(datetime.timezone.utc)
    head = [
        "# make bench: issue 29's figures" + (" (QUICK: harness check, not figures)"
                                              if quick else ""),
        "",
        f"Run {started:%Y-%m-%d %H:%M} - {finished:%H:%M} UTC "
        f"({(finished - started).total_seconds() / 60:.1f} min), commit {git_state()}; "
        f"{platform.machine()}, {os.cpu_count()} CPUs, CPython {platform.python_version()}, "
        f"numpy {np.__version__}; `python benchmarks/run_all.py"
        f"{' --quick' if quick else ''}`.",
        "",
        "Each figure in a fresh process (`benchmarks/figures.py NAME`), CPU time, the median of "
        f"{'3' if quick else '7'} repeats (C: {'5' if quick else '21'}; Dask: "
        f"{'1' if quick else '5'}) interleaved with its reference; the threads and Dask "
        "speed-ups on wall time (CPU time cannot show cores working at once). The load "
        "average is the machine's 1-minute figure before and after the figure's process: "
        f"on {os.cpu_count()} CPUs, a load above 1 means other work shared the cores and the "
        "figure is not a quiet one.",
        "",
    ]
    text = "\n".join(head + table) + "\n"
    out.parent.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(ROOT))
    from fuzzyc.atomic import write_text
    write_text(out, text)
    print(f"wrote {out}")
    return 1 if failed else 0


def docs(source: pathlib.Path, doc_path: pathlib.Path = DOC) -> int:
    """Put the summary between the markers of docs/benchmarks.md (a quick run refused)."""
    sys.path.insert(0, str(ROOT))
    from fuzzyc.atomic import write_text
    body = source.read_text()
    if "QUICK" in body.splitlines()[0]:
        print(f"{source} is a --quick run: not figures for the docs")
        return 1
    body = body.split("\n", 2)[2]          # the doc has its own title
    doc = doc_path.read_text()
    before, _, rest = doc.partition(BEGIN)
    _, _, after = rest.partition(END)
    if not rest:
        print(f"{doc_path} has no {BEGIN} marker")
        return 1
    write_text(doc_path, f"{before}{BEGIN}\n{body.strip()}\n{END}{after}")
    print(f"{doc_path}: the table of {source}")
    return 0


def tables() -> int:
    for script in TABLE_SCRIPTS:
        print(f"== {script}", flush=True)
        subprocess.run([sys.executable, str(HERE / script)], check=True)
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("--only", nargs="+", metavar="NAME",
                    choices=sorted({name for name, _ in FIGURES}))
    ap.add_argument("--docs", nargs="?", type=pathlib.Path, const=RESULTS / "summary.md")
    ap.add_argument("--tables", action="store_true")
    args = ap.parse_args(argv)
    if args.docs:
        return docs(args.docs)
    if args.tables:
        return tables()
    out = args.out or RESULTS / ("summary-quick.md" if args.quick else "summary.md")
    return summary(args.quick, args.only, out)


if __name__ == "__main__":
    sys.exit(main())
