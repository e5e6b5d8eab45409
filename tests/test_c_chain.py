"""The whole signal chain in C against `fuzzyc.engine.chain.Controller`, and the example program
(examples/c/main.c) built from `fuzzyc compile` output, plain and under ASan + UBSan.
"""
from __future__ import annotations

import pathlib
import subprocess

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.load import STRICT_FLAGS, CController
from fuzzyc.cli import main as cli_main
from fuzzyc.engine.chain import Controller
from fuzzyc.engine.inference import evaluate
from fuzzyc.language.parser import load

from test_c_backend import CASES, SHIPPED, inputs_for, shipped

ROOT = pathlib.Path(__file__).resolve().parents[1]
MAIN_C = ROOT / "examples" / "c" / "main.c"
N_STEPS = 10_000
BATCH = 4
# double C is the engine's arithmetic; float32 integrators (feed += 1.8e-4 * du1 every step)
# round differently, a few 1e-6 of the range after 10,000 steps.
CHAIN_TOLERANCE = {"double": 1e-12, "float": 5e-5}


def random_sequences(model, seed: int) -> np.ndarray:
    """(steps, batch, signals): random walks over (and a little past) each signal's range, with
    a NaN or +-inf sample now and then."""
    rng = np.random.default_rng(seed)
    lo = np.array([s.lo for s in model.signals])
    hi = np.array([s.hi for s in model.signals])
    walk = np.cumsum(rng.normal(0.0, 0.006, (N_STEPS, BATCH, len(lo))), axis=0)
    x = lo + (hi - lo) * np.clip(0.5 + walk, -0.05, 1.05)
    bad = rng.random(x.shape) < 0.002
    x[bad] = rng.choice([np.nan, np.inf, -np.inf], int(bad.sum()))
    return x


def run_chain(controller, model, x: np.ndarray) -> np.ndarray:
    """(steps, batch, outputs) of a controller stepped through the sequences x."""
    out = np.empty((N_STEPS, BATCH, len(model.outputs)))
    for k in range(N_STEPS):
        y = controller.step({s.name: x[k, :, i] for i, s in enumerate(model.signals)})
        out[k] = np.stack([y[o.name] for o in model.outputs], axis=1)
    return out


@pytest.mark.parametrize("name", SHIPPED)
def test_chain_agrees_step_by_step(name):
    model = shipped(name)
    x = random_sequences(model, seed=len(name))
    expected = run_chain(Controller(model, BATCH), model, x)
    span = np.array([o.hi - o.lo for o in model.outputs])
    # The outputs really move (not a saturated constant compared with itself).
    assert np.all(expected.max(axis=(0, 1)) - expected.min(axis=(0, 1)) > 1e-3 * span)
    for numeric, tolerance in CHAIN_TOLERANCE.items():
        compiled = CController(model, BATCH, numeric)
        assert compiled.input_names == [s.name for s in model.signals]
        assert compiled.output_names == [o.name for o in model.outputs]
        got = run_chain(compiled, model, x)
        assert np.all(np.isfinite(got))
        error = np.abs(got - expected) / span
        assert error.max() <= tolerance, (numeric, np.unravel_index(error.argmax(), error.shape))


def test_reset_restarts_the_chain():
    model = shipped("wedm_three_region")
    c = CController(model, batch=2)
    sample = {"spark_freq": np.array([10.0, 50.0]), "abnormal_ratio": np.array([0.6, 0.1])}
    first = c.step(sample)
    c.step(sample)
    c.reset()
    again = c.step(sample)
    for name in c.output_names:
        np.testing.assert_array_equal(first[name], again[name])


def build_example(header_dir: pathlib.Path, model_name: str, out: pathlib.Path,
                  extra: tuple[str, ...] = ()) -> pathlib.Path:
    cmd = ["gcc", *STRICT_FLAGS, *extra, "-I", str(header_dir), f"-DFZ_MODEL={model_name}",
           f"-DFZ_UPPER={model_name.upper()}", str(MAIN_C), "-lm", "-o", str(out)]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    return out


def run_csv(program: pathlib.Path, rows: np.ndarray, *args: str) -> np.ndarray:
    text = "\n".join(",".join(repr(float(v)) for v in row) for row in rows) + "\n"
    result = subprocess.run([str(program), *args], input="a,header,line\n" + text,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and result.stderr == "", result.stderr[:2000]
    lines = [line for line in result.stdout.splitlines() if not line.startswith("#")]
    return np.array([[float(v) for v in line.split(",")] for line in lines])


@pytest.fixture(scope="module")
def compiled_headers(tmp_path_factory):
    """`fuzzyc compile` of every shipped rule base into one folder."""
    folder = tmp_path_factory.mktemp("headers")
    for name in SHIPPED:
        assert cli_main(["compile", str(ROOT / "rulebases" / f"{name}.fz"),
                         "-o", str(folder)]) == 0
    return folder


SANITIZE = ("-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-g")


@pytest.mark.parametrize("sanitize", [False, True], ids=["plain", "asan-ubsan"])
@pytest.mark.parametrize("name", SHIPPED)
def test_example_program(compiled_headers, tmp_path, name, sanitize):
    model = load(ROOT / "rulebases" / f"{name}.fz")    # exactly what was compiled
    program = build_example(compiled_headers, name, tmp_path / "controller",
                            SANITIZE if sanitize else ())
    rb = model.rulebase
    # Bare rule base (-r): random points and every edge combination.
    x = inputs_for(rb, seed=3, n_random=3000)
    span = np.array([v.hi - v.lo for v in rb.outputs])
    got = run_csv(program, x, "-r")
    assert got.shape == (len(x), len(span))
    assert np.all(np.abs(got - evaluate(rb, x)) <= 1e-5 * span)
    # The chain: one loop, 2000 steps of a random sequence.
    seq = np.random.default_rng(4).uniform(
        [s.lo for s in model.signals], [s.hi for s in model.signals], (2000, len(model.signals)))
    seq[::97, 0] = np.nan
    reference = Controller(model, 1)
    steps = [reference.step({s.name: row[i:i + 1] for i, s in enumerate(model.signals)})
             for row in seq]
    expected = np.array([[step[o][0] for o in reference.output_names] for step in steps])
    got = run_csv(program, seq)
    out_span = np.array([o.hi - o.lo for o in model.outputs])
    assert np.all(np.abs(got - expected) <= 5e-5 * out_span)


@pytest.mark.parametrize("case", sorted(set(CASES) - set(SHIPPED)))
def test_other_code_paths_under_sanitizers(tmp_path, case):
    """Dense rules, hedges, NOT, OR, centroids and libm shapes under ASan + UBSan too."""
    assert np.all(sanitized_error(tmp_path, CASES[case](), n_random=2000) <= 1e-5)


def sanitized_error(tmp_path, model, n_random: int) -> np.ndarray:
    """|C - engine| / output range (N, O) of the model's float header built under ASan +
    UBSan, on its edges and n_random random inputs."""
    model.name = "variant"
    (tmp_path / "variant.h").write_text(generate_header(model))
    program = build_example(tmp_path, "variant", tmp_path / "controller", SANITIZE)
    rb = model.rulebase
    x = inputs_for(rb, seed=5, n_random=n_random)
    span = np.array([v.hi - v.lo for v in rb.outputs])
    return np.abs(run_csv(program, x, "-r") - evaluate(rb, x)) / span
