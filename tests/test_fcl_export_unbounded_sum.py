"""A rule base aggregated by the plain sum exports to FCL as `ACCU : UnboundedSum;` (fuzzylite
6's word: its FclImporter reads no `SUM`, measured), and reads back with the same numbers;
jFuzzyLogic's `ACCU : SUM;` is still read (issue 28)."""
from __future__ import annotations

import numpy as np
import pytest

from fuzzyc.conformance import oracles
from fuzzyc.formats import load_any, save
from fuzzyc.formats.tool_semantics import Chain

FZ = """controller sumexp "ACCU export" {
  input a in [0, 1]
  terms a : lo = tri(0, 0, 1), hi = tri(0, 1, 1)
  var y in [0, 10] default 0
  terms y : small = tri(0, 2, 5), big = tri(5, 8, 10)
  inference and = min, or = max, implication = min, aggregation = sum, defuzzify = centroid
  rule if a is lo then y is small
  rule if a is hi then y is big
  rule if a is hi then y is small
  output y_out in [0, 10] = y
}
"""
# inside the range: at 0 and 1 the exported point lists have a vertical edge, read by fuzzylite
# otherwise (another cause, docs/formats.md)
X = np.array([[0.2], [0.3], [0.5], [0.7], [0.9]])


def _fcl(tmp_path):
    src = tmp_path / "sumexp.fz"
    src.write_text(FZ)
    out = tmp_path / "sumexp.fcl"
    save(load_any(src), out)
    return src, out


def test_sum_exports_as_unbounded_sum_and_reads_back(tmp_path):
    src, out = _fcl(tmp_path)
    text = out.read_text()
    assert "ACCU : UnboundedSum;" in text and "ACCU : SUM;" not in text
    mine = Chain(load_any(src)).evaluate(X, "exact")
    back = Chain(load_any(out)).evaluate(X, "exact")
    np.testing.assert_allclose(back, mine, rtol=0, atol=1e-12)
    # jFuzzyLogic's word reads as the same aggregation
    jfl = tmp_path / "jfl.fcl"
    jfl.write_text(text.replace("ACCU : UnboundedSum;", "ACCU : SUM;"))
    np.testing.assert_allclose(Chain(load_any(jfl)).evaluate(X, "exact"), mine, atol=1e-12)


def test_fuzzylite_reads_the_export(tmp_path):
    if not oracles.have_fuzzylite():
        pytest.skip("no fuzzylite CLI")
    src, out = _fcl(tmp_path)
    header, values = oracles.fuzzylite_outputs(out, X)
    ours = Chain(load_any(out)).evaluate(X, "fuzzylite")
    np.testing.assert_allclose(values[:, [header.index("y")]], ours[:, :1], atol=1e-3 * 10)
