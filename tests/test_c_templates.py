"""The C back ends' rule-base-independent helpers are static .c templates (c_template.py):
each compiles alone under the strict flags, and a header holds the sections it needs verbatim
under its own prefix, the real type entering as the header's typedef (the type macro)."""
from __future__ import annotations

import re
from importlib import resources

import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c.helpers import TEMPLATE
from fuzzyc.backends.c.load import compile_shared
from fuzzyc.backends.c_template import sections

from test_c_area import BIS, CEN, MIN_MAX, MOM, wedm
from test_c_backend import shipped

CASES = {   # test_c_area's WEDM variants -> the real_helpers.c sections their header holds
    "bisector": (lambda: wedm(BIS, MIN_MAX), ["common", "points", "polygon", "sums", "bisector"]),
    "mom": (lambda: wedm(MOM, MIN_MAX), ["common", "points", "polygon", "mom"]),
    "smooth_bisector": (lambda: wedm(BIS, MIN_MAX, smooth=True),
                        ["common", "points", "sums", "bisector"]),
    "smooth_centroid": (lambda: wedm(CEN, MIN_MAX, smooth=True),
                        ["common", "points", "sums", "centroid"]),
    "centroid": (lambda: wedm(CEN, MIN_MAX), ["common"]),   # straight-line exact, no walk
}
WALKS = {"points", "polygon", "sums", "centroid", "bisector", "mom"}


def _renamed(text: str, name: str) -> str:
    return re.sub(r"\b(fuzzyc_|FUZZYC_)",
                  lambda m: name + "_" if m.group(1).islower() else name.upper() + "_", text)


@pytest.mark.parametrize("real", ["float", "double"])
def test_real_template_compiles_alone(real):
    text = resources.files("fuzzyc").joinpath(TEMPLATE).read_text()
    sqrt = {"float": "sqrtf", "double": "sqrt"}[real]
    compile_shared({"helpers.c": text}, "helpers.c",
                   (f"-DFUZZYC_REAL_TYPE={real}", f"-DFUZZYC_SQRT={sqrt}"))


@pytest.mark.parametrize("real", ["float", "double"])
@pytest.mark.parametrize("case", list(CASES))
def test_header_holds_its_sections_verbatim_and_no_other(real, case):
    build, held = CASES[case]
    model = build()
    name = model.name
    header = generate_header(model, real)
    assert f"typedef {real} {name}_real;" in header
    for section in held:
        assert _renamed(sections(TEMPLATE)[section], name) in header, section
    for section in WALKS - set(held):   # a walk is pasted only where the header uses it
        lines = _renamed(sections(TEMPLATE)[section], name).split("\n")
        defined = next(line for line in lines if line.startswith(("static inline", "typedef")))
        assert defined not in header, section


def test_constants_the_sections_use_are_defined_per_real_type():
    # 1e-12 is model.ACTIVATION_FLOOR; float's flat tolerance is 4 ulps of 1 (area.py):
    # 1 - 4 * 2**-23 = 0.999999523162841796875, printed by repr as 0.9999995231628418
    mom = generate_header(wedm(MOM, MIN_MAX))
    assert "#define WEDM_THREE_REGION_ACTIVATION_FLOOR 1e-12f\n" in mom
    assert "#define WEDM_THREE_REGION_TOP_SHARE 0.9999995231628418f\n" in mom
    bis = generate_header(wedm(BIS, MIN_MAX), "double")
    assert "#define WEDM_THREE_REGION_SQRT sqrt\n" in bis
    assert "#define WEDM_THREE_REGION_ACTIVATION_FLOOR 1e-12\n" in bis


def test_float_and_double_headers_of_two_controllers_share_a_translation_unit():
    headers = {}
    for name in ("wedm_corner", "edm_sink_gap"):
        for real in ("float", "double"):
            model = shipped(name)
            model.name = f"{name}_{real}"
            headers[f"{name}_{real}.h"] = generate_header(model, real)
    unit = "".join(f'#include "{h}"\n' for h in headers)
    compile_shared({**headers, "unit.c": unit}, "unit.c")
