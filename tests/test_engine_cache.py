"""The engine's compiled tables are never stale: compiling makes a rule base's arrays read-only
(an in-place write raises), and a new array assigned in their place is seen at the next call."""
import gc
import math
import weakref

import numpy as np
import pytest

from fuzzyc.engine.inference import CACHE_SIZE, compiled, evaluate
from fuzzyc.semantics.model import Connective, Defuzzifier, set_entries

from test_engine_core import rulebase, var

INF = math.inf


def two_rules(conn=Connective.AND):
    """x on [-1, 1]: L falls from 1 at -1 to 0 at 1, R rises the other way; L -> y A (0),
    R -> y B (10), center of area.  At x = 0 both rules fire 0.5."""
    x = var("x", {"L": ("trap", -INF, -INF, -1, 1), "R": ("trap", -1, 1, INF, INF)})
    y = var("y", {"A": ("single", 0.0), "B": ("single", 10.0)}, lo=0.0, hi=20.0)
    rules = [(["L"], ["A"], {"conn": conn}), (["R"], ["B"], {"conn": conn})]
    return rulebase([x], [y], rules, defuzzifier=Defuzzifier.CENTER_OF_AREA)


# a one-clause OR rule is the same rule, but not a plain AND conjunction: the dense path
PATHS = {"grid": Connective.AND, "dense": Connective.OR}


@pytest.mark.parametrize("path", sorted(PATHS))
def test_a_compiled_rule_base_refuses_in_place_writes(path):
    rb = two_rules(PATHS[path])
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(5.0)   # (0.5 * 0 + 0.5 * 10) / 1
    assert (compiled(rb).grid is not None) == (path == "grid")
    for array in (rb.weights, rb.consequents, rb.antecedents, rb.negated, rb.hedges,
                  rb.connective, rb.inputs[0].params, rb.outputs[0].params, rb.outputs[0].kinds):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = array[1]
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(5.0)


def test_the_array_a_view_was_taken_from_is_read_only_too():
    rb = two_rules()
    learned = np.array([1.0, 1.0, 7.0])
    rb.weights = learned[:2]
    evaluate(rb, [[0.0]])
    with pytest.raises(ValueError, match="read-only"):
        learned[1] = 0.25


@pytest.mark.parametrize("path", sorted(PATHS))
def test_new_arrays_are_seen_at_the_next_evaluation(path):
    rb = two_rules(PATHS[path])
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(5.0)
    # weights (1, 0.25): activations 0.5 and 0.125, y = 0.125 * 10 / 0.625 = 2
    rb.weights = np.array([1.0, 0.25])
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(2.0)
    # B moved to 20: y = 0.125 * 20 / 0.625 = 4
    set_entries(rb.outputs[0], "params", (1, 0), 20.0)
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(4.0)
    # rule 2 concludes A as well: every fired rule says 0
    set_entries(rb, "consequents", (1, 0), 0)
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(0.0)
    set_entries(rb, "consequents", (1, 0), 1)
    # many new weight arrays in a row (a freed array's id may come back): w2 = k / 10 gives
    # y = 0.5 w2 * 20 / (0.5 + 0.5 w2) = 20 w2 / (1 + w2)
    for k in range(1, 20):
        rb.weights = np.array([1.0, k / 10])
        assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(20 * (k / 10) / (1 + k / 10))


def test_params_in_a_list_are_compared_by_value():
    """Lists cannot be made read-only: a change in place is seen all the same."""
    rb = two_rules()
    rb.outputs[0].params = [[0.0, 0, 0, 0], [10.0, 0, 0, 0]]
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(5.0)
    rb.outputs[0].params[1][0] = 30.0                   # (0.5 * 0 + 0.5 * 30) / 1 = 15
    assert evaluate(rb, [[0.0]])[0, 0] == pytest.approx(15.0)


def test_scalars_and_inference_are_compared_by_value():
    rb = two_rules()
    rb.weights = np.array([1.0, 0.5])
    # at x = 0.5: L 0.25, R 0.75 * 0.5 = 0.375; y = 0.375 * 10 / 0.625 = 6
    assert evaluate(rb, [[0.5]])[0, 0] == pytest.approx(6.0)
    rb.inference.defuzzifier = Defuzzifier.WEIGHTED_SUM  # 0.25 * 0 + 0.375 * 10 = 3.75
    assert evaluate(rb, [[0.5]])[0, 0] == pytest.approx(3.75)
    rb.outputs[0].default = 3.0                          # nothing fires at NaN: the default
    assert evaluate(rb, [[np.nan]])[0, 0] == 3.0


def test_the_cache_lets_rule_bases_no_longer_used_go():
    first = two_rules()
    evaluate(first, [[0.0]])
    gone = weakref.ref(first)
    del first
    for _ in range(CACHE_SIZE):          # as many newer rule bases as the cache holds
        evaluate(two_rules(), [[0.0]])
    gc.collect()
    assert gone() is None


def test_a_rule_base_in_use_keeps_its_tables():
    rb = two_rules()
    tables = compiled(rb)
    for _ in range(CACHE_SIZE - 1):      # each call to rb moves it to the front
        evaluate(two_rules(), [[0.0]])
        assert compiled(rb) is tables
