"""The generated C proved free of run-time errors by Frama-C's EVA (`fuzzyc.backends.c.proof`):
every shipped rule base in every kind (float, double, q15, q31, lookup table: 30 analyses of
0.3-5 s, in the ordinary suite), and, marked `proofs` (`make proofs`, a minute or two), the
C tests' corpus (the float variants of test_c_backend, the fixed-point ones of test_c_fixed)
and every header the back ends write for the import corpus tests/format_corpus; no alarm and
every assertion of the harness valid.  All skip without frama-c."""
from __future__ import annotations

import pathlib

import pytest

from fuzzyc.api import load
from fuzzyc.backends.c.proof import KINDS, frama_c, header_for, prove
from fuzzyc.cli import main as cli_main
from fuzzyc.errors import FuzzycError

import test_c_backend
import test_c_fixed

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHIPPED = sorted(p.name for p in (ROOT / "rulebases").glob("*.fz"))
needs_frama_c = pytest.mark.skipif(frama_c() is None,
                                   reason="frama-c not installed (Debian: frama-c-base)")


def assert_proved(proof):
    assert not proof.alarms, proof.summary()
    assert proof.assertions[1] > 0 and proof.assertions[0] == proof.assertions[1], \
        proof.summary()


@needs_frama_c
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_header_has_no_run_time_error(name, kind):
    assert_proved(prove(load(ROOT / "rulebases" / name), kind))


@needs_frama_c
@pytest.mark.proofs
@pytest.mark.parametrize("case", sorted(test_c_backend.CASES))
def test_float_corpus_has_no_run_time_error(case):
    assert_proved(prove(test_c_backend.CASES[case](), "float"))


@needs_frama_c
@pytest.mark.proofs
@pytest.mark.parametrize("numeric", ["q15", "q31"])
@pytest.mark.parametrize("case", sorted(test_c_fixed.CASES))
def test_fixed_point_corpus_has_no_run_time_error(case, numeric):
    assert_proved(prove(test_c_fixed.CASES[case](), numeric))


CORPUS = ROOT / "tests" / "format_corpus"
FORMAT_CORPUS = sorted([p.name for p in CORPUS.iterdir() if not p.name.startswith("bad_")
                        and p.name != "blocks_tipper_fan.fcl"]
                       + ["blocks_tipper_fan.fcl::tipper", "blocks_tipper_fan.fcl::fan"])
FIXED = ("q15", "q31")
# The headers the back ends refuse to write, with words of the diagnostic; every other file
# and kind is proved.  Fixed point takes plain AND rules over two-active-term trapezoid
# partitions with center of area or weighted sums; float C takes min/product, max/probsum
# and no z/s-shapes.
REFUSED = {
    # C and the lookup table take several blocks (fixed point not the centroid)
    "blocks_mamdani_sugeno.fll": (FIXED, "`centroid` is not supported"),
    "blocks_tipper_fan.fcl::fan": (FIXED, "`centroid` is not supported"),
    "ramp.fll": (FIXED, "`bisector` is not supported"),
    "shapes_tsk.fll": (("float", "double", *FIXED), "einstein_product"),
    "small_export.fis": (FIXED, "`centroid` is not supported"),
    "sugeno.fis": (FIXED, "plain AND rules"),
    "sugeno.fll": (FIXED, "plain AND rules"),
    "sugeno_linear.fis": (("float", "double", *FIXED), "zshape terms"),
    "tipper.fcl": (FIXED, "`centroid` is not supported"),
    "tipper.fis": (FIXED, "`centroid` is not supported"),
    "tipper.fll": (FIXED, "`centroid` is not supported"),
    "valve.fcl": (FIXED, "partition of trapezoids"),
    "wsum.fll": (FIXED, "plain AND rules"),
}


@needs_frama_c
@pytest.mark.proofs
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", FORMAT_CORPUS)
def test_format_corpus_header_has_no_run_time_error(name, kind):
    model = load(str(CORPUS / name))
    refused_kinds, words = REFUSED.get(name, ((), ""))
    if kind in refused_kinds:
        with pytest.raises(FuzzycError, match=words):
            header_for(model, kind)
    else:
        assert_proved(prove(model, kind))


@needs_frama_c
def test_planted_errors_are_found():
    # The analysis is not vacuous: one more break point read (b <= nb) is an out-of-bounds
    # read, and the integrator without its overflow-free saturating add overflows int64 once
    # the state's range is widened.
    model = load(ROOT / "rulebases" / "wedm_three_region.fz")
    name, text = header_for(model, "q15")
    out_of_bounds = text.replace("for (b = 0; b < nb; ++b)", "for (b = 0; b <= nb; ++b)")
    assert out_of_bounds != text
    proof = prove(model, "q15", (name, out_of_bounds))
    assert not proof.proved and any("out of bounds" in a for a in proof.alarms)
    plain_add = text.replace("wedm_three_region_q15_sat_add(s->out_feed, ",
                             "wedm_three_region_q15_sat(s->out_feed + ")
    assert plain_add != text
    proof = prove(model, "q15", (name, plain_add))
    assert any("signed overflow" in a for a in proof.alarms)


@needs_frama_c
def test_compile_prove_says_what_it_proved(tmp_path, capsys):
    fz = ROOT / "rulebases" / "edm_sink_gap.fz"
    assert cli_main(["compile", str(fz), "--numeric", "q15", "--prove", "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "edm_sink_gap_q15.h: PROVED by Frama-C EVA" in out
    assert "every chain output is within its declared range" in out
    assert "Assuming `>>` of a negative integer arithmetic" in out
    assert "the state initialised by edm_sink_gap_q15_init" in out


def test_compile_prove_without_frama_c_refuses(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))      # no frama-c there
    fz = ROOT / "rulebases" / "edm_sink_gap.fz"
    assert cli_main(["compile", str(fz), "--prove", "-o", str(tmp_path)]) == 2
    assert "--prove needs Frama-C, which is not installed" in capsys.readouterr().err
    assert not list(tmp_path.glob("*.h"))


@needs_frama_c
@pytest.mark.proofs
def test_a_header_searching_its_cell_codes_has_no_run_time_error():
    # 9 inputs of 4 terms, rules on 3 of them: 4**9 = 262,144 cells, past MAX_C_TABLE_CELLS,
    # so the header keeps the 19,683 occupied cells' codes and binary-searches them (about
    # 40 s of EVA); EVA first raised an alarm on the search's probe (`base + half`), now
    # clamped to the table
    import itertools
    from fuzzyc.backends.c.header import HeaderWriter
    from fuzzyc.backends.c.expressions import REAL_TYPES
    from fuzzyc.semantics.model import Defuzzifier, Inference, Model
    from test_engine_wide import rulebase
    rb = rulebase(9, 4, itertools.product(range(3), repeat=9),
                  Inference(defuzzifier=Defuzzifier.CENTER_OF_AREA))
    model = Model.of_rulebase(rb, "wide9")
    assert HeaderWriter(model, REAL_TYPES["float"]).cells.codes is not None
    assert_proved(prove(model, "float"))


@needs_frama_c
@pytest.mark.proofs
@pytest.mark.parametrize("case", ["7 inputs with *", "9 inputs of 4 terms"])
def test_a_wide_fixed_point_header_has_no_run_time_error(case):
    # q15 past 6 inputs: the cell table indexed by the code (7 inputs, `*` on the last: 3**6 *
    # 4 = 2,916 codes, 5 s of EVA) and searched among the occupied cells' 32-bit codes (9
    # inputs of 4 terms: 4**9 codes, 19,683 occupied; 25 s)
    from test_c_fixed_wide import CASES
    assert_proved(prove(CASES[case].build(), "q15"))
