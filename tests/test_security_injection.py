"""Issue 13, C code injection: user text reaches the generated C only as inert comment text or
as identifiers of [A-Za-z0-9_].  Every route is compiled with gcc and checked after the
preprocessor has dropped the comments: the payload `int injected_ROUTE = 5;` is not code (no
such declaration in the preprocessed text, no such symbol in the object file)."""
from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess

import pytest
from hypothesis import given, strategies as st

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c_fixed.header import generate_fixed_header
from fuzzyc.backends.lut import LookupTable, generate_lut_header
from fuzzyc.errors import FuzzycError
from fuzzyc.escape import SAFE_NAME, c_comment, c_identifier
from fuzzyc.formats import load_any
from hostile_fis import sugeno_fis

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None or shutil.which("nm") is None,
                                reason="needs gcc and nm (binutils)")

PAYLOAD = re.compile(r"int\s+injected_\w+\s*=")

FZ = """\
controller t "TITLE" {
  input x in [0, 1]
  input y in [0, 1]
  terms x, y : lo = tri(-1, 0, 1), hi = tri(0, 1, 2)
  var u in [0, 1] default 0
  terms u : singletons small = 0 big = 1
  inference and = min, implication = min, aggregation = max, defuzzify = center_of_area
  rule if x is lo and y is lo then u is small
  rule if x is hi and y is hi then u is big
  output u_out in [0, 1] = u
}
"""

FLL = """\
Engine: e
description: d */ int injected_fll = 5; /* e
InputVariable: x
  enabled: true
  range: 0 1
  term: lo Triangle -1 0 1
  term: hi Triangle 0 1 2
OutputVariable: u
  enabled: true
  range: 0 1
  aggregation: none
  defuzzifier: WeightedAverage
  default: 0
  term: small Constant 0
  term: big Constant 1
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  activation: General
  rule: if x is lo then u is small
  rule: if x is hi then u is big
"""

FIS = sugeno_fis("sys */ int injected_sys = 5; /* x",
                 [("a/../x */ int injected_in = 5; /* y", "lo */ int injected_term = 5; /* b",
                   "hi"),
                  ("b*??/", "lo", "hi")],
                 ("out */ int injected_out = 5; /* z", "small */ int injected_oterm = 5; /* ",
                  "big"))


def compiled(header: str, tmp_path) -> tuple[str, str]:
    """(the header's code after the preprocessor, the object's global symbols); the header
    must compile as C99 without a warning."""
    h = tmp_path / "generated.h"
    h.write_text(header)
    obj = tmp_path / "generated.o"
    built = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-x", "c", "-c",
                            str(h), "-o", str(obj)], capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    code = subprocess.run(["gcc", "-std=c99", "-E", "-P", "-x", "c", str(h)],
                          capture_output=True, text=True, check=True).stdout
    symbols = subprocess.run(["nm", "-g", "--defined-only", str(obj)],
                             capture_output=True, text=True, check=True).stdout
    return code, symbols


def assert_inert(header: str, tmp_path) -> None:
    code, symbols = compiled(header, tmp_path)
    assert not PAYLOAD.search(code)
    assert "injected" not in symbols


def every_header(model) -> list[str]:
    """The float and double headers, the q15 one (when the model is in its reach) and the
    lookup table."""
    headers = [generate_header(model, "float"), generate_header(model, "double"),
               generate_lut_header(model, LookupTable(model.rulebase, 5), [0.0] * 1)]
    try:
        headers.append(generate_fixed_header(model, "q15"))
    except FuzzycError:
        pass
    return headers


def test_the_oracle_sees_a_live_payload(tmp_path):
    # Without escaping, the FIS term name's `*/` closes the comment: the check must fail.
    code, symbols = compiled("/* lo */ int injected_term = 5; /* b */\n", tmp_path)
    assert PAYLOAD.search(code) and "injected_term" in symbols


def test_fz_title(tmp_path):
    path = tmp_path / "t.fz"
    path.write_text(FZ.replace("TITLE", "a */ int injected_title = 5; /* b"))
    model = load_any(path)
    assert "*/ int injected_title" in model.title     # the text arrived as written
    headers = every_header(model)
    assert len(headers) == 4
    for header in headers:
        assert_inert(header, tmp_path)
    assert "a * / int injected_title = 5; / * b" in headers[0]   # shown, split


def test_fll_description(tmp_path):
    path = tmp_path / "d.fll"
    path.write_text(FLL)
    model = load_any(path)
    assert "injected_fll" in model.title
    for header in every_header(model):
        assert_inert(header, tmp_path)


def test_fis_system_variable_and_term_names(tmp_path):
    path = tmp_path / "n.fis"
    path.write_text(FIS)
    model = load_any(path)
    assert model.rulebase.inputs[0].names[0] == "lo */ int injected_term = 5; /* b"
    headers = every_header(model)
    assert len(headers) == 4
    for header in headers:
        assert_inert(header, tmp_path)
    # the names that are identifiers are made of [A-Za-z0-9_]
    assert "#define SYS____INT_INJECTED_SYS___5_____X_IN_A____X____INT_INJECTED_IN___5_____Y 0" \
        in headers[0]


def test_source_path(tmp_path):
    folder = tmp_path / "p*" / " int injected_path = 5; " / "*q"
    folder.mkdir(parents=True)
    path = folder / "m.fz"
    path.write_text(FZ.replace("TITLE", "plain"))
    model = load_any(str(path))
    assert "p*/ int injected_path = 5; /*q" in model.source_path
    for header in every_header(model):
        assert_inert(header, tmp_path)


def test_in_memory_title_with_line_breaks_trigraphs_and_unicode(tmp_path):
    path = tmp_path / "t.fz"
    path.write_text(FZ.replace("TITLE", "plain"))
    title = "x *??/\n/ int injected_splice = 5; /* \\\n*/ int injected_bs = 5; /* µ\u2028"
    model = dataclasses.replace(load_any(path), title=title, source_path=None)
    for header in every_header(model):
        assert_inert(header, tmp_path)
    assert "<U+00B5><U+2028>" in generate_header(model)


@given(st.text())
def test_c_comment_leaves_nothing_the_preprocessor_reads(text):
    shown = c_comment(text)
    assert all(" " <= c <= "~" for c in shown)
    for token in ("*/", "/*", "??", "\\"):
        assert token not in shown


@given(st.text())
def test_c_identifier_is_an_identifier(name):
    assert SAFE_NAME.fullmatch(c_identifier(name))


def test_names_that_meet_as_c_names_are_refused(tmp_path):
    path = tmp_path / "clash.fis"
    path.write_text(sugeno_fis("m", [("a_b", "lo", "hi"), ("a-b", "lo", "hi")],
                               ("u", "small", "big")))
    model = load_any(path)
    with pytest.raises(FuzzycError, match="`a_b` and `a-b` give the same C name a_b"):
        generate_header(model)
    with pytest.raises(FuzzycError, match="`a_b` and `a-b`"):
        generate_fixed_header(model, "q15")
