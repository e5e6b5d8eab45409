"""fuzzylite's `hybrid` FIS (issue 28): a defuzzifier per output, which FIS cannot say.

fuzzyc reads DefuzzMethod for the outputs of area terms and the weighted average for the
outputs whose terms are all constants (what the engine's .fll and .fcl say); fuzzylite 6 reads
the file back with DefuzzMethod for every output, each Constant term a membership flat over the
range, which `--semantics fuzzylite` reproduces (`fuzzylite flat` in .fz).  Known answers by
hand, then the fuzzylite CLI run live on the same file (skipped with the reason when missing).
"""
import numpy as np
import pytest

from fuzzyc.backends.c.load import CController
from fuzzyc.conformance import oracles
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fis, write_fz
from fuzzyc.formats.tool_semantics import Chain
from fuzzyc.language.parser import parse

# x in [0, 10]: lo = 1 - x/10, hi = x/10.  m: a = tri(0, 2, 4), b = tri(6, 8, 10) (apart);
# s: constants c = 4, d = 16 on [0, 20].  Row 2 weighs 0.5.
HYBRID = """[System]
Name='hyb'
Type='hybrid'
NumInputs=1
NumOutputs=2
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='max'
DefuzzMethod='centroid'

[Input1]
Name='x'
Range=[0 10]
NumMFs=2
MF1='lo':'trimf',[-10 0 10]
MF2='hi':'trimf',[0 10 20]

[Output1]
Name='m'
Range=[0 10]
NumMFs=2
MF1='a':'trimf',[0 2 4]
MF2='b':'trimf',[6 8 10]

[Output2]
Name='s'
Range=[0 20]
NumMFs=2
MF1='c':'constant',[4]
MF2='d':'constant',[16]

[Rules]
1, 1 1 (1) : 1
2, 2 2 (0.5) : 1
"""
X = np.array([[2.0], [5.0], [30.0]])


def _chain(text=HYBRID, name="hyb.fis"):
    return Chain(read_fis(text, name))


def test_constant_outputs_take_the_weighted_average_by_hand():
    y = _chain().evaluate(X, "exact")
    # x = 2: lo 0.8, hi 0.2 weighed 0.5 -> 0.1: s = (0.8*4 + 0.1*16) / 0.9 = 4.8/0.9
    assert y[0, 1] == pytest.approx(4.8 / 0.9, abs=1e-12)
    # x = 5: 0.5 and 0.25: s = (0.5*4 + 0.25*16) / 0.75 = 8
    assert y[1, 1] == pytest.approx(8.0, abs=1e-12)
    # m at x = 5: a clipped at 0.5 is the trapezoid 0, 1, 3, 4 (area (4+2)/2*0.5 = 1.5, centre
    # 2), b at 0.25 the trapezoid 6, 6.5, 9.5, 10 (area (4+3)/2*0.25 = 0.875, centre 8):
    # (1.5*2 + 0.875*8) / 2.375 = 10/2.375
    assert y[1, 0] == pytest.approx(10 / 2.375, abs=1e-12)
    # x = 30: nothing fires, MATLAB's default the middle of each range
    assert y[2].tolist() == [5.0, 10.0]


def test_fuzzylite_reads_the_constants_flat_by_hand():
    y = _chain().evaluate(X, "fuzzylite")
    # a flat membership over [0, 20] wherever a rule fires: its centroid is the middle, 10
    assert y[:2, 1] == pytest.approx([10.0, 10.0], abs=1e-9)
    # the Mamdani output is sampled (100 midpoints) and unchanged by the reading
    assert y[1, 0] == pytest.approx(10 / 2.375, abs=1e-3)
    # nothing fired: fuzzylite's FIS reading has default nan
    assert np.isnan(y[2]).all()


def test_the_reading_round_trips_through_fz():
    model = read_fis(HYBRID, "hyb.fis")
    text = write_fz(model)
    assert "  fuzzylite flat s\n" in text
    assert "  inference s: aggregation = max, defuzzify = weighted_average\n" in text
    again = Chain(parse(text, "hyb.fz"))
    for semantics in ("exact", "fuzzylite", "pyfuzzylite", "octave"):
        np.testing.assert_allclose(again.evaluate(X, semantics),
                                   _chain().evaluate(X, semantics), atol=1e-12, rtol=0)


def test_the_exact_reading_compiles_to_c():
    # one header: the rule block split per defuzzifier (backends.rule_blocks), in double C
    model = read_fis(HYBRID, "hyb.fis")
    got = CController(model, 3, "double").step({"x": X[:, 0]})
    assert [o.name for o in model.outputs] == list(got)
    np.testing.assert_allclose(np.column_stack(list(got.values())), _chain().evaluate(X, "exact"),
                               atol=1e-12, rtol=0)


@pytest.mark.parametrize("written, instead, where, what", [
    ("MF2='d':'constant',[16]", "MF2='d':'linear',[1 2]", "hyb.fis:32:5:",
     "`d`: a linear term in a hybrid FIS is a membership of the inputs"),
    ("MF2='b':'trimf',[6 8 10]", "MF2='b':'constant',[8]", "hyb.fis:25:5:",
     "`b`: an output of a hybrid FIS needs constant terms only or none"),
    ("DefuzzMethod='centroid'", "DefuzzMethod='wtaver'", "hyb.fis:3:6:",
     "type `hybrid` needs the DefuzzMethod of its Mamdani outputs"),
])
def test_what_a_hybrid_fis_cannot_hold_is_refused_where_it_is(written, instead, where, what):
    with pytest.raises(FuzzycError) as caught:
        read_fis(HYBRID.replace(written, instead), "hyb.fis")
    assert where in str(caught.value) and what in str(caught.value)


def test_fuzzylite_cli_gives_the_flat_reading(tmp_path):
    if not oracles.have_fuzzylite():
        pytest.skip("fuzzylite not installed")
    path = tmp_path / "hyb.fis"
    path.write_text(HYBRID)
    names, got = oracles.fuzzylite_outputs(path, X)
    assert names == ["x", "m", "s"]
    np.testing.assert_allclose(got[:, 1:], _chain().evaluate(X, "fuzzylite"), atol=1e-3, rtol=0)


FLAT_FZ = """controller c {
  input x in [0, 1]
  terms x : lo = tri(0, 0, 1), hi = tri(0, 1, 1)
  var y in [0, 10]
  terms y : a = singleton(2), b = singleton(8)
  fuzzylite flat y
  inference defuzzify = weighted_average
  rule if x is lo then y is a
  rule if x is hi then y is b
  output u in [0, 10] = y
}
"""


def test_fuzzylite_flat_in_fz_by_hand():
    chain = Chain(parse(FLAT_FZ, "flat.fz"))
    x = np.array([[0.25]])
    # x = 0.25: lo 0.75, hi 0.25: (0.75*2 + 0.25*8) / 1 = 3.5.  Under a weighted-average
    # block the flat reading changes nothing (a constant formula's value is the constant)
    for semantics in ("exact", "fuzzylite"):
        assert chain.evaluate(x, semantics)[0, 0] == pytest.approx(3.5, abs=1e-12)
    centroid = Chain(parse(FLAT_FZ.replace("defuzzify = weighted_average",
                                           "defuzzify = centroid"), "flat.fz"))
    # under a centroid block every constant is flat over [0, 10]: the middle, 5
    assert centroid.evaluate(x, "fuzzylite")[0, 0] == pytest.approx(5.0, abs=1e-9)


def test_fuzzylite_flat_takes_concluded_variables():
    with pytest.raises(FuzzycError, match=r"flat.fz:6:18: error: `fuzzylite flat` names the "
                                          r"input `x`: it takes the variables the rules conclude"):
        parse(FLAT_FZ.replace("fuzzylite flat y", "fuzzylite flat x"), "flat.fz")
