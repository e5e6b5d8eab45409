from fuzzyc.language.parser import parse
from fuzzyc.verifier import verify_model, Options
TEXT = """controller t {
  input a in [0, 1]  input b in [0, 1]
  let x in [0, 1] = a  let y in [0, 1] = b
  terms x, y : uniform L M H
  var z in [0, 1]
  terms z : singletons L=0 M=0.5 H=1
  inference and = AND_NORM, defuzzify = center_of_area
  table z (rows x: L M H; cols y: L M H) {
    L L M
    L M H
    M H H
  }
  verify {
    covers x, y at least 0.5
    bounded z in [0, 1]
    monotone z increasing in x
  }
}"""
def test_a_norm_outside_the_proofs_is_searched_not_proved():
    # drastic product fires 0 wherever both inputs are strictly between terms: coverage fails
    results = verify_model(parse(TEXT.replace("AND_NORM", "drastic_product"), "t.fz"), Options(max_examples=20))
    covers = results[0]
    assert covers.evidence[0].status.value == "undecided" and "drastic_product" in covers.evidence[0].detail
    assert covers.status.value == "violated"
    # with min the same table is proved covered
    assert verify_model(parse(TEXT.replace("AND_NORM", "min"), "t.fz"), Options(max_examples=20))[0].status.value == "proved"


def test_fixed_point_refuses_what_the_c_back_end_cannot_emit():
    # a linear (first-order Takagi-Sugeno) consequent: the q15 writer must give a diagnostic,
    # not a traceback from the term's NaN peak
    import pytest
    from fuzzyc.backends.c_fixed.header import generate_fixed_header
    from fuzzyc.errors import FuzzycError
    text = TEXT.replace("AND_NORM", "min").replace("center_of_area", "weighted_average") \
        .replace("terms z : singletons L=0 M=0.5 H=1",
                 "terms z : L = linear(0, 0.2, 0.2), M = linear(0.5, 0, 0), H = linear(1, 0, 0)")
    text = text[:text.index("  verify {")] + "}"
    with pytest.raises(FuzzycError) as info:
        generate_fixed_header(parse(text, "t.fz"), "q15")
    assert "linear" in info.value.diagnostics[0].message
