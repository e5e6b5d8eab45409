"""The `tune { ... }` section: what it frees, with which bounds, its located errors, and the
.fz writer's round trip of it."""
from __future__ import annotations

import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.formats.fz import write_fz
from fuzzyc.language.parser import parse

BASE = """controller demo {
  input e in [-2, 2]
  param GE = 1.5
  terms e : NB = tri(-3, -1, 0), Z = tri(-1, 0, 1), PB = tri(0, 1, 3)   # a partition
  var y in [-10, 10] default 0
  terms y : singletons lo=-5 mid=0 hi=5
  rule r1: if e is NB then y is lo
  rule r2: if e is Z then y is mid with 0.8
  rule if e is PB then y is hi
  output u in [-10, 10] = y
"""


def tuned(body: str):
    return parse(BASE + "  tune {\n    " + body + "\n  }\n}\n", "t.fz")


def error_of(body: str) -> str:
    with pytest.raises(FuzzycError) as info:
        tuned(body)
    return str(info.value).splitlines()[0]


def test_targets_and_bounds():
    model = tuned("e.NB.center in [-1.2, -0.8]\n e.PB in \u00b1 0.2\n y.* in +/- 1\n"
                  "r1.weight, r2.weight in [0.5, 1]\n GE in [1, 2]")
    got = {n.target: (n.kind, n.value, n.lo, n.hi) for n in model.tunables}
    assert got == {
        "e.NB.b": ("term", -1.0, -1.2, -0.8),          # `center` is the tri's b
        "e.PB.a": ("term", 0.0, -0.2, 0.2), "e.PB.b": ("term", 1.0, 0.8, 1.2),
        "e.PB.c": ("term", 3.0, 2.8, 3.2),
        "y.lo.value": ("term", -5.0, -6.0, -4.0), "y.mid.value": ("term", 0.0, -1.0, 1.0),
        "y.hi.value": ("term", 5.0, 4.0, 6.0),
        "r1.weight": ("weight", 1.0, 0.5, 1.0), "r2.weight": ("weight", 0.8, 0.5, 1.0),
        "GE": ("param", 1.5, 1.0, 2.0)}
    by = {n.target: n for n in model.tunables}
    # a tri's b is the model's b and c (a tri is the trapezoid (a, b, b, c))
    assert by["e.NB.b"].slots == (1, 2) and by["e.PB.c"].slots == (3,)
    # where each number is written (line:col of its token), and where r1's weight goes
    assert (by["e.NB.b"].token.line, by["e.NB.b"].token.col) == (4, 26)
    assert by["r1.weight"].token is None
    assert (by["r1.weight"].insert_at.line, by["r1.weight"].insert_at.col) == (7, 35)
    assert (by["r2.weight"].token.line, by["r2.weight"].token.col) == (8, 41)
    assert (by["GE"].token.line, by["GE"].token.col) == (3, 14)


def test_no_tune_section_frees_nothing():
    assert parse(BASE + "}\n").tunables == []


@pytest.mark.parametrize("body, message", [
    ("x.A in [0, 1]", "t.fz:12:5: error: `x` is no variable, param or named rule"),
    ("e.QQ in [0, 1]", "t.fz:12:7: error: `e` has no term `QQ`: known: NB Z PB"),
    ("e.NB.width in [0, 1]", "t.fz:12:10: error: tri `NB` has no parameter `width`"),
    ("e.NB.b in [1, 0]", "t.fz:12:16: error: the bounds [1, 0] are empty"),
    ("e.NB.b in +/- 0", "t.fz:12:19: error: the spread +/- 0 is empty"),
    ("e.NB.b in [0, 1]", "t.fz:12:16: error: `e.NB.b` is -1 as written, outside its bounds"),
    # b may reach 0.5, past c = 0: the break points would leave their order
    ("e.NB.b in +/- 1.5", "t.fz:12:5: error: the bounds of `e.NB` let b (up to 0.5) pass c"),
    ("r1.weight in [0.5, 1.5]", "t.fz:12:5: error: a rule weight must lie in [0, 1]"),
    ("GE.x in [0, 1]", "t.fz:12:8: error: `GE` is a param, one number: write `GE`"),
    ("e.NB.b in [-1.1, -0.9]\n e.NB in +/- 0.1", "t.fz:13:2: error: `e.NB.b` is already tuned"),
    # lo may reach 3, past mid = 0: the singletons of y would leave their order
    ("y.lo.value in [-5, 3]", "t.fz:12:5: error: the bounds let `y.lo` peak at 3, at or past"),
    # an unnamed rule has no name to tune by
    ("e.NB in +/- 0.1\n r3.weight in [0, 1]", "t.fz:13:2: error: `r3` is no variable"),
    ("e.NB.b e.Z.b in [0, 1]", "t.fz:12:12: error: unexpected `e`"),
])
def test_located_errors(body, message):
    assert error_of(body).startswith(message)


def test_positive_widths_and_uniform_partitions():
    text = """controller g {
  input x in [0, 10]
  input z in [0, 1]
  terms x : A = bell(2, 1.5, 2), B = gauss(8, 1)
  terms z : uniform L H
  var y in [0, 1]
  terms y : lo = singleton(0), hi = singleton(1)
  rule if x is A then y is lo
  rule if x is B and z is H then y is hi
  output u in [0, 1] = y
  tune {
    %s
  }
}
"""
    with pytest.raises(FuzzycError, match=r"t.fz:12:5: error: the bounds of `x.B` let its sigma "
                                          r"reach 0; it must stay above 0"):
        parse(text % "x.B.sigma in [0, 2]", "t.fz")
    with pytest.raises(FuzzycError, match="t.fz:12:5: error: term `L` of `z` has no numbers of "
                                          "its own to tune: it belongs to a `uniform`"):
        parse(text % "z.L in +/- 0.1", "t.fz")
    model = parse(text % "x.*.center in +/- 1\n x.A.slope in [1, 3]", "t.fz")
    assert [(n.target, n.lo, n.hi) for n in model.tunables] == [
        ("x.A.center", 1.0, 3.0), ("x.B.mean", 7.0, 9.0), ("x.A.slope", 1.0, 3.0)]


def test_shared_terms_statement_is_refused():
    text = BASE.replace("terms e : NB", "input f in [-2, 2]\n  terms e, f : NB")
    with pytest.raises(FuzzycError, match="written together with those of `f`"):
        parse(text + "  tune {\n    e.NB in +/- 0.1\n  }\n}\n", "t.fz")


def test_writer_round_trip_keeps_the_section():
    model = tuned("e.NB.center in [-1.2, -0.8]\n e.PB in +/- 0.2\n y.* in +/- 1\n"
                  "r1.weight, r2.weight in [0.5, 1]\n GE in [1, 2]")
    warnings: list[str] = []
    text = write_fz(model, warnings)
    assert "  rule r1: if e is NB then y is lo\n" in text     # named: its weight is tuned
    assert "    e.NB.b in [-1.2, -0.8]\n" in text
    again = parse(text)

    def key(m):
        return sorted((n.kind, n.var, n.term, n.index, n.rule, n.lo, n.hi)
                      for n in m.tunables if n.kind != "param")
    assert key(again) == key(model) and len(key(model)) == 9
    assert any("`GE` is a param" in w for w in warnings)    # the writer has no params
    assert write_fz(again) == text
