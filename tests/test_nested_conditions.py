"""Nested rule conditions (and/or/not, parentheses, hedges): the matrix row kept for flat rules,
a clause program otherwise; hand-computed activations, the .fz, FLL and FCL front ends, the
exporters, and the back ends that follow (engine, lookup table) or refuse by name (C, fixed
point, FIS, the verifier's rule-table analysis).  fuzzylite's CLI is the outside oracle."""
from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from fuzzyc.backends.c.header import generate_header
from fuzzyc.backends.c_fixed.header import generate_fixed_header
from fuzzyc.backends.lut import LookupTable
from fuzzyc.language.conditions import Cond, premise
from fuzzyc.engine.inference import activations, evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.formats import read_fcl, read_fll
from fuzzyc.formats.fcl import write_fcl
from fuzzyc.formats.fis import write_fis
from fuzzyc.formats.fll import write_fll
from fuzzyc.formats.fz import write_fz
from fuzzyc.semantics.model import CondOp, Connective, Hedge
from fuzzyc.language.parser import parse
from fuzzyc.verifier.result import Status
from fuzzyc.verifier.runner import Options, check_property
from fuzzyc.semantics.model import Property

# Three inputs on [0, 1], L = tri(-1, 0, 1) = 1 - x and H = tri(0, 1, 2) = x there.
FZ = """controller nested {
  input a in [0, 1]
  input b in [0, 1]
  input c in [0, 1]
  terms a : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  terms b : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  terms c : L = tri(-1, 0, 1), H = tri(0, 1, 2)
  var y in [0, 10]
  terms y : singletons lo = 0 mid = 4 hi = 10
  inference and = AND_, or = OR_, defuzzify = coa
  rule if (a is H or b is very H) and not c is H then y is hi
  rule if not (a is H or b is H) then y is lo
  rule if a is H or b is H and c is H then y is mid
  rule if a is H and b is L then y is mid
  output u in [0, 10] = y
}
"""
X = [0.2, 0.6, 0.3]     # a: H .2 L .8; b: H .6 L .4, very H .36; c: H .3, not H .7


def model(and_: str = "min", or_: str = "max"):
    return parse(FZ.replace("AND_", and_).replace("OR_", or_), "nested.fz")


def test_only_nested_rules_get_a_program():
    rb = model().rulebase
    assert sorted(rb.conditions) == [0, 1, 2]         # rule 4 is a flat conjunction
    assert rb.antecedents[3].tolist() == [1, 0, -1]
    assert (rb.antecedents[:3] == -1).all()
    # rule 2: a.H b.H OR NOT (postfix)
    assert rb.conditions[1][:, :3].tolist() == [[CondOp.CLAUSE, 0, 1], [CondOp.CLAUSE, 1, 1],
                                                 [CondOp.OR, 0, 0], [CondOp.NOT, 0, 0]]
    assert rb.describe_rule(0) == "if (a is H or b is very H) and c is not H then y is hi"
    assert rb.describe_rule(1) == "if not (a is H or b is H) then y is lo"
    assert rb.describe_rule(2) == "if a is H or (b is H and c is H) then y is mid"


def test_min_max_activations_by_hand():
    act = activations(model().rulebase, [X])[0]
    # 1: min(max(.2, .6^2 = .36), 1 - .3) = min(.36, .7) = .36
    # 2: 1 - max(.2, .6) = .4
    # 3: `and` binds tighter: max(.2, min(.6, .3)) = .3
    # 4: min(.2, .4) = .2
    np.testing.assert_allclose(act, [0.36, 0.4, 0.3, 0.2], rtol=0, atol=1e-15)
    # centre of area, alpha per term = max over its rules: hi .36, lo .4, mid max(.3, .2) = .3
    #   (.36*10 + .4*0 + .3*4) / (.36 + .4 + .3) = 4.8 / 1.06
    np.testing.assert_allclose(evaluate(model().rulebase, [X])[0, 0], 4.8 / 1.06, rtol=1e-14)


def test_product_probsum_activations_by_hand():
    act = activations(model("product", "probsum").rulebase, [X])[0]
    # 1: (.2 + .36 - .072) * .7 = .488 * .7 = .3416
    # 2: 1 - (.2 + .6 - .12) = .32
    # 3: .2 + .18 - .036 = .344
    # 4: .2 * .4 = .08
    np.testing.assert_allclose(act, [0.3416, 0.32, 0.344, 0.08], rtol=0, atol=1e-15)


def leaf(name: str, term: int, negated: bool = False) -> Cond:
    return Cond("is", leaf=(name, (term, negated, Hedge.NONE)))


def test_premise_keeps_flat_rules_flat():
    a, b, c = leaf("a", 0), leaf("b", 1), leaf("c", 1)
    # (a and b) and c folds left to right as a flat conjunction does: the matrix row
    clauses, conn, program = premise(Cond("and", [Cond("and", [a, b]), c]))
    assert program is None and conn == Connective.AND and list(clauses) == ["a", "b", "c"]
    # not on one clause is the clause's negation; double not cancels
    clauses, conn, program = premise(Cond("not", [Cond("not", [Cond("not", [a])])]))
    assert program is None and clauses == {"a": (0, True, Hedge.NONE)}
    clauses, conn, program = premise(Cond("or", [a, Cond("and", [b])]))
    assert program is None and conn == Connective.OR
    # one input twice is not a matrix row
    _, _, program = premise(Cond("or", [a, leaf("a", 1)]))
    assert [step[0] for step in program] == [CondOp.CLAUSE, CondOp.CLAUSE, CondOp.OR]


def test_same_input_twice_is_a_program():
    text = FZ.replace("  rule if a is H and b is L then y is mid\n",
                      "  rule if a is L or a is H then y is mid\n")
    rb = parse(text.replace("AND_", "min").replace("OR_", "max"), "n.fz").rulebase
    # max(1 - .2, .2) = .8 (a flat or-row could not hold `a` twice)
    assert activations(rb, [X])[0, 3] == pytest.approx(0.8, abs=1e-15)


FLL = """Engine: nested
InputVariable: a
  enabled: true
  range: 0.000 1.000
  term: L Triangle -1.000 0.000 1.000
  term: H Triangle 0.000 1.000 2.000
InputVariable: b
  enabled: true
  range: 0.000 1.000
  term: L Triangle -1.000 0.000 1.000
  term: H Triangle 0.000 1.000 2.000
InputVariable: c
  enabled: true
  range: 0.000 1.000
  term: L Triangle -1.000 0.000 1.000
  term: H Triangle 0.000 1.000 2.000
OutputVariable: y
  enabled: true
  range: 0.000 10.000
  aggregation: none
  defuzzifier: WeightedAverage TakagiSugeno
  default: nan
  term: lo Constant 0.000
  term: hi Constant 10.000
  term: mid Constant 4.000
RuleBlock: r
  enabled: true
  conjunction: AlgebraicProduct
  disjunction: AlgebraicSum
  implication: none
  activation: General
  rule: if (a is H or b is very H) and c is not H then y is hi
  rule: if a is L and (b is L or c is L) then y is lo
  rule: if a is H or b is H and c is H then y is mid
"""
POINTS = np.array([X, [0.9, 0.1, 0.5], [0.5, 0.5, 0.5], [0.0, 1.0, 0.25], [1.0, 0.0, 1.0]])


def test_fll_nested_by_hand():
    y = evaluate(read_fll(FLL, "n.fll").rulebase, [X])[0, 0]
    # product/probsum: 1: (.2 + .36 - .072) * .7 = .3416 -> 10
    #   2: .8 * (.4 + .7 - .28) = .8 * .82 = .656 -> 0;  3: .2 + .18 - .036 = .344 -> 4
    # weighted average: (3.416 + 1.376) / (.3416 + .656 + .344) = 4.792 / 1.3416
    assert y == pytest.approx(4.792 / 1.3416, rel=1e-14)


def test_fll_nested_agrees_with_the_fuzzylite_cli(tmp_path):
    if shutil.which("fuzzylite") is None:
        pytest.skip("the fuzzylite CLI is not installed (Debian package fuzzylite)")
    (tmp_path / "n.fll").write_text(FLL)
    (tmp_path / "in.fld").write_text("\n".join(" ".join(map(str, p)) for p in POINTS) + "\n")
    subprocess.run(["fuzzylite", "-i", str(tmp_path / "n.fll"), "-of", "fld", "-d",
                    str(tmp_path / "in.fld"), "-o", str(tmp_path / "out.fld"),
                    "-decimals", "9"], check=True, capture_output=True)
    rows = (tmp_path / "out.fld").read_text().split("\n")[1:]
    theirs = np.array([float(r.split()[-1]) for r in rows if r.strip()])
    ours = evaluate(read_fll(FLL, "n.fll").rulebase, POINTS)[:, 0]
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-8)


FCL = """FUNCTION_BLOCK nested
VAR_INPUT a : REAL; b : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY a
  TERM L := (0, 1) (1, 0);
  TERM H := (0, 0) (1, 1);
END_FUZZIFY
FUZZIFY b
  TERM L := (0, 1) (1, 0);
  TERM H := (0, 0) (1, 1);
END_FUZZIFY
DEFUZZIFY y
  TERM lo := 0;
  TERM hi := 10;
  METHOD : COGS;
  DEFAULT := 0;
  RANGE := (0 .. 10);
END_DEFUZZIFY
RULEBLOCK r
  AND : MIN;
  OR : MAX;
  ACT : MIN;
  ACCU : MAX;
  RULE 1 : IF NOT (a IS H AND b IS H) THEN y IS lo;
  RULE 2 : IF a IS H AND (b IS H OR b IS L) THEN y IS hi;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_fcl_nested_by_hand():
    rb = read_fcl(FCL, "n.fcl").rulebase
    assert sorted(rb.conditions) == [0, 1]
    # at (.2, .6): 1: 1 - min(.2, .6) = .8;  2: min(.2, max(.6, .4)) = .2
    np.testing.assert_allclose(activations(rb, [[0.2, 0.6]])[0], [0.8, 0.2], atol=1e-15)
    # singletons, centroid = (.8*0 + .2*10) / (.8 + .2) = 2
    assert evaluate(rb, [[0.2, 0.6]])[0, 0] == pytest.approx(2.0, abs=1e-14)


@pytest.mark.parametrize("source, write, read", [
    (lambda: model("product", "probsum"), write_fz, lambda text: parse(text, "again.fz")),
    (lambda: read_fll(FLL, "n.fll"), write_fll, lambda text: read_fll(text, "again.fll")),
    (lambda: read_fcl(FCL, "n.fcl"), write_fcl, lambda text: read_fcl(text, "again.fcl")),
])
def test_exports_keep_nested_conditions(source, write, read):
    source = source()
    again = read(write(source))
    assert sorted(again.rulebase.conditions) == sorted(source.rulebase.conditions)
    points = POINTS[:, :len(source.rulebase.inputs)]
    np.testing.assert_allclose(evaluate(again.rulebase, points),
                               evaluate(source.rulebase, points), rtol=1e-12)


def test_fll_and_fis_refuse_by_name():
    with pytest.raises(FuzzycError, match=r"rule 2 negates a compound condition.*FLL"):
        write_fll(model())
    with pytest.raises(FuzzycError, match=r"rule 1 `if \(a is H or b is very H\).*nested"):
        write_fis(model())


def test_c_and_fixed_point_refuse_by_name_the_lookup_table_follows():
    m = model()
    with pytest.raises(FuzzycError, match=r"rule 1 `if \(a is H .* and 2 more has a nested"):
        generate_header(m)
    with pytest.raises(FuzzycError, match="nested condition"):
        generate_fixed_header(m, "q15")
    table = LookupTable(m.rulebase, 3)      # grid points 0, .5, 1 on every axis
    grid = np.array([[0.5, 1.0, 0.0], [1.0, 0.5, 0.5]])
    np.testing.assert_allclose(table.evaluate(grid), evaluate(m.rulebase, grid), atol=1e-12)


def test_verifier_says_undecided_for_the_rule_tables_and_searches_instead():
    m = model()
    [evidence] = check_property(m, Property("consistent", {}), Options())
    assert evidence.status == Status.UNDECIDED and "nested condition" in evidence.detail
    # covers: no proof for programs, the grid search evaluates them (coa, every rule >= 0):
    # rule 2 (1 - max(a, b)) and rule 3 (max(a, min(b, c))) leave no point dark
    evidence = check_property(m, Property("covers", {"inputs": ["a", "b", "c"], "level": 0.1}),
                              Options())
    assert evidence[0].status == Status.UNDECIDED and "nested" in evidence[0].detail
    assert evidence[-1].method == "grid" and evidence[-1].status == Status.HELD
