"""The collection of error messages (tests/message_log.py) and their review
(tests/message_review.py, tests/error_messages_reviewed.txt): kinds, rules, the check."""
from __future__ import annotations

import pytest

from fuzzyc.errors import FuzzycError
from fuzzyc.language.parser import parse
from tests import message_log
from tests.message_review import RULES, check, kind_of, merge, read_reviewed, rules_met

REVIEWED = message_log.REVIEWED


def record(message, loc=(True, 3, 5, True), source="raise", tests=("t::a",)):
    return {"source": source, "type": "FuzzycError", "message": message,
            "loc": list(loc) if loc else None, "tests": list(tests)}


@pytest.mark.parametrize("message, kind", [
    ("unknown term shape `TRIAN`: did you mean `tri`?", "unknown term shape `X`: did you mean `X`?"),
    ("unknown term shape `Ramp`: did you mean `lshoulder` or `rshoulder`?",
     "unknown term shape `X`: did you mean `X`?"),
    ("the range of input `a` is empty: [10, 0]; write the lower bound first",
     "the range of input `X` is empty: [N]; write the lower bound first"),
    ("cannot read /tmp/x y/a.fz: [Errno 2] No such file or directory: '/tmp/x y/a.fz'",
     "cannot read PATH: [Errno N] No such file or directory: 'S'"),
    ("unit mismatch: cannot subtract kHz and Hz", "unit mismatch: cannot subtract U and U"),
    ("this table row has 1 cell; the table declares 3 columns",
     "this table row has N cell(s); the table declares N column(s)"),
    ("byte 0xff is not UTF-8: save the file as UTF-8",
     "byte 0xN is not UTF-8: save the file as UTF-8"),
])
def test_a_kind_replaces_the_concrete_parts(message, kind):
    assert kind_of(message) == kind


def test_the_rules_are_checked_on_every_message_of_a_kind():
    kinds = merge([record("unknown term shape `TRIAN`: did you mean `tri`?"),
                   record("unknown term shape `Ramp`: did you mean `ramp`?", loc=None)])
    (kind, entry), = kinds.items()
    assert rules_met(kind, entry) == {"what", "fix"}       # one of the two has no place
    assert rules_met("oops", {"records": [record("oops")]}) == {"loc"}   # says nothing


def test_a_new_kind_or_a_broken_rule_is_a_problem(tmp_path):
    reviewed = tmp_path / "reviewed.txt"
    reviewed.write_text("# comment\nloc what fix | unknown term shape `X`: did you mean `X`?\n"
                        "what | cannot read PATH: ...\n")
    kinds = merge([record("unknown term shape `TRIAN`: did you mean `tri`?", loc=None),
                   record("cannot read a.fz: [Errno 13] Permission denied", loc=None),
                   record("something new went wrong here")])
    problems, unused, _ = check(kinds, reviewed)
    assert unused == []
    assert sorted(p.split(":")[0] for p in problems) == ["BREAKS `loc`", "NOT REVIEWED"], problems


def test_a_new_kind_only_drawn_inputs_gave_is_listed_not_gated(tmp_path):
    reviewed = tmp_path / "reviewed.txt"
    reviewed.write_text("loc what | unknown section X\n")
    drawn = {**record("unexpected character U+8600D", tests=("t::fuzz",)), "drawn": ["t::fuzz"]}
    kinds = merge([drawn, record("unexpected character U+8600D", tests=("t::fixed",))])
    problems, _, listed = check(kinds, reviewed)        # a fixed test gave it too: the gate
    assert [p.split(":")[0] for p in problems] == ["NOT REVIEWED"] and listed == []
    problems, _, listed = check(merge([drawn]), reviewed)
    assert problems == [] and listed[0].startswith("DRAWN, NOT REVIEWED: unexpected character")
    mute = {**record("oops", tests=("t::fuzz",)), "drawn": ["t::fuzz"]}
    problems, _, listed = check(merge([mute]), reviewed)  # says nothing: a problem all the same
    assert [p.split(":")[0] for p in problems] == ["NOT REVIEWED"] and listed == []


def test_the_reviewed_list_reads_and_each_kind_is_listed_once():
    lines = [line for line in REVIEWED.read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    reviewed = read_reviewed(REVIEWED)
    assert len(reviewed) == len(lines), "a kind is listed twice"
    assert all("what" in rules and rules <= set(RULES) for rules in reviewed.values())


def test_the_log_records_fuzzycs_own_errors_and_not_a_tests():
    before = dict(message_log._seen)
    with pytest.raises(FuzzycError):
        parse("controller c {\n  input log_probe in [10, 0]\n}\n", "c.fz")
    FuzzycError([])                                    # made here, not by fuzzyc: not logged
    new = {k: v for k, v in message_log._seen.items() if k not in before}
    assert any(source == "raise" and loc and loc[1] == 2 for source, _, _, loc in new), new
