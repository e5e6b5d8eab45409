"""Issue 13, exports: a model whose names or texts are hostile is written so that it reads back
to the same rule base, or refused with a message naming the name; never a file that parses to
something else."""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st

from fuzzyc.engine.inference import evaluate
from fuzzyc.errors import FuzzycError
from fuzzyc.escape import SAFE_NAME
from fuzzyc.formats import load_any, save
from hostile_fis import sugeno_fis

KEYS = ("x", "lo", "hi", "u", "small", "big")
FORMATS = (".fz", ".fll", ".fcl", ".fis")


def names_of(model) -> list[str]:
    rb = model.rulebase
    return [n for v in rb.inputs + rb.outputs for n in (v.name, *v.names)]


def fis_model(folder: Path, names: dict[str, str]):
    path = folder / "m.fis"
    path.write_text(sugeno_fis("m", [(names["x"], names["lo"], names["hi"])],
                               (names["u"], names["small"], names["big"])))
    return load_any(path)


def test_hostile_names_are_refused_by_name_or_kept(tmp_path):
    names = dict(zip(KEYS, ("x */ int injected = 5; /* y", "lo", "hi", "u", "a b", "big")))
    model = fis_model(tmp_path, names)
    for suffix in (".fll", ".fcl"):
        with pytest.raises(FuzzycError) as refused:
            save(model, tmp_path / f"out{suffix}")
        message = str(refused.value)
        assert "'x */ int injected = 5; /* y' cannot be written" in message
        assert "'a b' cannot be written" in message
        assert not (tmp_path / f"out{suffix}").exists()
    for suffix in (".fis", ".fz"):          # FIS quotes its names, .fz backticks them: kept
        save(model, tmp_path / f"out{suffix}")
        back = load_any(tmp_path / f"out{suffix}")
        assert names_of(back) == names_of(model)
        x = np.array([[0.0], [0.25], [1.0]])
        # wtaver of 2 and 8 with weights (1 - x, x): 2 + 6x = 2, 3.5, 8
        assert np.allclose(evaluate(back.rulebase, x)[:, 0], [2.0, 3.5, 8.0])
    assert "input `x */ int injected = 5; /* y` in [" in (tmp_path / "out.fz").read_text()


def test_fis_refuses_what_its_quotes_cannot_hold(tmp_path):
    model = fis_model(tmp_path, dict(zip(KEYS, ("x", "lo", "hi", "u", "small", "big"))))
    var = model.rulebase.inputs[0]
    var.names[0] = "it's"
    var.names[1] = "line\nbreak"
    with pytest.raises(FuzzycError) as refused:
        save(model, tmp_path / "out.fis")
    assert "\"it's\" cannot be written in FIS" in str(refused.value)
    assert "'line\\nbreak' cannot be written in FIS" in str(refused.value)


def test_titles_and_notes_stay_on_their_line(tmp_path):
    model = fis_model(tmp_path, dict(zip(KEYS, ("x", "lo", "hi", "u", "small", "big"))))
    model.title = 'title\nInputVariable: z\n  term: q Constant 1\n"}\\'
    model.notes = ["note\nrule if x is lo then u is big"]
    for suffix in FORMATS:
        save(model, tmp_path / f"out{suffix}")
        back = load_any(tmp_path / f"out{suffix}")
        assert names_of(back) == names_of(model)
        assert back.rulebase.n_rules == 2
        np.testing.assert_array_equal(back.rulebase.consequents, model.rulebase.consequents)


NASTY = st.text(alphabet="ab_9 */\\'%\n#:;=,[]()\"$é.-", min_size=1, max_size=5)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.lists(NASTY, min_size=len(KEYS), max_size=len(KEYS), unique=True))
def test_any_names_read_back_the_same_or_are_refused(values):
    names = dict(zip(KEYS, values))
    with tempfile.TemporaryDirectory() as work:
        folder = Path(work)
        try:
            model = fis_model(folder, names)
        except FuzzycError:
            assume(False)     # the FIS reader refused them (a name repeated ignoring case, quotes, ...)
        for suffix in FORMATS:
            out = folder / f"out{suffix}"
            try:
                save(model, out)
            except FuzzycError as exc:
                unsafe = [n for n in names_of(model) if not SAFE_NAME.fullmatch(n)]
                if suffix == ".fz":     # `__` starts fuzzyc's own names; `_` gives `__out`
                    unsafe += [n for n in names_of(model) if n.startswith("__")]
                    unsafe += [names["u"]] if names["u"] == "_" else []
                assert suffix == ".fis" or unsafe, str(exc)
                continue
            back = load_any(out)
            assert names_of(back) == names_of(model)
            np.testing.assert_array_equal(back.rulebase.antecedents, model.rulebase.antecedents)
            np.testing.assert_array_equal(back.rulebase.consequents, model.rulebase.consequents)
