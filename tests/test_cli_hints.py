"""A refusal or a lossy result says what to do instead (issue 30, "Errors at the right line, with
the fix"): q15 on a centroid file at its `defuzzify = centroid`, naming the float headers and
the lookup table; a coarse lookup table naming --resolution; convert naming what it drops and a
renamed output; and the q15 header of several rule blocks states each block's bound."""
from __future__ import annotations

import re

from fuzzyc.cli import main

CENTROID = """controller cen {
  input a in [0, 10]
  terms a : lo = tri(-10, 0, 10), hi = tri(0, 10, 20)
  var y in [0, 10]
  terms y : lo = tri(-10, 0, 10), hi = tri(0, 10, 20)
  inference defuzzify = centroid   # what q15 cannot emit
  rule if a is lo then y is lo
  rule if a is hi then y is hi
  output u in [0, 10] = y
}
"""


def test_q15_refusal_is_at_the_defuzzifier_and_names_what_takes_it(tmp_path, capsys):
    path = tmp_path / "cen.fz"
    path.write_text(CENTROID)
    assert main(["compile", str(path), "--numeric", "q15", "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{path}:6:25: error: the q15 back end emits" in err   # the `c` of centroid
    assert "`centroid` is not supported" in err
    assert "`--numeric float`" in err and "`--target lut`" in err
    assert not (tmp_path / "out" / "cen_q15.h").exists()


def test_a_coarse_lookup_table_names_its_resolution(tmp_path, capsys):
    path = tmp_path / "cen.fz"
    path.write_text(CENTROID)
    # 3 points over [0, 10] (0, 5, 10): the centroid between them is not linear, its error
    # is printed (0.32 here, 3.2 % of the range) with the option that lowers it
    assert main(["compile", str(path), "--target", "lut", "--resolution", "3",
                 "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    error = float(re.search(r"max error y: (\S+) \(", out).group(1))
    assert error > 1e-3 * 10 and "(--resolution, now 3)" in out
    # a fine grid: within 1e-3 of the range, no hint
    assert main(["compile", str(path), "--target", "lut", "--resolution", "2001",
                 "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert float(re.search(r"max error y: (\S+) \(", out).group(1)) <= 1e-2
    assert "--resolution" not in out


def test_convert_says_what_it_drops_and_a_renamed_output(tmp_path, capsys):
    path = tmp_path / "tip.fz"
    path.write_text(CENTROID.replace("output u in [0, 10] = y\n}",
                                     "output tip_pct in [0, 10] = y\n"
                                     "  verify {\n    consistent\n    complete\n  }\n}"))
    assert main(["convert", str(path), str(tmp_path / "tip.fis")]) == 0
    err = capsys.readouterr().err
    assert "warning: output tip_pct is the rule-base output y under another name" in err
    assert "warning: 2 verify properties dropped: the format has no place for them" in err


def test_q15_of_several_blocks_states_each_blocks_bound(tmp_path, capsys):
    from test_c_blocks import FIXED
    path = tmp_path / "fx.fz"
    path.write_text(FIXED)
    assert main(["compile", str(path), "--numeric", "q15", "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "derived worst case of rule block 0 (first): g " in out
    assert "derived worst case of rule block 1 (second): du " in out
    assert (tmp_path / "fx_q15.h").exists()


def test_closed_loop_counts_agree_with_their_noun():
    # a Gymnasium loop with nothing to vary runs as few as one environment
    from fuzzyc.semantics.model import Property
    from fuzzyc.verifier.result import Evidence, Result, Status
    prop = Property("closed_loop", {}, None, "closed_loop x")

    def summary(n):
        return Result(prop, "x", [Evidence("closed-loop", Status.HELD, "", cases=n)]).summary()
    assert (summary(1), summary(2)) == ("held: 1 closed loop", "held: 2 closed loops")
