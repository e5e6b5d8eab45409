"""The Mackey-Glass benchmark of Jang's ANFIS paper (1993): predict x(t+6) from x(t-18),
x(t-12), x(t-6), x(t) with 16 rules of two generalized-bell terms per input (104 parameters),
trained on 500 samples, checked on the next 500.

    python -m fuzzyc.tune.mackey_glass                  # Jang's rule, 500 epochs, its table
    python -m fuzzyc.tune.mackey_glass --epochs 20      # a quick one
    python -m fuzzyc.tune.mackey_glass --method least_squares --passes 1 --max-nfev 1000
    python -m fuzzyc.tune.mackey_glass --export DIR   # the rule file and data for fuzzyc tune

The series: dx/dt = 0.2 x(t-17) / (1 + x(t-17)^10) - 0.1 x(t), x(0) = 1.2, x(t) = 0 for t < 0,
as Jang's own generator computes it (mackeyglass.c, "Roger Jang, UC Berkeley, 1992", which
prints t = 0..1200 with six decimals, the layout of MATLAB's mgdata.dat): fourth-order
Runge-Kutta with step 0.1, the delayed value read from a ring of the last 170 values computed
(zero at first, x(0) never in it), so the step from x_k holds x_{k-169} over its four stages,
one step later than x(t - 17).  The chaotic series is that sensitive: with x_{k-170} instead
(this module until issue 31's ANFIS work; --delay-steps 170) the same 500 epochs give NDEI
train 0.0061, check 0.0094 against 0.0056 and 0.0052, the checking error above the training
error where Jang's paper and MATLAB's demo have it below.
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

TAU, STEP, X0 = 17.0, 0.1, 1.2
INPUTS = ("x18", "x12", "x6", "x0")         # x(t-18), x(t-12), x(t-6), x(t)
JANG_NDEI_CHECK = 0.007                      # Jang 1993, ANFIS, checking data
FZ_FILE = Path(__file__).resolve().parents[2] / "rulebases" / "mackey_glass_anfis.fz"


def series(t_end: float = 1200.0, back: int = 169) -> np.ndarray:
    """x at t = 0, 0.1, ..., t_end (index k is t = k * STEP), as mackeyglass.c computes it;
    back = 170 reads x_{k-170} = x(t - 17) instead (--delay-steps 170)."""
    lag = int(round(TAU / STEP))
    n = int(round(t_end / STEP)) + 1
    x = np.zeros(n)
    x[0] = X0

    def delayed(k: int) -> float:              # the ring's oldest: x_{k-169}; 0 before
        return x[k - back] if k >= lag else 0.0

    def f(value: float, past: float) -> float:
        return 0.2 * past / (1.0 + past ** 10) - 0.1 * value

    for k in range(n - 1):
        past = delayed(k)        # held over the step's four stages
        k1 = f(x[k], past)
        k2 = f(x[k] + 0.5 * STEP * k1, past)
        k3 = f(x[k] + 0.5 * STEP * k2, past)
        k4 = f(x[k] + STEP * k3, past)
        x[k + 1] = x[k] + STEP / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def samples(back: int = 169) -> np.ndarray:
    """x(t) at t = 0, 1, ..., 1200 with six decimals (mgdata.dat's column: printf %f)."""
    return np.array([float(f"{v:f}") for v in series(back=back)[::int(round(1 / STEP))]])


def dataset(back: int = 169) -> tuple[np.ndarray, np.ndarray]:
    """(X (1000, 4), y (1000,)) for t = 118..1117: inputs x(t-18), x(t-12), x(t-6), x(t),
    target x(t+6)."""
    x = samples(back)
    t = np.arange(118, 1118)
    X = np.column_stack([x[t - lag] for lag in (18, 12, 6, 0)])
    return X, x[t + 6]


def rule_file() -> Path:
    """examples/tuning/mackey_glass_anfis.fz, in the source tree or as installed."""
    import fuzzyc.rulebases
    return (Path(fuzzyc.rulebases.__file__).resolve().parent.parent / "examples" / "tuning"
            / "mackey_glass_anfis.fz")


def export(folder: Path) -> list[Path]:
    """The rule file and the data as files (train.csv, check.csv), for `fuzzyc tune`."""
    from .data import write_csv
    folder.mkdir(parents=True, exist_ok=True)
    X, y = dataset()
    names = [*INPUTS, "y"]
    written = [folder / "mackey_glass_anfis.fz", folder / "train.csv", folder / "check.csv"]
    written[0].write_text(rule_file().read_text())
    write_csv(written[1], names, np.column_stack([X[:500], y[:500]]))
    write_csv(written[2], names, np.column_stack([X[500:], y[500:]]))
    return written


def run(passes: int, max_nfev: int | None, seed: int = 0, bounded: tuple | None = None,
        method: str = "anfis", back: int = 169, monotone: str | None = None):
    """(the fit, NDEI train, NDEI check, CPU seconds) of the 104-parameter ANFIS; `bounded`
    (lo, hi): with `verify { bounded y in [lo, hi] }` added to the file, kept by the tuner;
    `monotone` an input: `monotone y increasing in` it, likewise.
    method "anfis": Jang's rule, `passes` epochs; "least_squares": the hybrid passes and the
    joint least squares (max_nfev evaluations)."""
    from ..language.parser import parse
    from .fit import fit_data
    text = rule_file().read_text()
    lines = [f"bounded y in [{bounded[0]:g}, {bounded[1]:g}]"] if bounded is not None else []
    lines += [f"monotone y increasing in {monotone}"] if monotone is not None else []
    if lines:
        text = text.replace("  tune {", "  verify {\n" + "".join(f"    {v}\n" for v in lines)
                            + "  }\n  tune {")
    model = parse(text, str(rule_file()))
    X, y = dataset(back)
    start = time.process_time()
    fit = fit_data(model, X[:500], y[:500], validate=(X[500:], y[500:]), seed=seed,
                   passes=passes, max_nfev=max_nfev, method=method)
    seconds = time.process_time() - start
    return fit, fit.rmse_after / np.std(y[:500]), fit.validation / np.std(y[500:]), seconds


def row_name(method: str, passes: int, max_nfev: int | None) -> str:
    """The table's name for a run."""
    if method == "anfis":
        return f"fuzzyc tune, method anfis ({passes} epochs)"
    return f"fuzzyc tune ({passes} pass{'es' if passes != 1 else ''}, max_nfev {max_nfev})"


def table(fit, ndei_train: float, ndei_check: float, seconds: float, name: str,
          kept: list | None = None) -> str:
    """The table; `kept`: (label, fit, NDEI train, NDEI check, seconds) of constrained runs."""
    def row(label, fit, train, check, seconds):
        return (label, f"{train:.4f}", f"{check:.4f}", str(len(fit.numbers)), f"{seconds:.0f} s")
    rows = [("", "NDEI train", "NDEI check", "parameters", "CPU time"),
            row(name, fit, ndei_train, ndei_check, seconds),
            *(row(*k) for k in kept or []),
            ("Jang 1993, ANFIS (500 epochs)", "-", f"{JANG_NDEI_CHECK:.3f}", "104", "-")]
    lines = ["| " + " | ".join(row) + " |" for row in rows]
    lines.insert(1, "|" + "---|" * len(rows[0]))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzzyc.tune.mackey_glass",
                                     description=__doc__.split("\n\n")[0])
    # Jang's rule with his settings (500 epochs, k = 0.01 as MATLAB's anfis): one setting,
    # chosen before any run; nothing here reads the checking data but the table's column
    parser.add_argument("--method", choices=("anfis", "least_squares"), default="anfis")
    parser.add_argument("--epochs", type=int, default=500, help="anfis epochs (default 500)")
    parser.add_argument("--passes", type=int, default=1,
                        help="least_squares: hybrid passes (default 1)")
    parser.add_argument("--max-nfev", type=int, default=1000,
                        help="least_squares: evaluations per least-squares run (default 1000)")
    parser.add_argument("--delay-steps", type=int, default=169, choices=(169, 170),
                        help="the series' delay read: x_{k-169} as Jang's generator "
                        "(default), or x_{k-170}")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--bounded", type=float, nargs=2, metavar=("LO", "HI"),
                        help="also tune with `bounded y in [LO, HI]` kept (a second row)")
    parser.add_argument("--monotone", choices=INPUTS, metavar="INPUT",
                        help="also tune with `monotone y increasing in INPUT` kept (a row)")
    parser.add_argument("-o", "--output", help="write the tuned .fz here")
    parser.add_argument("--export", metavar="DIR", help="only write the rule file, train.csv "
                        "and check.csv to DIR (for `fuzzyc tune`)")
    args = parser.parse_args(argv)
    if args.export:
        for path in export(Path(args.export)):
            print(f"wrote {path}")
        return 0
    passes = args.epochs if args.method == "anfis" else args.passes
    fit, ndei_train, ndei_check, seconds = run(passes, args.max_nfev, args.seed,
                                               method=args.method, back=args.delay_steps)
    kept = []
    if args.bounded:
        lo, hi = args.bounded
        bounded = run(passes, args.max_nfev, args.seed, (lo, hi), args.method,
                      args.delay_steps)
        kept.append((f"the same, keeping bounded y in [{lo:g}, {hi:g}]", *bounded))
    if args.monotone:
        monotone = run(passes, args.max_nfev, args.seed, None, args.method, args.delay_steps,
                       args.monotone)
        kept.append((f"the same, keeping monotone y increasing in {args.monotone}", *monotone))
    print("Mackey-Glass x(t+6), 500 training and 500 checking samples (t = 118..1117); "
          "NDEI = RMSE / standard deviation of the target")
    if args.delay_steps != 169:
        print(f"series with the delay read x_(k-{args.delay_steps}), not Jang's generator's")
    print(table(fit, ndei_train, ndei_check, seconds,
                row_name(args.method, passes, args.max_nfev), kept))
    for label, fitted, *_ in kept:
        for c in fitted.properties:
            print(f"{label}: `{c.text}` {c.before} before tuning, {c.after} after")
        print(f"{label}: {fitted.method}")
        for why in fitted.rejected:
            print(f"{label}: rejected: {why}")
    if args.output:
        from ..language.parser import load
        from .rewrite import rewrite
        model = load(rule_file())
        lines = [f"python -m fuzzyc.tune.mackey_glass --method {args.method} --epochs "
                 f"{args.epochs} --passes {args.passes} --max-nfev {args.max_nfev} --seed "
                 f"{args.seed}: {fit.method}",
                 f"NDEI train {ndei_train:.6g}, check {ndei_check:.6g}"]
        Path(args.output).write_text(rewrite(model.source_text, fit.numbers, fit.values, lines))
        print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
