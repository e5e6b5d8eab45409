"""Every random rule base of the differential fuzzer that imports converts to `.fz` and reads
back with the same numbers under every semantics (issue 28), at the generator's evaluation
points: bit-identical, NaN and NaN, or within 1e-12 (tests/differential/roundtrip.py).  A
file the writer refuses, one that does not read back, other numbers or a crash fails: `.fz`
says everything these generators write (terms peaking outside their ranges included: a
located warning when read back, docs/formats.md).
`python -m differential` reports the same per tool over its campaign."""
from __future__ import annotations

import collections

import numpy as np
import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.formats import load_any
from tests.differential.render import SUFFIX, render
from tests.differential.roundtrip import fz_round_trip
from tests.differential.spec import Generator, evaluation_points

PER_FORMAT = 40


# FLL in pyfuzzylite's vocabulary (fuzzylite 6's is a subset of it) and fuzzylite's FCL; the
# Octave FIS and the 200-file campaigns: `python -m differential` (its `.fz round trip` column)
@pytest.mark.parametrize("fmt", ["fll", "fcl"])
def test_random_rule_bases_round_trip_through_fz(fmt, tmp_path):
    generator = Generator(fmt, 2026 + len(fmt))
    outcomes = collections.Counter()
    for k in range(PER_FORMAT):
        system = generator.system(f"rt{k}")
        path = tmp_path / f"rt{k}{SUFFIX[fmt]}"
        path.write_text(render(system))
        try:
            model = load_any(path)
        except FuzzycError:
            outcomes["not imported"] += 1
            continue
        x = np.array(evaluation_points(system, k))
        done = fz_round_trip(model, x, str(path.with_suffix(".fz")))
        assert done.status == "same", (path.name, render(system), done.message)
        outcomes[done.status] += 1
    # most files import (the tools' vocabulary is wider than ours in a few refused corners)
    assert outcomes["same"] >= PER_FORMAT * 9 // 10, outcomes
