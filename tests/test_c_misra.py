"""The MISRA C:2012 rules the generated headers break, as cppcheck's MISRA addon reports them
(Debian package cppcheck; the addon checks the rules it implements, without the rule texts),
are exactly the ones docs/c-proofs.md names and explains, kind by kind over every shipped rule
base: a new kind of violation, or one the generator no longer makes, fails here until the docs
say so.  Skipped without cppcheck."""
from __future__ import annotations

import pathlib
import re
import shutil
import subprocess

import pytest

from fuzzyc.api import load
from fuzzyc.backends.c.proof import KINDS, header_for

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHIPPED = sorted((ROOT / "rulebases").glob("*.fz"))

# docs/c-proofs.md, "MISRA-C:2012 rules the headers follow, and those they break"
_EVERY_KIND = {"2.5", "8.9", "10.1", "10.3", "12.1", "12.3"}
_FLOATING = _EVERY_KIND | {"2.2", "9.3", "10.4", "13.4", "14.4", "18.4"}
_FIXED = _EVERY_KIND | {"2.2", "10.7"}
BROKEN = {"float": _FLOATING, "double": _FLOATING, "q15": _FIXED, "q31": _FIXED | {"10.8"},
          "lut": _EVERY_KIND | {"10.4", "15.5"}}


def misra_rules(header_name: str, text: str, work: pathlib.Path) -> set[str]:
    """The MISRA C:2012 rules cppcheck's addon reports in the header."""
    (work / header_name).write_text(text)
    unit = work / "unit.c"
    unit.write_text(f'#include "{header_name}"\n')
    result = subprocess.run(["cppcheck", "--addon=misra", "--std=c99", "--quiet",
                             "--error-exitcode=0", str(unit)],
                            capture_output=True, text=True, check=True)
    return set(re.findall(r"\[misra-c2012-([\d.]+)\]", result.stderr))


@pytest.mark.skipif(shutil.which("cppcheck") is None,
                    reason="cppcheck not installed (Debian: cppcheck)")
@pytest.mark.parametrize("kind", KINDS)
def test_headers_break_only_the_documented_misra_rules(kind, tmp_path):
    found = {}
    for path in SHIPPED:
        for rule in misra_rules(*header_for(load(path), kind), tmp_path):
            found.setdefault(rule, path.name)
    assert set(found) == BROKEN[kind], {
        "not documented": {r: found[r] for r in set(found) - BROKEN[kind]},
        "no longer broken": sorted(BROKEN[kind] - set(found))}
