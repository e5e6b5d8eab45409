"""Failure classes found by the harness that other branches are fixing.

Each entry: (regex over the class signature, owner, what it is). The pytest sample skips these
classes and fails on any other; `make fuzz` counts them all and names the owner. Remove an
entry when its fix lands: the sample then guards against the class coming back.
"""
from __future__ import annotations

import re

KNOWN_OPEN: list[tuple[str, str, str]] = []


def known_owner(signature: str) -> str | None:
    for pattern, owner, _what in KNOWN_OPEN:
        if re.search(pattern, signature):
            return owner
    return None
