"""fuzzyc.ModelBuilder (issue 30): a model declared in Python is the model of the same .fz text
(it is rendered as .fz and parsed: one front end checks both), every kind of declaration
arrives in the model, a hostile name is data or refused, and a mistake is reported at the
Python line that made it."""
import inspect
import sys

import numpy as np
import pytest

import fuzzyc
from fuzzyc.language.model_builder import CallSite

HERE = __file__

# the model below, written by hand as .fz text
TIPPER_FZ = '''
controller tipper "tips, built in code" {
  note "hand-written twin"
  input food in [0, 10]
  input service : stars in [0, 5]
  var tip : % in [0, 30] default 15
  terms food : bad = lshoulder(1, 4), ok = tri(2, 5, 8), good = rshoulder(6, 9)
  terms service : uniform poor fair great
  terms tip : low = tri(0, 5, 10), mid = trap(8, 12, 18, 22), high = tri(20, 25, 30)
  inference and = product, or = probsum, defuzzify = centroid
  rule if food is bad or service is poor then tip is low
  rule named: if food is good and service is not very poor then tip is high with 0.8
  table tip (rows service: poor fair great; cols food: bad good) {
    low -
    mid high
    - high
  }
  verify {
    covers food at least 0.2
    complete
  }
}
'''


def tipper() -> fuzzyc.ModelBuilder:
    b = fuzzyc.ModelBuilder("tipper", "tips, built in code")
    b.note("hand-written twin")
    food = b.input("food", 0, 10)
    food.terms(bad=("lshoulder", 1, 4), ok=("tri", 2, 5, 8), good=("rshoulder", 6, 9))
    b.input("service", 0, 5, unit="stars").uniform("poor", "fair", "great")
    tip = b.output("tip", 0, 30, unit="%", default=15)
    tip.terms(low=("tri", 0, 5, 10), mid=("trap", 8, 12, 18, 22), high=("tri", 20, 25, 30))
    b.inference(and_="product", or_="probsum", defuzzify="centroid")
    b.rule("if food is bad or service is poor then tip is low")
    b.rule(when={"food": "good", "service": "not very poor"}, then={"tip": "high"},
           weight=0.8, name="named")
    b.table("tip", rows=("service", ["poor", "fair", "great"]), cols=("food", ["bad", "good"]),
            cells=[["low", None], ["mid", "high"], [None, "high"]])
    b.verify("covers food at least 0.2", "complete")
    return b


def test_the_built_model_evaluates_as_the_same_model_parsed_from_text():
    built = tipper().build()
    parsed = fuzzyc.parse(TIPPER_FZ, name="tipper.fz")
    food, service = np.meshgrid(np.linspace(-1, 11, 49), np.linspace(-0.5, 5.5, 25))
    grid = {"food": food, "service": service}
    assert np.array_equal(fuzzyc.evaluate(built, grid)["tip"],
                          fuzzyc.evaluate(parsed, grid)["tip"])
    assert built.rulebase.n_rules == parsed.rulebase.n_rules == 6   # 2 rules + 4 cells
    for array in ("antecedents", "consequents", "negated", "hedges", "connective", "weights"):
        assert np.array_equal(getattr(built.rulebase, array), getattr(parsed.rulebase, array))


def test_a_known_answer():
    # food 9, service 5: good = 1 (rshoulder(6, 9)), bad = ok = 0; service is great (1), so
    # poor = 0: rule 1 fires at 0 or 0 = 0; `named` at good * (1 - 0^2) = 1, weighted 0.8;
    # the table's (great, good) cell at 1 * 1. Only `high` = tri(20, 25, 30) is concluded: a
    # shape symmetric about 25, so the centroid is 25.
    out = fuzzyc.evaluate(tipper().build(), {"food": 9.0, "service": 5.0})
    assert out["tip"].tolist() == pytest.approx(25.0, abs=1e-12)
    # food 5: bad = good = 0 (ok = 1, which no rule reads); service 5: poor = 0: no rule
    # fires, and tip is its default 15
    assert fuzzyc.evaluate(tipper().build(), {"food": 5.0, "service": 5.0})["tip"] == 15.0


def test_every_kind_of_declaration_arrives_in_the_model():
    b = tipper()
    b.output("z", -1, 1).singletons(neg=-1, pos=1).inference(aggregation="sum",
                                                              defuzzify="weighted_average")
    b.rule("if food is good then z is pos")
    b.rule(when={"food": "somewhat bad"}, then={"z": -0.5})     # a number: a singleton
    b.input("mood", 0, 1).terms(calm=("lshoulder", 0.2, 0.8), cross=("rshoulder", 0.2, 0.8))
    b.table("z", rows=("food", ["bad", "good"]), cols=("service", ["poor", "great"]),
            cells=[[0.0, 0.25], [0.5, 1.0]], when={"mood": "calm"}, learnable=True)
    model = b.build()
    rb = model.rulebase
    assert model.name == "tipper" and model.title == "tips, built in code"
    assert model.notes == ["hand-written twin"]
    assert [(v.name, v.lo, v.hi, v.unit) for v in rb.inputs] == [
        ("food", 0, 10, None), ("service", 0, 5, "stars"), ("mood", 0, 1, None)]
    tip, z = rb.outputs
    assert (tip.unit, tip.default, z.default) == ("%", 15, 0)
    assert rb.inputs[0].names == ["bad", "ok", "good"]
    assert rb.inputs[1].names == ["poor", "fair", "great"]
    assert list(rb.inputs[1].term_numbers(1)) == [0, 2.5, 2.5, 5]  # uniform: fair peaks mid-range
    assert tip.params[1].tolist() == [8, 12, 18, 22]
    assert z.names[:2] == ["neg", "pos"] and len(z.names) == 3 + 4   # + -0.5, + 4 table cells
    assert [p.text for p in model.properties] == ["covers food at least 0.2", "complete"]
    inf = rb.inference
    assert (inf.and_.name, inf.or_.name, inf.defuzzifier.name) == (
        "PRODUCT", "PROBSUM", "CENTROID")
    own = rb.inference_of(1)
    assert (own.aggregation.name, own.defuzzifier.name) == ("SUM", "WEIGHTED_AVERAGE")
    assert rb.n_rules == 6 + 2 + 4
    # the rendered text is the model's source, and reads back to the same rule base
    assert model.source_text == b.text()
    again = fuzzyc.parse(b.text())
    assert np.array_equal(again.rulebase.antecedents, rb.antecedents)


def test_numbers_round_trip_exactly():
    b = fuzzyc.ModelBuilder("exact")
    b.input("x", -0.1, 1 / 3).terms(a=("tri", -0.1, 0.1, 1 / 3), b=("gauss", 0.2, 1e-7))
    b.output("y", 0, 1).singletons(lo=np.float64(0.1), hi=0.7)
    b.rule("if x is a then y is lo")
    b.rule("if x is b then y is hi")
    x = b.build().rulebase.inputs[0]
    assert (x.lo, x.hi) == (-0.1, 1 / 3)
    assert list(x.term_numbers(0)) == [-0.1, 0.1, 0.1, 1 / 3]   # a triangle: trap(a, b, b, c)
    assert list(x.term_numbers(1))[:2] == [0.2, 1e-7]


def test_a_name_spelled_like_a_keyword_round_trips_as_data():
    b = fuzzyc.ModelBuilder("rule", "a */ title: not code")
    b.input("if", 0, 1, unit="in").terms({"tri": ("tri", 0, 0, 1), "in": ("tri", 0, 1, 1)})
    b.output("then", 0, 1).singletons({"is": 0, "rule": 1})
    b.rule(when={"if": "not very tri"}, then={"then": "is"})
    b.rule("if `if` is `in` then `then` is `rule`")
    b.table("then", rows=("if", ["tri", "in"]), cols=("if", ["in", "tri"]),
            cells=[[None, "is"], ["rule", None]])
    model = b.build()
    assert (model.name, model.title) == ("rule", "a */ title: not code")
    rb = model.rulebase
    assert [v.name for v in rb.inputs + rb.outputs] == ["if", "then"]
    assert rb.inputs[0].names == ["tri", "in"] and rb.inputs[0].unit == "in"
    assert rb.outputs[0].names == ["is", "rule"]
    # `if` 1: tri = 0 (not very: 1), in = 1: both rules fire fully, is = 0 and rule = 1
    assert fuzzyc.evaluate(model, {"if": 1.0})["then"] == pytest.approx(0.5)


@pytest.mark.parametrize("name", ['a"b', "a\nb", "a*/b", "a b", "1a", "", "x;", "`x`", "é"])
def test_a_name_that_is_no_identifier_is_refused_at_the_call(name):
    b = fuzzyc.ModelBuilder("m")
    with pytest.raises(ValueError, match="is not a .fz name: use letters, digits and _"):
        b.input(name, 0, 1)
    x = b.input("x", 0, 1)
    with pytest.raises(ValueError, match="is not a .fz name"):
        x.terms({name: ("tri", 0, 0, 1)})
    with pytest.raises(ValueError, match="is not a .fz name"):
        b.rule(when={"x": "lo"}, then={name: "hi"})
    with pytest.raises(ValueError, match="is not a .fz name"):
        fuzzyc.ModelBuilder(name)
    assert b.text().count("\n") == 3      # the header, `input x` and the `}`: nothing else


@pytest.mark.parametrize("text", ['say "hi"', "two\nlines", "back\\slash", "nul\x00"])
def test_a_title_or_note_that_would_not_read_back_is_refused(text):
    with pytest.raises(ValueError, match="cannot be written as .fz text"):
        fuzzyc.ModelBuilder("m", text)
    with pytest.raises(ValueError, match="cannot be written as .fz text"):
        fuzzyc.ModelBuilder("m").note(text)


def test_text_that_would_be_more_than_its_own_declaration_is_refused():
    b = fuzzyc.ModelBuilder("m")
    x = b.input("x", 0, 1)
    with pytest.raises(ValueError, match="unit of `y` must be named atoms"):
        b.output("y", 0, 1, unit="% in [0, 1] default 1")
    with pytest.raises(ValueError, match="starts a comment"):
        b.rule("if x is lo then y is lo # the rest")
    with pytest.raises(ValueError, match=r"\[not\] \[hedge\] term"):
        b.rule(when={"x": "lo then y is hi"}, then={"y": "lo"})
    with pytest.raises(ValueError, match="not a word"):
        x.terms(lo=("tri(0, 0, 1), hi = tri", 0, 1, 1))
    with pytest.raises(ValueError, match="finite number"):
        x.terms(lo=("tri", 0, float("nan"), 1))
    with pytest.raises(TypeError, match="must be a number, not bool"):
        b.input("w", False, 1)
    with pytest.raises(TypeError, match=r"\(shape, number, ...\)"):
        x.terms(lo="tri(0, 0, 1)")
    with pytest.raises(ValueError, match="unknown inference setting `andd`"):
        b.inference(andd="min")
    with pytest.raises(TypeError, match=r"`over` of `x` is \(low, high\)"):
        x.uniform("a", "b", over=(0, 1, 2))
    with pytest.raises(ValueError, match="not both"):
        b.rule("if x is lo then y is lo", when={"x": "lo"}, then={"y": "lo"})


def line_of_next_call() -> int:
    """The line after the caller's: where its next statement (the call under test) is."""
    return sys._getframe(1).f_lineno + 1


def small() -> fuzzyc.ModelBuilder:
    b = fuzzyc.ModelBuilder("small")
    b.input("x", 0, 1).terms(lo=("tri", 0, 0, 1), hi=("tri", 0, 1, 1))
    b.output("y", 0, 1).singletons(lo=0, hi=1)
    return b


def test_an_unknown_term_is_reported_at_the_python_line_of_its_rule():
    b = small()
    b.rule("if x is lo then y is lo")
    line = line_of_next_call()
    b.rule("if x is high then y is hi")
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    (d,) = caught.value.diagnostics
    assert isinstance(d.loc, CallSite) and (d.loc.file, d.loc.line) == (HERE, line)
    assert str(caught.value) == (
        f"{HERE}:{line}: error: rule 2: unknown term `high` of `x`: did you mean `hi`? "
        "(known terms are lo hi)\n"
        "    rule if x is high then y is hi\n"
        "                 ^")


def test_every_mistake_is_reported_each_at_its_own_line():
    b = small()
    first = line_of_next_call()
    b.input("x", 0, 2)
    shape = line_of_next_call()
    b.output("z", 0, 1).terms(a=("triangle", 0, 0, 1))
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    # the syntax error stops the parse: the shape first; fixed, the duplicate
    (d,) = caught.value.diagnostics
    assert d.loc.line == shape and "terms of `z`: unknown term shape `triangle`: did you " \
                                   "mean `tri`?" in d.message
    b = small()
    again = line_of_next_call()
    b.input("x", 0, 2)
    reserved = line_of_next_call()
    b.output("__z", 0, 1).singletons(a=0)
    b.rule("if x is lo then y is lo")
    empty = line_of_next_call()
    b.output("w", 1, 0).singletons(a=1)
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    found = {d.loc.line: d.message for d in caught.value.diagnostics}
    assert sorted(found) == sorted([again, reserved, empty])
    declared = inspect.getsourcelines(small)[1] + 2       # small()'s `b.input("x", ...)`
    assert found[again] == (f"input `x`: `x` is already declared at {HERE}:{declared}; give "
                            "this input another name")
    assert found[reserved].startswith("output `__z`: `__z`: names starting with `__` are "
                                      "reserved")
    assert found[empty].startswith("output `w`: the range of `w` is empty: [1, 0]")


def test_a_syntax_error_in_a_rule_text_is_at_its_line_with_the_grammar_s_words():
    b = small()
    line = line_of_next_call()
    b.rule("if x is then y is lo")
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    (d,) = caught.value.diagnostics
    assert (d.loc.file, d.loc.line) == (HERE, line)
    assert d.message.startswith("rule 1: ")
    assert d.source_line == "rule if x is then y is lo"


def test_a_rule_text_holding_two_rules_or_closing_the_model_is_refused_at_its_line():
    b = small()
    line = line_of_next_call()
    b.rule("if x is lo then y is lo rule if x is hi then y is hi")
    with pytest.raises(fuzzyc.FuzzycError, match=rf"{line}: error: rule 1: the text is not "
                                                 "one rule but 2; give each rule its own call"):
        b.build()
    b = small()
    line = line_of_next_call()
    b.rule("if x is lo then y is lo } controller z {")
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    assert caught.value.diagnostics[0].loc.line == line
    b = small()
    b.rule("if x is lo then y is lo")
    line = line_of_next_call()
    b.verify("complete consistent")
    with pytest.raises(fuzzyc.FuzzycError, match=rf"{line}: error: property 1: the text is "
                                                 "not one property but 2"):
        b.build()
    b = small()
    b.rule("if x is lo then y is lo")
    line = line_of_next_call()
    b.tune("y.hi in [0.6, 1] y.lo in [0, 0.4]")
    with pytest.raises(fuzzyc.FuzzycError, match=rf"{line}: error: tune line 1: the text is "
                                                 "not one tune line but 2"):
        b.build()


def test_a_bad_inference_word_is_reported_at_its_call():
    b = small()
    b.rule("if x is lo then y is lo")
    line = line_of_next_call()
    b.inference(defuzzify="centroidd")
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    (d,) = caught.value.diagnostics
    assert d.loc.line == line and d.message.startswith("inference: ")
    assert "centroid" in d.message


def test_a_refused_call_takes_no_number():
    b = small()
    with pytest.raises(ValueError):
        b.rule("if x is lo # then y is lo")
    b.rule("if x is lo then y is lo")
    with pytest.raises(ValueError):
        b.verify("complete", "covers x at least 0.5 # more")
    b.verify("covers x at least 2 and 3")
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    assert [d.message.split(":")[0] for d in caught.value.diagnostics] == ["property 1"]
    assert repr(b) == "<ModelBuilder small: 2 variables, 1 rule, 0 tables>"


def test_a_built_model_verifies_compiles_and_saves_like_a_parsed_one(tmp_path):
    b = small()
    b.rule("if x is lo then y is lo")
    b.rule("if x is hi then y is hi")
    b.verify("complete")
    model = b.build()
    report = fuzzyc.verify(model)
    assert [(r.name, r.status.value) for r in report.results] == [
        ("small.fz::complete", "proved")]
    assert fuzzyc.compile_c(model).filename == "small.h"
    fuzzyc.save(model, tmp_path / "small.fz")
    again = fuzzyc.load(tmp_path / "small.fz")
    x = np.linspace(0, 1, 11)
    # lo = tri(0, 0, 1), hi = tri(0, 1, 1) sum to 1: y = hi's share = x
    assert fuzzyc.evaluate(again, {"x": x})["y"].tolist() == pytest.approx(x.tolist())
    assert np.array_equal(fuzzyc.evaluate(again, {"x": x})["y"],
                          fuzzyc.evaluate(model, {"x": x})["y"])


CHAIN_FZ = '''
controller chain {
  input a in [0, 1]
  input b in [0, 1]
  var m in [0, 1]
  terms a, b, m : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var y in [0, 10]
  terms y : singletons lo=0 hi=10
  block first {
    inference and = product, defuzzify = centroid
    rule if a is H and b is H then m is H
    rule if a is L or b is L then m is L
  }
  block second {
    inference defuzzify = weighted_average
    rule if m is H then y is hi
    rule if m is L then y is lo
  }
}
'''


def test_rule_blocks_chain_as_the_same_blocks_written_in_text():
    b = fuzzyc.ModelBuilder("chain")
    for name in ("a", "b"):
        b.input(name, 0, 1).terms(L=("tri", -1, 0, 1), H=("tri", 0, 1, 2))
    b.output("m", 0, 1).terms(L=("tri", -1, 0, 1), H=("tri", 0, 1, 2))
    b.output("y", 0, 10).singletons(lo=0, hi=10)
    first = b.block("first")
    second = b.block("second")
    second.rule("if m is H then y is hi")        # blocks take their declarations any time
    first.inference(and_="product", defuzzify="centroid")
    first.rule("if a is H and b is H then m is H")
    first.rule(when={"a": "L"}, then={"m": "L"})
    second.rule("if m is L then y is lo")
    second.inference(defuzzify="weighted_average")
    text = b.text()
    assert "block first {\n    inference and = product" in text
    assert text.index("block first") < text.index("block second")
    built = b.build()
    parsed = fuzzyc.parse(CHAIN_FZ.replace("a is L or b is L", "a is L"))
    assert [rb.name for rb in built.blocks] == ["first", "second"]
    a, bb = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 11))
    runs = []
    for model in (built, parsed):
        controller = fuzzyc.Controller(model, batch=a.size)
        controller.step({"a": a.ravel(), "b": bb.ravel()})
        runs.append(controller.signals["y"])
    assert np.array_equal(*runs)
    # a = b = 1: m's H fires at 1 * 1 and L at 0, so m is the centroid of H = tri(0, 1, 2)
    # on m's range [0, 1], the rising ramp: 2/3; then H(2/3) = 2/3, L = 1/3: y = 10 * 2/3
    assert runs[0][-1] == pytest.approx(20 / 3)


def test_a_rule_outside_the_blocks_of_a_model_with_blocks_is_at_its_line():
    b = small()
    b.block("only").rule("if x is lo then y is lo")
    line = line_of_next_call()
    b.rule("if x is hi then y is hi")
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    (d,) = caught.value.diagnostics
    assert d.loc.line == line and d.message.startswith("rule 2: a rule outside the blocks")


def test_a_tune_section_makes_a_model_fuzzyc_tune_fits(tmp_path):
    b = small()
    b.inference(defuzzify="weighted_average")
    b.rule("if x is lo then y is lo")
    b.rule("if x is hi then y is hi")
    b.tune("y.hi in [0.25, 1]")
    model = b.build()
    assert [n.target for n in model.tunables] == ["y.hi.value"]
    # lo + hi = 1 everywhere: y = 0 * (1 - x) + hi * x, so data y = x / 2 fits hi = 0.5
    data = tmp_path / "data.csv"
    data.write_text("x,y\n" + "".join(f"{x / 10},{x / 20}\n" for x in range(11)))
    fit = fuzzyc.tune(model, data).fit
    assert fit.values.tolist() == pytest.approx([0.5])
    line = line_of_next_call()
    b.tune("y.lo in [0.25, 1]")          # lo is 0, outside its bounds
    with pytest.raises(fuzzyc.FuzzycError) as caught:
        b.build()
    assert [(d.loc.line, d.message.split(":")[0]) for d in caught.value.diagnostics] == [
        (line, "tune line 2")]
