"""One figure of issue 29's table, measured in this (fresh) process beside its reference.

    python benchmarks/figures.py NAME [--quick]

prints one JSON line: {"rows": [...]} where each row has the figure's label, value and unit, its
reference's label and value, the ratio of the two (how it is taken is in "ratio_means"), the
issue's target and whether it is met, and notes.  benchmarks/run_all.py runs every NAME in a
fresh process of its own (FIGURES lists them with the environment each needs), prints the rows
beside the load average and writes benchmarks/results/summary.md.

Every time is CPU time (time.process_time, or the C driver's CLOCK_PROCESS_CPUTIME_ID; for
Dask the workers' CPU is added through getrusage(RUSAGE_CHILDREN) once they have exited), the
median of interleaved repeats: per repeat the figure and its reference run one after the other,
so a change of the machine's load falls on both.  Two goals are speed-ups from running on
several cores (threads, Dask workers): CPU time cannot show those, so their ratio is taken on
wall time (time.perf_counter), the CPU time printed beside it.
"""
from __future__ import annotations

import json
import os
import pathlib
import resource
import statistics
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"
sys.path.insert(0, str(BENCH))
sys.path.append(str(ROOT))   # after site-packages: fuzzyc is the installed one
# where `make bench` installs ferrifuzz (pip install --no-deps --target): not in the dev env
BENCH_DEPS = ROOT / "build" / "bench-deps"

from common import faults_per_call, triangle_outputs  # noqa: E402

WEDM = ROOT / "rulebases" / "wedm_three_region.fz"
QUICK = "--quick" in sys.argv
REPEATS = 3 if QUICK else 7


def repeats_cpu(fns, repeats: int = REPEATS, clock=time.process_time) -> np.ndarray:
    """(repeats, len(fns)) seconds: one warm-up call of each, then per repeat each fn once, in
    turn."""
    for fn in fns:
        fn()
    times = np.empty((repeats, len(fns)))
    for r in range(repeats):
        for k, fn in enumerate(fns):
            start = clock()
            fn()
            times[r, k] = clock() - start
    return times


def median_ratio(times: np.ndarray, num: int, den: int) -> float:
    """The median over the repeats of times[:, num] / times[:, den]."""
    return float(np.median(times[:, num] / times[:, den]))


def row(label, value, unit, ref_label, ref_value, ratio, ratio_means, target, met, notes=""):
    def num(v):
        return None if v is None else float(v)
    return {"label": label, "value": num(value), "unit": unit, "reference": ref_label,
            "ref_value": num(ref_value), "ratio": num(ratio), "ratio_means": ratio_means,
            "target": target, "met": None if met is None else bool(met), "notes": notes}


def wedm():
    from fuzzyc.language.parser import load
    return load(WEDM).rulebase


def trim_note() -> str:
    trim = os.environ.get("MALLOC_TRIM_THRESHOLD_")
    return f"MALLOC_TRIM_THRESHOLD_={trim}" if trim else "glibc's default thresholds"


# -- engine ---------------------------------------------------------------------------------

def engine(method: str, n: int) -> list[dict]:
    """Engine evaluations/s on WEDM at batch n beside np.copyto of the same (n, 3) input."""
    from fuzzyc.engine.inference import evaluate
    rb = wedm() if method == "coa" else triangle_outputs(wedm())
    goal = {("coa", 1_000_000): 30e6, ("coa", 100_000): 25e6}.get((method, n), 15e6)
    nominal = n
    n = min(n, 20_000) if QUICK else n          # the target stays the nominal batch's
    x = np.random.default_rng(0).uniform(-1, 1, (n, 3))
    out = np.empty_like(x)
    fns = [lambda: evaluate(rb, x), lambda: np.copyto(out, x)]
    times = repeats_cpu(fns)
    rate = n / float(np.median(times[:, 0]))
    copy_rate = n / float(np.median(times[:, 1]))
    ratio = median_ratio(times, 0, 1)
    faults = faults_per_call(fns[0])
    name = "COA" if method == "coa" else "exact centroid (triangle outputs)"
    if method == "coa":
        target = f">= {goal / 1e6:.0f} M/s, <= 15x the copy"
        met = rate >= goal and ratio <= 15
    else:
        target = f">= {goal / 1e6:.0f} M/s"
        met = rate >= goal
    if n != nominal:
        target += f" (batch {nominal:,}'s target)"
    return [row(f"engine {name}, WEDM, batch {n:,} ({trim_note()})", rate, "evals/s",
                "np.copyto of the input", copy_rate, ratio, "engine time / copy time",
                target, met, f"{faults:,.0f} minor faults per call")]


# -- one evaluation from Python -------------------------------------------------------------

def ferrifuzz_wedm(rb):
    """ferrifuzz's FuzzySystem for WEDM (its defaults: Mamdani, min/max, centroid), input and
    output terms as in the file (shoulders cut beyond the range, which it clamps inputs to),
    the 75 rules; None when ferrifuzz is not importable."""
    if BENCH_DEPS.is_dir():
        sys.path.append(str(BENCH_DEPS))
    try:
        import ferrifuzz as ff
    except ImportError:
        return None, None

    def variable(v):
        var = ff.Variable(v.name, float(v.lo), float(v.hi))
        span = float(v.hi - v.lo)
        for name, (a, b, c, d) in zip(v.names, v.params):
            a = b - span if not np.isfinite(a) else a
            b = a if not np.isfinite(b) else b
            d = c + span if not np.isfinite(d) else d
            c = d if not np.isfinite(c) else c
            var[name] = (ff.mf.triangle(float(a), float(b), float(d)) if b == c
                         else ff.mf.trapezoid(float(a), float(b), float(c), float(d)))
        return var

    system = ff.FuzzySystem()
    for v in rb.inputs:
        system.add_input(variable(v))
    for v in rb.outputs:
        system.add_output(variable(v))
    for ante, cons in zip(rb.antecedents, rb.consequents):
        when = " AND ".join(f"{v.name} IS {v.names[t]}" for v, t in zip(rb.inputs, ante))
        then = " AND ".join(f"{v.name} IS {v.names[t]}" for v, t in zip(rb.outputs, cons))
        system += f"IF {when} THEN {then}"
    return system, getattr(ff, "__version__", "?")


def python_step() -> list[dict]:
    """CPU us per one-point evaluation from Python: the compiled header through ctypes
    (fuzzyc.compiled_evaluator), the scalar path, fuzzyc.evaluate(model, dict),
    Controller.step, beside ferrifuzz's positional evaluate, passes interleaved."""
    import fuzzyc
    from fuzzyc.engine.chain import Controller
    from fuzzyc.engine.inference import evaluate, scalar_evaluator
    model = fuzzyc.load(WEDM)
    rb = model.rulebase
    points_n = 200 if QUICK else 2000
    x = np.random.default_rng(0).uniform(-1, 1, (points_n, 3))
    points = x.tolist()
    named = [dict(zip([v.name for v in rb.inputs], p)) for p in points]
    scalar = scalar_evaluator(rb)
    compiled = fuzzyc.compiled_evaluator(model)
    for label, fn in [("the scalar path", scalar), ("the compiled evaluator", compiled)]:
        if not np.array_equal(np.array([fn(p) for p in points]), evaluate(rb, x)):
            raise SystemExit(f"{label} and the batch engine disagree")
    controller = Controller(model, batch=1)
    lo = np.array([s.lo for s in model.signals], dtype=float)
    hi = np.array([s.hi for s in model.signals], dtype=float)
    steps = [{s.name: np.array([v]) for s, v in zip(model.signals, r)}
             for r in np.random.default_rng(1).uniform(lo, hi, (points_n, len(lo)))]
    triangles = triangle_outputs(rb)
    system, version = ferrifuzz_wedm(triangles)

    def over(fn, items):
        return lambda: [fn(item) for item in items]

    fns = [over(compiled, points), over(scalar, points),
           over(lambda d: fuzzyc.evaluate(model, d), named), over(controller.step, steps)]
    ref = len(fns)
    gap = None
    if system is not None:
        fns.append(over(system.evaluate, points))
        ours = evaluate(triangles, x)
        answers = [system.evaluate(p) for p in points[:200]]
        theirs = np.array([list(a.values()) if isinstance(a, dict) else list(a)
                           for a in answers])
        gap = float(np.abs(theirs - ours[:200]).max())
    times = repeats_cpu(fns) / points_n * 1e6
    med = np.median(times, axis=0)
    if system is None:
        ref_label, ref_value = "ferrifuzz: not installed (pip install ferrifuzz failed)", None
    else:
        ref_label = (f"ferrifuzz {version} system.evaluate (Mamdani centroid; max diff "
                     f"{gap:.1e} from fuzzyc's exact centroid)")
        ref_value = float(med[ref])
    rows = []
    for k, label in enumerate(["compiled header (fuzzyc.compiled_evaluator(model))",
                               "scalar path (scalar_evaluator(rb))",
                               "fuzzyc.evaluate(model, dict)", "Controller.step, batch 1"]):
        ratio = median_ratio(times, k, ref) if system is not None else None
        target = "<= 5 us, faster than ferrifuzz" if k == 0 else "(beside the compiled header)"
        met = (med[0] <= 5 and (ref_value is None or med[0] < ref_value)) if k == 0 else None
        rows.append(row(f"one evaluation from Python, WEDM: {label}", float(med[k]), "us",
                        ref_label, ref_value, ratio, "fuzzyc time / ferrifuzz time", target,
                        met, f"{points_n} points per pass"
                        + ("; bits equal to the batch engine's" if k < 2 else "")))
    return rows


# -- threads --------------------------------------------------------------------------------

def threads() -> list[dict]:
    """Engine COA at 1e6 with threads=2 against threads=1 (same bits checked): wall time."""
    from fuzzyc.engine.inference import evaluate
    rb = wedm()
    n = 20_000 if QUICK else 1_000_000
    x = np.random.default_rng(0).uniform(-1, 1, (n, 3))
    if not np.array_equal(evaluate(rb, x, threads=2), evaluate(rb, x)):
        raise SystemExit("threads=2 changed the bits")
    fns = [lambda: evaluate(rb, x, threads=2), lambda: evaluate(rb, x)]
    wall = repeats_cpu(fns, clock=time.perf_counter)
    cpu = repeats_cpu(fns)
    speedup = median_ratio(wall, 1, 0)
    return [row(f"engine COA, WEDM, batch {n:,}, threads=2 (bits equal to threads=1)",
                n / float(np.median(wall[:, 0])), "evals/s wall", "threads=1",
                n / float(np.median(wall[:, 1])), speedup,
                "speed-up: threads=1 wall time / threads=2 wall time", ">= 1.7x",
                speedup >= 1.7,
                f"CPU s per call {np.median(cpu[:, 0]):.3f} (2 threads) vs "
                f"{np.median(cpu[:, 1]):.3f} (1)")]


# -- alternating batch sizes ----------------------------------------------------------------

def alternation() -> list[dict]:
    """Batch 1 and batch 1000 calls alternating on one rule base against each size alone: the
    CPU time of a pair (one call of each) alternating over the sum of the two alone."""
    from fuzzyc.engine.inference import evaluate
    sys.path.insert(0, str(BENCH))
    from bench_wide import full_grid
    rows = []
    pairs = 30 if QUICK else 200
    for label, rb in [("WEDM (3 inputs, 75 rules)", wedm()),
                      ("full table of 6 inputs (729 rules)", full_grid(6))]:
        n_in = len(rb.inputs)
        rng = np.random.default_rng(0)
        ones = [rng.uniform(-1, 1, (1, n_in)) for _ in range(pairs)]
        thousands = [rng.uniform(-1, 1, (1000, n_in)) for _ in range(8)]

        def alone_one():
            for x in ones:
                evaluate(rb, x)

        def alone_thousand():
            for k in range(pairs):
                evaluate(rb, thousands[k % 8])

        def alternating():
            for k, x in enumerate(ones):
                evaluate(rb, x)
                evaluate(rb, thousands[k % 8])

        times = repeats_cpu([alternating, alone_one, alone_thousand])
        ratios = times[:, 0] / (times[:, 1] + times[:, 2])
        ratio = float(np.median(ratios))
        pair_us = float(np.median(times[:, 0])) / pairs * 1e6
        alone_us = float(np.median(times[:, 1] + times[:, 2])) / pairs * 1e6
        rows.append(row(f"alternating batch 1 / batch 1000, {label}", pair_us, "us per pair",
                        "each size alone (batch 1 + batch 1000)", alone_us, ratio,
                        "alternating time / alone time", "<= 1.2x", ratio <= 1.2,
                        f"batch 1 alone {np.median(times[:, 1]) / pairs * 1e6:.1f} us, "
                        f"batch 1000 alone {np.median(times[:, 2]) / pairs * 1e6:.1f} us"))
    return rows


# -- generated C against the hand-written versions ------------------------------------------

def c_headers() -> list[dict]:
    """ns per call at gcc -O2 (timing loop in C, CPU time, median of interleaved repeats):
    the generated float COA header and the generated q15 header against the hand-written
    active-rules versions, float and q15, of the same rule base."""
    import shutil
    import subprocess
    import tempfile
    import bench_c
    from fuzzyc.language.parser import load
    if shutil.which("gcc") is None:
        return [row("generated C (gcc missing)", None, "ns", "", None, None, "", "<= 1.1x",
                    None, "gcc not found")]
    model = load(WEDM)
    entries = bench_c.entries(model)
    keep = {"float": next(e for e in entries if e[0].startswith("C float, rule base")),
            "q15": next(e for e in entries if e[0].startswith("C q15 rule base"))}
    hand_q15 = bench_c.hand_q15_entry()
    all_entries = [("gen_float", keep["float"]), ("gen_q15", keep["q15"]),
                   ("hand_q15", hand_q15)]
    repeats = 5 if QUICK else 21
    iterations = 10_000 if QUICK else 100_000
    with tempfile.TemporaryDirectory() as work:
        ns = bench_c.run_driver(all_entries, pathlib.Path(work), repeats=repeats,
                                iterations=iterations,
                                hand=("hand_wedm_active_rules",),
                                extra_sources=("hand_wedm_active_rules_q15.c",))
    notes = (f"gcc {' '.join(bench_c.FLAGS)}, median of {repeats} interleaved runs of "
             f"{iterations:,} calls; both q15 entries include the same float-to-q15 input "
             "conversion")
    out = []
    for key, hand_key, label, hand_label in [
            ("gen_float", "hand_wedm_active_rules", "generated float header, COA",
             "hand-written active-rules C, float"),
            ("gen_q15", "hand_q15", "generated q15 header, COA",
             "hand-written active-rules C, q15")]:
        ratio = ns[key] / ns[hand_key]
        out.append(row(f"{label}, WEDM, gcc -O2", ns[key], "ns per call", hand_label,
                       ns[hand_key], ratio, "generated time / hand-written time", "<= 1.1x",
                       ratio <= 1.1, notes))
    return out


# -- closed loop ----------------------------------------------------------------------------

def closed_loop() -> list[dict]:
    """WEDM test-1 loops (rule base + gap plant) at batch 1000: controller+plant steps per CPU
    second, beside the rule base alone evaluated on as many batches of 1000."""
    from bench_loop import _scenario
    from fuzzyc.engine.inference import evaluate
    from fuzzyc.runtime.blocks import PlantBlock  # noqa: F401
    from fuzzyc.runtime.loop import run
    from fuzzyc.runtime.simulate import build
    seconds = 1.0 if QUICK else 20.0
    batch = 1000
    scenario, controller = _scenario(seconds, batch)
    periods = int(round(seconds / scenario.period))
    rb = wedm()
    x = np.random.default_rng(0).uniform(-1, 1, (batch, 3))
    seeds = iter(range(10_000))

    def loop():
        blocks = build(scenario, controller, batch, next(seeds), randomize=True)
        start = time.process_time()
        trace = run(blocks, scenario.period, scenario.duration, batch,
                    initial=scenario.data.get("initial"), record=["abnormal_ratio"])
        loop.seconds = time.process_time() - start
        loop.steps = trace.steps

    def engine_alone():
        for _ in range(periods):
            evaluate(rb, x)

    # the loop's own clock excludes building its blocks
    loop()
    engine_alone()
    loop_t, engine_t = [], []
    for _ in range(REPEATS):
        loop()
        loop_t.append(loop.seconds)
        start = time.process_time()
        engine_alone()
        engine_t.append(time.process_time() - start)
    loop_t, engine_t = np.array(loop_t), np.array(engine_t)
    rate = loop.steps * batch / float(np.median(loop_t))
    engine_rate = periods * batch / float(np.median(engine_t))
    ratio = float(np.median(loop_t / engine_t))
    return [row(f"closed loop, WEDM test 1, batch {batch}", rate, "steps/s",
                "the rule base alone, as many batch-1000 calls", engine_rate, ratio,
                "loop time / rule base time", ">= 4 M steps/s", rate >= 4e6,
                f"{seconds:g} simulated s per run")]


# -- Dask -----------------------------------------------------------------------------------

def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def dask() -> list[dict]:
    """A campaign in this process against the same on `--workers 2`: the campaign's wall time
    (the speed-up) without the cluster's start-up and close, which are stated apart; CPU time
    of this process and its exited children (the workers) beside it.  The summaries must be
    equal bit for bit."""
    from fuzzyc.runtime.campaign import Cluster, simulate_campaign
    from fuzzyc.plants.scenario import load
    loops = 8_000 if QUICK else 1_000_000
    seconds = 0.2 if QUICK else 5.0
    chunk = 2_000 if QUICK else 10_000
    repeats = 1 if QUICK else 5
    scenario = load("wedm_finish", {"duration": str(seconds)})
    command = (f"fuzzyc simulate --scenario wedm_finish --set duration={seconds:g} --batch "
               f"{loops} --randomize --chunk {chunk}")
    summaries = set()
    local_wall, local_cpu, dask_wall, dask_cpu, start_up, close = [], [], [], [], [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        campaign = simulate_campaign(scenario, loops, Cluster(chunk=chunk, progress=False),
                                     randomize=True)
        local_wall.append(time.perf_counter() - w0)
        local_cpu.append(time.process_time() - c0)
        summaries.add(json.dumps(campaign.summary))
        ch0, c0, w0 = children_cpu(), time.process_time(), time.perf_counter()
        with Cluster(workers=2, chunk=chunk, progress=False) as cluster:
            cluster.client()
            w1 = time.perf_counter()
            campaign = simulate_campaign(scenario, loops, cluster, randomize=True)
            w2 = time.perf_counter()
        w3 = time.perf_counter()
        start_up.append(w1 - w0)
        dask_wall.append(w2 - w1)
        close.append(w3 - w2)
        dask_cpu.append(time.process_time() - c0 + children_cpu() - ch0)
        summaries.add(json.dumps(campaign.summary))
    if len(summaries) != 1:
        raise SystemExit("the campaign's summary differs between in-process and Dask")
    speedup = float(np.median(np.array(local_wall) / np.array(dask_wall)))
    med = statistics.median
    return [row(f"Dask campaign, --workers 2 ({loops:,} loops of {seconds:g} s, chunk {chunk:,})",
                loops / med(dask_wall), "loops/s wall", "in this process",
                loops / med(local_wall), speedup,
                "speed-up: in-process wall time / Dask wall time (start-up and close apart)",
                ">= 1.7x on a campaign of >= 60 s", speedup >= 1.7 and med(local_wall) >= 60,
                f"`{command} [--workers 2]`; in-process {med(local_wall):.1f} s wall, "
                f"{med(local_cpu):.1f} s CPU; Dask {med(dask_wall):.1f} s wall, "
                f"{med(dask_cpu):.1f} s CPU with the workers (their start-up included); "
                f"cluster start-up "
                f"{med(start_up):.2f} s, close {med(close):.2f} s; summaries equal")]


FIGURES = {
    "engine-coa-1e5": lambda: engine("coa", 100_000),
    "engine-coa-1e6": lambda: engine("coa", 1_000_000),
    "engine-centroid-1e6": lambda: engine("centroid", 1_000_000),
    "python-step": python_step,
    "threads": threads,
    "alternation": alternation,
    "c-headers": c_headers,
    "closed-loop": closed_loop,
    "dask": dask,
}

if __name__ == "__main__":
    name = next(a for a in sys.argv[1:] if not a.startswith("--"))
    rows = FIGURES[name]()
    print(json.dumps({"rows": rows, "repeats": REPEATS}))
