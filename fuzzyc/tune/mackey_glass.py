"""The Mackey-Glass benchmark of Jang's ANFIS paper (1993): predict x(t+6) from x(t-18),
x(t-12), x(t-6), x(t) with 16 rules of two generalized-bell terms per input (104 parameters),
trained on 500 samples, checked on the next 500.

    python -m fuzzyc.tune.mackey_glass                          # the full run, its table
    python -m fuzzyc.tune.mackey_glass --passes 1 --max-nfev 3  # a quick one
    python -m fuzzyc.tune.mackey_glass --export DIR   # the rule file and data for fuzzyc tune

The series: dx/dt = 0.2 x(t-17) / (1 + x(t-17)^10) - 0.1 x(t), x(0) = 1.2, x(t) = 0 for t < 0,
fourth-order Runge-Kutta with step 0.1, the delayed value x(t-17) held over each step's four
stages (the usual discretisation of the delay; interpolating it at the half steps gives
another trajectory of the chaotic series, on which the same fit checks at NDEI 0.0118 against
0.0092 here, both with 150 evaluations); samples at t = 118..1117.
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


def series(t_end: float = 1130.0) -> np.ndarray:
    """x at t = 0, 0.1, ..., t_end (index k is t = k * STEP)."""
    lag = int(round(TAU / STEP))
    n = int(round(t_end / STEP)) + 1
    x = np.zeros(n)
    x[0] = X0

    def delayed(k: int) -> float:              # x(k STEP - TAU); 0 before t = 0
        return x[k - lag] if k >= lag else 0.0

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


def dataset() -> tuple[np.ndarray, np.ndarray]:
    """(X (1000, 4), y (1000,)) for t = 118..1117: inputs x(t-18), x(t-12), x(t-6), x(t),
    target x(t+6)."""
    x = series()
    per = int(round(1 / STEP))
    t = np.arange(118, 1118)
    X = np.column_stack([x[(t - lag) * per] for lag in (18, 12, 6, 0)])
    return X, x[(t + 6) * per]


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


def run(passes: int, max_nfev: int | None, seed: int = 0, bounded: tuple | None = None):
    """(the fit, NDEI train, NDEI check, CPU seconds) of the 104-parameter ANFIS; `bounded`
    (lo, hi): with `verify { bounded y in [lo, hi] }` added to the file, kept by the tuner."""
    from ..language.parser import parse
    from .fit import fit_data
    text = rule_file().read_text()
    if bounded is not None:
        text = text.replace("  tune {", f"  verify {{\n    bounded y in [{bounded[0]:g}, "
                                         f"{bounded[1]:g}]\n  }}\n  tune {{")
    model = parse(text, str(rule_file()))
    X, y = dataset()
    start = time.process_time()
    fit = fit_data(model, X[:500], y[:500], validate=(X[500:], y[500:]), seed=seed,
                   passes=passes, max_nfev=max_nfev)
    seconds = time.process_time() - start
    return fit, fit.rmse_after / np.std(y[:500]), fit.validation / np.std(y[500:]), seconds


def table(fit, ndei_train: float, ndei_check: float, seconds: float, passes: int,
          max_nfev: int | None, kept: list | None = None) -> str:
    """The table; `kept`: (label, fit, NDEI train, NDEI check, seconds) of constrained runs."""
    def row(label, fit, train, check, seconds):
        return (label, f"{train:.4f}", f"{check:.4f}", str(len(fit.numbers)), f"{seconds:.0f} s")
    rows = [("", "NDEI train", "NDEI check", "parameters", "CPU time"),
            row(f"fuzzyc tune ({passes} pass{'es' if passes != 1 else ''}, max_nfev "
                f"{max_nfev})", fit, ndei_train, ndei_check, seconds),
            *(row(*k) for k in kept or []),
            ("Jang 1993, ANFIS (500 epochs)", "-", f"{JANG_NDEI_CHECK:.3f}", "104", "-")]
    lines = ["| " + " | ".join(row) + " |" for row in rows]
    lines.insert(1, "|" + "---|" * len(rows[0]))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m fuzzyc.tune.mackey_glass",
                                     description=__doc__.split("\n\n")[0])
    # one hybrid pass (the consequents by least squares on the written bells) and then the
    # joint least squares to convergence: the best checking error of the settings tried
    # (20 passes and 300 evaluations: NDEI check 0.0100)
    parser.add_argument("--passes", type=int, default=1, help="hybrid passes (default 1)")
    parser.add_argument("--max-nfev", type=int, default=1000,
                        help="evaluations per least-squares run (default 1000)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--bounded", type=float, nargs=2, metavar=("LO", "HI"),
                        help="also tune with `bounded y in [LO, HI]` kept (a second row)")
    parser.add_argument("-o", "--output", help="write the tuned .fz here")
    parser.add_argument("--export", metavar="DIR", help="only write the rule file, train.csv "
                        "and check.csv to DIR (for `fuzzyc tune`)")
    args = parser.parse_args(argv)
    if args.export:
        for path in export(Path(args.export)):
            print(f"wrote {path}")
        return 0
    fit, ndei_train, ndei_check, seconds = run(args.passes, args.max_nfev, args.seed)
    kept = []
    if args.bounded:
        lo, hi = args.bounded
        bounded = run(args.passes, args.max_nfev, args.seed, (lo, hi))
        kept.append((f"the same, keeping bounded y in [{lo:g}, {hi:g}]", *bounded))
    print("Mackey-Glass x(t+6), 500 training and 500 checking samples (t = 118..1117); "
          "NDEI = RMSE / standard deviation of the target")
    print(table(fit, ndei_train, ndei_check, seconds, args.passes, args.max_nfev, kept))
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
        lines = [f"python -m fuzzyc.tune.mackey_glass --passes {args.passes} --max-nfev "
                 f"{args.max_nfev} --seed {args.seed}: {fit.method}",
                 f"NDEI train {ndei_train:.6g}, check {ndei_check:.6g}"]
        Path(args.output).write_text(rewrite(model.source_text, fit.numbers, fit.values, lines))
        print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
