"""The stated limits (fuzzyc.language.limits) at the limit and one past it, and the regressions of issue
13's "limits and numbers": each case is the issue's own."""
from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from fuzzyc.engine import inference as engine
from fuzzyc.language import limits
from fuzzyc.cli import compile as cli_compile
from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any
from fuzzyc.semantics.model import ACTIVATION_FLOOR, SourceLoc
from fuzzyc.language.parser import parse
from conftest import ROOT

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")


def controller(x_range="[0, 1]", x_terms="uniform L H", rules=None, outputs=True,
               extra="") -> str:
    rules = rules if rules is not None else ["rule if x is L then y is A",
                                             "rule if x is H then y is B"]
    return "\n".join(["controller c {", f"  input x in {x_range}", f"  terms x : {x_terms}",
                      "  var y in [0, 1]", "  terms y : singletons A=0 B=1",
                      "  inference defuzzify = center_of_area", extra,
                      *("  " + r for r in rules),
                      "  output u in [0, 1] = y" if outputs else "", "}", ""])


def errors_of(text: str) -> list[str]:
    with pytest.raises(FuzzycError) as info:
        parse(text, "t.fz")
    return [d.format() for d in info.value.diagnostics]


# -- counts -------------------------------------------------------------------------------------

def test_terms_per_variable_at_the_limit_and_past_it():
    names = lambda n: "uniform " + " ".join(f"T{i}" for i in range(n))   # noqa: E731
    model = parse(controller(x_terms=names(limits.MAX_TERMS),
                             rules=["rule if x is T0 then y is A"]), "t.fz")
    assert model.rulebase.inputs[0].n_terms == limits.MAX_TERMS
    (message,) = errors_of(controller(x_terms=names(limits.MAX_TERMS + 1),
                                      rules=["rule if x is T0 then y is A"]))
    # located at the first term past the limit: `T253` on line 3
    column = len("  terms x : uniform ") + len(" ".join(f"T{i}" for i in range(253))) + 2
    assert message.startswith(f"t.fz:3:{column}: error: `x` has 254 terms: at most 253")


def _with_rules(model, n: int):
    """The model with its first rule repeated n times (parsing 10k rules takes ~18 s)."""
    rb = model.rulebase
    for name in ("antecedents", "consequents", "weights", "negated", "hedges", "connective"):
        array = getattr(rb, name)
        setattr(rb, name, np.repeat(array[:1], n, axis=0))
    rb.rule_locs = [SourceLoc("t.fz", 8 + r, 3) for r in range(n)]
    return model


def test_rules_at_the_limit_and_past_it():
    limits.check_model(_with_rules(parse(controller()), limits.MAX_RULES))
    with pytest.raises(FuzzycError) as info:
        limits.check_model(_with_rules(parse(controller()), limits.MAX_RULES + 1))
    (message,) = [d.format() for d in info.value.diagnostics]
    # located at the first rule past the limit
    assert message.startswith(f"t.fz:{8 + limits.MAX_RULES}:3: error: "
                              f"{limits.MAX_RULES + 1} rules: at most {limits.MAX_RULES}")


def _inputs_file(n: int) -> str:
    lines = ["controller c {"]
    for i in range(n):
        lines += [f"  input x{i} in [0, 1]", f"  terms x{i} : uniform L H"]
    lines += ["  var y in [0, 1]", "  terms y : singletons A=0 B=1",
              "  rule if x0 is L then y is A", "}"]
    return "\n".join(lines)


def test_rulebase_inputs_at_the_limit_and_past_it():
    assert len(parse(_inputs_file(limits.MAX_RULEBASE_INPUTS)).rulebase.inputs) == \
        limits.MAX_RULEBASE_INPUTS
    (message,) = errors_of(_inputs_file(limits.MAX_RULEBASE_INPUTS + 1))
    # input 33 (x32) is declared on line 2 + 2 * 32; its terms statement makes it linguistic
    assert f"{limits.MAX_RULEBASE_INPUTS + 1} rule-base inputs: at most 32" in message
    assert message.startswith(f"t.fz:{2 + 2 * limits.MAX_RULEBASE_INPUTS + 1}:")


def _outputs_file(n: int) -> str:
    lines = ["controller c {", "  input x in [0, 1]", "  terms x : uniform L H"]
    for o in range(n):
        lines += [f"  var y{o} in [0, 1]", f"  terms y{o} : singletons A=0 B=1"]
    lines += ["  rule if x is L then " + ", ".join(f"y{o} is A" for o in range(n)), "}"]
    return "\n".join(lines)


def test_rulebase_outputs_at_the_limit_and_past_it():
    assert len(parse(_outputs_file(limits.MAX_RULEBASE_OUTPUTS)).rulebase.outputs) == 32
    (message,) = errors_of(_outputs_file(limits.MAX_RULEBASE_OUTPUTS + 1))
    assert "33 rule-base outputs: at most 32" in message


def test_source_size_at_the_limit_and_past_it(tmp_path):
    text = controller()
    pad = limits.MAX_SOURCE_BYTES - len(text.encode()) - 1      # "#" + pad + text
    path = tmp_path / "big.fz"
    path.write_text("#" + "x" * pad + "\n" + text[:-1])
    assert path.stat().st_size == limits.MAX_SOURCE_BYTES
    assert load_any(path).name == "c"
    path.write_text("#" + "x" * (pad + 1) + "\n" + text[:-1])
    with pytest.raises(FuzzycError, match=f"larger than {limits.MAX_SOURCE_BYTES} bytes"):
        load_any(path)
    fis = tmp_path / "big.fis"                 # every format: read through the same gate
    fis.write_bytes(b"%" * (limits.MAX_SOURCE_BYTES + 1))
    with pytest.raises(FuzzycError, match="larger than"):
        load_any(fis)


# -- numbers ------------------------------------------------------------------------------------

@pytest.mark.parametrize("number, ok", [
    (limits.MAX_MAGNITUDE, True), (limits.MAX_MAGNITUDE * 1.5, False),
    (limits.MIN_MAGNITUDE, True), (limits.MIN_MAGNITUDE / 1.5, False)])
def test_number_magnitude_at_the_limit_and_past_it(number, ok):
    text = controller(x_range=f"[0, {number!r}]")
    if ok:
        assert parse(text).signals[0].hi == number
    else:
        (message,) = errors_of(text)
        assert message.startswith("t.fz:2:18: error: the number")


def test_range_width_at_the_limit_and_past_it():
    # [1e6 - 10, 1e6]: width 10 = 1e-5 * 1e6 (at the limit); [1e6 - 9, 1e6]: 9 < 10
    assert limits.MIN_RELATIVE_WIDTH == 1e-5
    parse(controller(x_range="[999990, 1000000]"))
    messages = errors_of(controller(x_range="[999991, 1000000]"))
    assert any("narrower than 1e-05 of its magnitude" in m for m in messages)


def test_issue_1e308_is_a_stated_limit_not_an_overflow():
    (message,) = errors_of(controller(x_range="[0, 1e308]"))
    assert message.startswith("t.fz:2:18: error: the number 1e+308 is larger than 1e+12")
    assert "inf" not in message


def test_issue_1e400_is_rejected_by_check_not_a_compile_crash():
    (message,) = errors_of(controller(x_range="[0, 1e400]"))
    assert message.startswith("t.fz:2:18: error: the number inf is not finite")


def test_issue_denormal_range_is_rejected_with_its_place(tmp_path, capsys):
    path = tmp_path / "d.fz"
    path.write_text(controller(x_range="[1e-310, 2e-310]"))
    out = tmp_path / "out"
    assert main(["compile", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:2:15: error: the number 1e-310 is smaller than 1e-12" in err
    assert not out.exists()


def test_importers_meet_the_same_number_limits(tmp_path):
    fis = tmp_path / "huge.fis"
    text = open(f"{ROOT}/tests/format_corpus/sugeno.fis").read().replace("Range=[0 1]",
                                                                  "Range=[0 1e300]", 1)
    fis.write_text(text)
    with pytest.raises(FuzzycError, match="huge.fis:15:1: error: `x`: the number 1e.300 is "
                                          "larger than 1e.12") as info:
        load_any(fis)
    assert len(info.value.diagnostics) == 1      # not again for the input of the same range


# -- the C headers: built before they are published ---------------------------------------------

@needs_gcc
def test_issue_no_output_statement_compiles(tmp_path, capsys):
    path = tmp_path / "n.fz"
    path.write_text(controller(outputs=False, extra="  let z = x * 2"))   # z is unused too
    for numeric in ("float", "double", "q15", "q31"):
        assert main(["compile", str(path), "--numeric", numeric, "-o", str(tmp_path)]) == 0
    assert "test-built with gcc -std=c99" in capsys.readouterr().out


@needs_gcc
def test_a_header_gcc_rejects_never_lands(tmp_path, monkeypatch, capsys):
    from fuzzyc.backends.c import header as c
    path = tmp_path / "c.fz"
    path.write_text(controller())
    out = tmp_path / "out"
    out.mkdir()
    monkeypatch.setattr(c, "generate_header", lambda model, numeric: "int broken(void) {\n")
    assert main(["compile", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"the C compiler rejected the generated code (nothing was written to {out}/c.h)" \
        in err
    assert list(out.iterdir()) == []             # no header, no temporary file


def test_without_a_compiler_the_header_is_written_and_says_so(tmp_path, monkeypatch, capsys):
    path = tmp_path / "c.fz"
    path.write_text(controller())
    monkeypatch.setattr(cli_compile.shutil, "which", lambda name: None)
    assert main(["compile", str(path), "-o", str(tmp_path)]) == 0
    assert "not test-built: no C compiler `gcc` on PATH" in capsys.readouterr().out
    assert (tmp_path / "c.h").exists()


def _table_file(n_inputs: int, n_terms: int) -> str:
    names = " ".join(f"T{i}" for i in range(n_terms))
    lines = ["controller g {"]
    for i in range(n_inputs):
        lines += [f"  input x{i} in [0, 1]", f"  terms x{i} : uniform {names}"]
    lines += ["  inference defuzzify = center_of_area", "  var y in [0, 1]",
              "  terms y : singletons A=0 B=1",
              "  rule if " + " and ".join(f"x{i} is T0" for i in range(n_inputs))
              + " then y is A",
              "  rule if " + " and ".join(f"x{i} is T1" for i in range(n_inputs))
              + " then y is B", "  output u in [0, 1] = y", "}"]
    return "\n".join(lines)


@needs_gcc
@pytest.mark.parametrize("n_terms, direct", [(16, True), (17, False)])
def test_float_cell_table_at_the_limit_and_past_it(n_terms, direct):
    """4 inputs: 16^4 = 65536 = MAX_C_TABLE_CELLS cells (a code per tuple of terms), indexed
    by the cell code; 17^4 = 83521 past it: the header keeps the 2 occupied cells' codes and
    searches them; it agrees with the engine either way (past MAX_C_TABLE_CELLS occupied
    cells it loops over every rule: tests/test_engine_wide.py)."""
    from fuzzyc.backends.c.header import HeaderWriter
    from fuzzyc.backends.c.expressions import REAL_TYPES
    from fuzzyc.backends.c.load import CController
    model = parse(_table_file(4, n_terms))
    writer = HeaderWriter(model, REAL_TYPES["double"])
    assert writer.sparse and (writer.cells.codes is None) is direct
    x = np.random.default_rng(1).uniform(0, 0.2, (200, 4))
    np.testing.assert_allclose(CController(model, numeric="double").evaluate(x),
                               engine.evaluate(model.rulebase, x), atol=1e-12)


@needs_gcc
@pytest.mark.parametrize("n_terms, direct", [(16, True), (17, False)])
def test_fixed_cell_table_at_the_limit_and_past_it(n_terms, direct):
    """The q15 header takes the float header's cell table: 16^4 = 65536 = MAX_C_TABLE_CELLS
    cells indexed by the code, 17^4 = 83521 past it: the 2 occupied cells' codes searched.
    Rule 1 (all T0 -> A = 0) fires alone at x = 0: y = 0; near the T1 peak 1 / (T - 1)
    (xq = round(32767 / 15) = 2184, round(32767 / 16) = 2048) rule 2 (all T1 -> B = 1)
    fires at about 1 and rule 1 at the T0 membership left there (1 - 15 * 2184 / 32767 =
    2.1e-4 at 16 terms): the engine's y, within the stated bound 2^-11 (16 LSB)."""
    from fuzzyc.backends.c_fixed.header import FixedPointWriter
    from test_c_fixed import fixed_point_runner
    model = parse(_table_file(4, n_terms))
    cells = FixedPointWriter(model, "q15").tables.cells
    assert (cells.codes is None) is direct and cells.rows.shape[0] == (65536 if direct else 3)
    peak = round(32767 / (n_terms - 1))
    xq = np.array([[0] * 4, [peak] * 4])
    yq = fixed_point_runner(model, "q15")(xq)[:, 0]
    y = engine.evaluate(model.rulebase, xq / 32767)[:, 0]
    assert yq[0] == 0 and y[1] > 0.999 and abs(yq[1] - y[1] * 32767) <= 16


@pytest.mark.parametrize("n_inputs, n_terms, words", [
    # 12^9 = 5.2e9 codes: a code would pass 32 bits (the float header loops over every rule)
    (9, 12, "5159780352 codes .* pass 32 bits"),
    # 2 slots per input: 2^17 = 131072 combinations a call, past MAX_C_SLOT_COMBINATIONS
    (17, 2, "131072 per call, at most 65536")])
def test_fixed_header_past_its_limits_says_which(n_inputs, n_terms, words):
    from fuzzyc.backends.c_fixed.header import generate_fixed_header
    with pytest.raises(FuzzycError, match=words):
        generate_fixed_header(parse(_table_file(n_inputs, n_terms)), "q15")


def test_fixed_header_at_the_combination_limit():
    # 16 inputs of 2 terms: 2^16 = 65536 = MAX_C_SLOT_COMBINATIONS combinations, and 2^16
    # codes: a direct table
    from fuzzyc.backends.c_fixed.header import FixedPointWriter
    tables = FixedPointWriter(parse(_table_file(16, 2)), "q15").tables
    assert tables.combos == 65536 and tables.cells.codes is None


# -- never NaN, C and engine agree outside the range --------------------------------------------

SUGENO_LINEAR = f"{ROOT}/tests/format_corpus/sugeno_linear.fis"


def _eval(capsys, *args) -> str:
    assert main(["eval", *args]) == 0
    return capsys.readouterr().out


def test_issue_ts_nan_input_gives_the_default(capsys):
    # x = nan: rule 4 (x is high or w is not neg) still fires at 1 (w = 0.5 is not neg), but its
    # consequent ramp weights x, so it has no value; nothing else fires -> z's default, the
    # middle of [-20, 40] = 10.
    assert "outputs: z = 10, z_out = 10" in _eval(capsys, SUGENO_LINEAR, "x=nan", "w=0.5")
    data = json.loads(_eval(capsys, "--json", SUGENO_LINEAR, "x=nan", "w=0.5"))
    assert data["outputs"] == {"z": 10.0, "z_out": 10.0}


def test_issue_ts_huge_input_reads_the_range_edge(capsys):
    # x = 1e308 -> the consequents read x = 10 (its range's top); memberships at 1e308: high 1,
    # low = mid = 0; w = 0.5: pos 1, neg 0.  Rule 3 (high and pos, weight 0.5) -> steep
    # 0.5*10 + 4*0.5 - 2 = 5 at 0.5; rule 4 (high or not neg) -> ramp 2*10 - 3*0.5 + 1 = 19.5
    # at 1.  (19.5 + 0.5*5) / 1.5 = 14.6667
    out = _eval(capsys, SUGENO_LINEAR, "x=1e308", "w=0.5")
    assert "outputs: z = 14.6667" in out
    data = json.loads(_eval(capsys, "--json", SUGENO_LINEAR, "x=inf", "w=0.5"))
    assert data["outputs"]["z"] == pytest.approx(22 / 1.5)


@pytest.mark.parametrize("path", [f"{ROOT}/tests/format_corpus/sugeno.fis", SUGENO_LINEAR,
                                  f"{ROOT}/rulebases/wedm_three_region.fz",
                                  f"{ROOT}/rulebases/milling_neurofuzzy.fz"])
def test_every_rule_base_kind_is_finite_for_hostile_inputs(path):
    rb = load_any(path).rulebase
    hostile = np.array([np.nan, np.inf, -np.inf, 1e308, -1e308, 0.0])
    grid = np.stack(np.meshgrid(*[hostile] * len(rb.inputs)), -1).reshape(-1, len(rb.inputs))
    with np.errstate(all="ignore"):
        y = engine.evaluate(rb, grid)
    assert np.all(np.isfinite(y))


@needs_gcc
def test_issue_float_header_agrees_with_the_engine_far_outside_the_range():
    """sugeno.fis at x = -3, y = +-1e30: the only positive activation is rule 2's
    0.5 * probor(0, bell(y)) with bell(1e30) = 1/(1 + (2e30)^4) ~ 6e-122 < ACTIVATION_FLOOR: no
    rule fires, both give the default 5 (the float header could not hold 6e-122: it gave 5 while
    the engine said 8)."""
    from fuzzyc.backends.c.load import CController
    model = load_any(f"{ROOT}/tests/format_corpus/sugeno.fis")
    x = np.array([[-3.0, 1e30], [-3.0, -1e30], [0.5, 1e30]])
    expected = [[5.0], [5.0], [8.0]]          # x = 0.5: rule 2 at 0.5 * probor(0.5, ~0) -> b = 8
    assert engine.evaluate(model.rulebase, x) == pytest.approx(np.array(expected))
    assert CController(model, numeric="float").evaluate(x) == pytest.approx(np.array(expected))


def test_an_activation_below_the_floor_does_not_fire():
    # one rule on L = gauss(0, 1): at x = 7.5, mu = exp(-56.25/2) = exp(-28.125) = 6.1e-13 <
    # ACTIVATION_FLOOR: nothing fires -> y's default 0.5; at x = 7, exp(-49/2) = 2.3e-11 fires
    # -> A = 0
    text = controller(x_range="[0, 20]", x_terms="L = gauss(0, 1), H = gauss(20, 1)",
                      rules=["rule if x is L then y is A"]).replace(
        "var y in [0, 1]", "var y in [0, 1] default 0.5")
    rb = parse(text).rulebase
    x = np.array([[7.5], [7.0]])
    assert engine.activations(rb, x)[:, 0] == pytest.approx([0.0, np.exp(-24.5)], rel=1e-12)
    assert engine.evaluate(rb, x)[:, 0].tolist() == [0.5, 0.0]
    assert ACTIVATION_FLOOR == 1e-12


def _scaled_file(s: float) -> str:
    return f"""controller s {{
  input x in [{-s!r}, {s!r}]
  terms x : uniform N Z P
  var y in [{-s!r}, {s!r}]
  terms y : N = tri({-s!r}, {-s!r}, 0), Z = tri({-s!r}, 0, {s!r}), P = tri(0, {s!r}, {s!r})
  inference defuzzify = centroid
  rule if x is N then y is N
  rule if x is Z then y is Z
  rule if x is P then y is P
  output u in [{-s!r}, {s!r}] = y
}}"""


@needs_gcc
@pytest.mark.parametrize("scale", [limits.MAX_MAGNITUDE, limits.MIN_MAGNITUDE, 1.0])
def test_float_header_is_as_accurate_at_the_magnitude_limits_as_at_scale_one(scale):
    """The exact centroid (cubes of u over the output's range) in float: measured 1.1e-7,
    1.0e-7 and 1.3e-7 of the range at 1e12, 1e-12 and 1; overflow or denormals would be far
    off (inf, NaN or the default)."""
    from fuzzyc.backends.c.load import CController
    model = parse(_scaled_file(scale))
    x = np.linspace(-scale, scale, 101)[:, None]
    error = np.abs(CController(model, numeric="float").evaluate(x)
                   - engine.evaluate(model.rulebase, x)).max()
    assert error <= 1e-6 * scale


def test_issue_ten_thousand_terms_are_refused_before_compile(tmp_path, capsys):
    # was: compile used 3.6 GB and died
    path = tmp_path / "t.fz"
    path.write_text(controller(x_terms="uniform " + " ".join(f"T{i}" for i in range(10_000)),
                               rules=["rule if x is T0 then y is A"]))
    assert main(["compile", str(path), "-o", str(tmp_path / "out")]) == 2
    assert "`x` has 10000 terms: at most 253 per variable" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_issue_half_a_million_params_are_refused_unread(tmp_path, capsys):
    # was: check took over 2 minutes and 866 MB; now refused after reading MAX_SOURCE_BYTES + 1
    path = tmp_path / "p.fz"
    path.write_text(controller(extra="\n".join(f"  param p{i} = {i}" for i in range(500_000))))
    assert path.stat().st_size > limits.MAX_SOURCE_BYTES
    assert main(["check", str(path)]) == 2
    assert f"is larger than {limits.MAX_SOURCE_BYTES} bytes" in capsys.readouterr().err
