"""The lookup-table back end: exact where the rule base is multilinear per grid cell, its C
equal to its Python, NaN/inf handling, and the measured error written into the header."""
from __future__ import annotations

import ctypes
import pathlib

import numpy as np
import pytest

from fuzzyc.backends.c.load import compile_shared
from fuzzyc.backends.lut import LookupTable, generate_lut_header
from fuzzyc.cli import main as cli_main
from fuzzyc.engine.inference import evaluate
from fuzzyc.language.parser import load

from test_c_backend import shipped

ROOT = pathlib.Path(__file__).resolve().parents[1]

SHIM = """\
#include "{name}_lut.h"
void lut_batch(int n, const double *x, double *y) {{
    int b, k;
    for (b = 0; b < n; ++b) {{
        float xf[{n_in}], yf[{n_out}];
        for (k = 0; k < {n_in}; ++k) xf[k] = (float)x[b * {n_in} + k];
        {name}_lut(xf, yf);
        for (k = 0; k < {n_out}; ++k) y[b * {n_out} + k] = (double)yf[k];
    }}
}}
"""


def c_lut(model, table, error):
    shim = SHIM.format(name=model.name, n_in=len(table.inputs), n_out=len(table.outputs))
    lib = ctypes.CDLL(str(compile_shared(
        {f"{model.name}_lut.h": generate_lut_header(model, table, error), "shim.c": shim},
        "shim.c")))
    dptr = ctypes.POINTER(ctypes.c_double)
    lib.lut_batch.argtypes = [ctypes.c_int, dptr, dptr]

    def run(x):
        x = np.ascontiguousarray(x, dtype=float)
        y = np.empty((len(x), len(table.outputs)))
        lib.lut_batch(len(x), x.ctypes.data_as(dptr), y.ctypes.data_as(dptr))
        return y
    return run


def test_exact_when_the_rule_base_is_bilinear_per_cell():
    # Milling: 7 uniform triangles per input (break points at k/3), product t-norm, weighted
    # sum of singletons: y = sum mu_e mu_cf z, bilinear between break points.  With 7 grid
    # points per input the grid is the break points, so interpolation is exact.
    rb = shipped("milling_neurofuzzy").rulebase
    table = LookupTable(rb, 7)
    x = np.random.default_rng(0).uniform(-1, 1, (20_000, 2))
    np.testing.assert_allclose(table.evaluate(x), evaluate(rb, x), atol=1e-12)
    # One grid point off the break points and it is not exact any more.
    assert np.abs(LookupTable(rb, 8).evaluate(x) - evaluate(rb, x)).max() > 1e-3


def test_grid_nodes_are_the_engine():
    rb = shipped("wedm_three_region").rulebase
    table = LookupTable(rb, 9)
    nodes = np.array([[-1.0, -0.75, 0.25], [1.0, 1.0, -1.0], [0.5, 0.0, 0.75]])
    np.testing.assert_allclose(table.evaluate(nodes), evaluate(rb, nodes), atol=1e-12)


def test_measured_error_shrinks_with_resolution():
    rb = shipped("wedm_three_region").rulebase
    coarse, fine = LookupTable(rb, 9).measure_error(), LookupTable(rb, 33).measure_error()
    assert np.all(fine < coarse) and np.all(fine > 0)


def test_c_table_equals_python_table_and_edges():
    model = shipped("wedm_three_region")
    table = LookupTable(model.rulebase, 17)
    error = table.measure_error()
    run = c_lut(model, table, error)
    rng = np.random.default_rng(1)
    x = np.concatenate([rng.uniform(-1.2, 1.2, (50_000, 3)),
                        [[np.inf, -np.inf, 0.3], [np.nan, 0.1, 0.2], [1.0, 1.0, 1.0]]])
    np.testing.assert_allclose(run(x), table.evaluate(x), atol=1e-5 * 2)
    # +-inf read the table's edge, NaN gives the declared defaults (0 for du1 and du2).
    np.testing.assert_allclose(table.evaluate(x[-3:-2]), table.evaluate([[1.0, -1.0, 0.3]]))
    np.testing.assert_array_equal(table.evaluate(x[-2:-1]), [[0.0, 0.0]])


def test_cli_writes_the_measured_error(tmp_path, capsys):
    path = ROOT / "rulebases" / "edm_sink_gap.fz"
    assert cli_main(["compile", str(path), "--target", "lut", "--resolution", "21",
                     "-o", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    text = (tmp_path / "edm_sink_gap_lut.h").read_text()
    error = LookupTable(load(path).rulebase, 21).measure_error()[0]
    assert f"dv {error:.3g}" in text and f"{error:.4g}" in printed
    assert load(path).source_hash in text


def test_bad_resolution_is_a_diagnostic():
    from fuzzyc.errors import FuzzycError
    with pytest.raises(FuzzycError, match="resolution"):
        LookupTable(shipped("edm_sink_gap").rulebase, 1)


def test_several_rule_blocks_are_one_table_by_hand():
    # tests/test_rule_blocks.py's chain: block `first` computes m from a and b, `second` reads
    # m for y and z.  The table's inputs are a and b (m is computed), its outputs m, y, z.
    # At a = .6, b = .5 (grid nodes at resolution 11) m = .559 / 1.26, y = 10 m, z = 5 m
    # (the arithmetic is there); the C header gives the same in float.
    from test_rule_blocks import M, chain
    model = chain()
    table = LookupTable(model, 11)
    assert [v.name for v in table.inputs] == ["a", "b"]
    assert [v.name for v in table.outputs] == ["m", "y", "z"]
    np.testing.assert_allclose(table.evaluate([[0.6, 0.5]]), [[M, 10 * M, 5 * M]], rtol=1e-12)
    header = generate_lut_header(model, table, table.measure_error())
    assert "block first: " in header and "block second: " in header
    run = c_lut(model, table, table.measure_error())
    x = np.random.default_rng(1).uniform(0, 1, (500, 2))
    np.testing.assert_allclose(run(x), table.evaluate(x), rtol=1e-5, atol=1e-5)
    assert run(np.array([[0.6, 0.5]]))[0] == pytest.approx([M, 10 * M, 5 * M], rel=1e-6)


def test_a_held_output_has_no_table():
    from fuzzyc.errors import FuzzycError
    rb = shipped("milling_neurofuzzy").rulebase
    rb.outputs[0].lock_previous = True
    with pytest.raises(FuzzycError, match="a lookup table holds no state: output `.*` keeps "
                                          "its last value"):
        LookupTable(rb, 5)


def test_cli_tabulates_a_file_of_several_rule_blocks(tmp_path, capsys):
    # two RuleBlocks side by side (y Mamdani, z Takagi-Sugeno): one table over a and b with
    # both outputs; at a grid node (a = b = 1 at resolution 9) the engine's numbers: the rule
    # `a is H and b is H` fires 1 alone in each block: y the centroid of hi clipped to
    # [0, 10], (0..10 rising triangle) 20/3; z the constant 10
    path = ROOT / "tests" / "format_corpus" / "blocks_mamdani_sugeno.fll"
    assert cli_main(["compile", str(path), "--target", "lut", "--resolution", "9",
                     "-o", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert "lookup table max error y: " in printed and "lookup table max error z: " in printed
    from fuzzyc.formats import load_any
    model = load_any(path)
    table = LookupTable(model, 9)
    assert table.evaluate([[1.0, 1.0]])[0] == pytest.approx([20 / 3, 10.0], abs=2e-3)
    run = c_lut(model, table, table.measure_error())
    assert run(np.array([[1.0, 1.0]]))[0] == pytest.approx([20 / 3, 10.0], abs=2e-3)
