"""The collected error messages as kinds, and the rules each kind is held to (issue 30: "right
line, what is wrong, what to write instead"); tests/message_log.py collects, this module judges.

A kind is a message with the test's concrete parts replaced: a name or text in backticks by
`X`, a quoted text by "S", a number by N, a path by PATH, a run of alternatives (`a` or `b`,
`a`, `b`) by one `X`, a list after `known:` by `...`.  The reviewed list
(tests/error_messages_reviewed.txt) has one line per kind:

    loc what fix | unknown term shape `X`: did you mean `X`?

with the rules the kind meets, each checked on every message of the kind the run collected:

    loc   the message is about a place in a file and carries file:line:col (col within the
          shown line), so the caret is under the mistake;
    what  it says what is wrong: a sentence of at least three words, no Python repr, no
          traceback - every kind must meet it, marked or not;
    fix   it says what to write instead: `write ...`, `did you mean ...`, `declare ...`,
          `known: ...`, `expected ...`, `use ...`, `give ...` and the like (HINT below).

A kind without `loc` is about no place in a file (a command-line option, a file that cannot
be read, a call of the Python API); one without `fix` has no single thing to write instead
(the reviewer's judgement, recorded by leaving the mark out).  A kind may end with ` ...` to
accept any tail: the text of an operating-system or library error that fuzzyc passes on,
whose wording belongs to the installed version, not to fuzzyc.

    python tests/message_review.py COLLECTED.json            # the kinds and what they meet
    python tests/message_review.py COLLECTED.json --update   # add new kinds to the list
"""
from __future__ import annotations

import json
import re
import sys
from collections import defaultdict
from pathlib import Path

RULES = ("loc", "what", "fix")
HINT = re.compile(
    r"did you mean|written in backticks|known: |\bexpected\b|\bmust\b|\bneeds?\b|\bone of\b"
    r"|\binstead\b|\bpip install\b|\bis only allowed\b|\bonly\b.*\ballowed\b|\bwrite `|\btakes\b"
    # an imperative after a separator: `; write the lower bound first`, `: use a let`
    r"|(?:[;:,(—-] |\bthen )(?:write|declare|give|use|add|remove|save|name|pass|set|install|"
    r"choose|try|put|rename|drop|split|move|lower|raise|widen|narrow|make|call|run|keep|"
    r"start|end|close|quote|leave|replace|see|check|list|define|shorten)\b", re.IGNORECASE)
NOT_A_SENTENCE = re.compile(r"object at 0x|Traceback|^\W*$|\bNone\b$")

_BACKTICKED = re.compile(r"`[^`\n]*`")
_DOUBLE = re.compile(r'"[^"\n]*"')
_SINGLE = re.compile(r"(?<![A-Za-z])'[^'\n]*'")
_PATH = re.compile(r"(?<![\w`])(?:[\w.~-]*/[\w./~-]*|[\w-]+\.(?:fz|fis|fcl|fll|json|yaml|yml|csv|"
                   r"c|h|py|txt|xml|npz|jfl|toml|ipynb|md))(?![\w`])")
_NUMBER = re.compile(r"(?<![\w`])(?<!UTF-)[-+]?(?:\d+\.?\d*(?:e[-+]?\d+)?|\.\d+|inf|nan|infinity)(?![\w`])",
                     re.IGNORECASE)
_ALTERNATIVES = re.compile(r"`X`(?:(?:, | or | and |, or |, and | )`X`)+")
_KNOWN = re.compile(r"(known|choose from|one of|are|is one of):( [^;()\n]+)")
_HEX = re.compile(r"0x[0-9a-fA-F]+")
_FILE_OP = re.compile(r"^(.*?\bcannot (?:read|write to|open|create|load|find) )(?!standard )(.+?)(: |$)")
_NAMES = re.compile(r"\((?!s\)|N\))\w+(?:, \w+)*\)|\(known terms are [^)]*\)")
_UNITS = re.compile(r"(unit mismatch: cannot \w+) .+ and .+$")
_DECLARED_UNIT = re.compile(r"\bin \S+ but its expression is in \S+")
_PLURAL = re.compile(r"\b(N (?:cell|row|column|number|argument|error|term|input|output|rule|"
                     r"value|point|line|item|step|byte|character|block|file|test|name))s?\b(?!\()")


def kind_of(message: str) -> str:
    """The message with its concrete parts replaced (see the module's docstring)."""
    text = "".join(c if c.isprintable() or c in "\t\n" else f"U+{ord(c):04X}"
                   for c in message.strip())       # a NUL of a hostile name stays visible
    text = _FILE_OP.sub(lambda m: f"{m.group(1)}PATH{m.group(3)}", text)
    text = _UNITS.sub(lambda m: f"{m.group(1)} U and U", text)
    text = _DECLARED_UNIT.sub("in U but its expression is in U", text)
    text = _BACKTICKED.sub("`X`", text)
    text = _DOUBLE.sub('"S"', text)
    text = _SINGLE.sub("'S'", text)
    text = _HEX.sub("0xN", text)
    text = _PATH.sub("PATH", text)
    text = _NUMBER.sub("N", text)
    text = _ALTERNATIVES.sub("`X`", text)
    text = _NAMES.sub(lambda m: "(known terms are ...)" if m.group(0).startswith("(known")
                      else "(...)", text)
    text = _KNOWN.sub(lambda m: f"{m.group(1)}: ...", text)
    text = re.sub(r"(?:N(?:, | |-|\.\.))+N\b", "N", text)       # lists and ranges of numbers
    text = _PLURAL.sub(r"\1(s)", text)
    text = re.sub(r"\s+", " ", text)
    return text


def merge(records: list[dict]) -> dict[str, dict]:
    """kind -> {"tests": ids, "sources", "types", "located": [bool per record], "messages"}."""
    kinds: dict[str, dict] = defaultdict(lambda: {"tests": set(), "sources": set(),
                                                  "types": set(), "records": []})
    for record in records:
        entry = kinds[kind_of(record["message"])]
        entry.setdefault("drawn", set()).update(record.get("drawn", ()))
        entry["tests"].update(record["tests"])
        entry["sources"].add(record["source"])
        entry["types"].add(record["type"])
        entry["records"].append(record)
    return dict(sorted(kinds.items()))


def located(record: dict) -> bool:
    loc = record["loc"]
    return bool(loc and loc[0] and loc[1] is not None and loc[2] is not None and loc[2] >= 1
                and loc[3])


def rules_met(kind: str, entry: dict) -> set[str]:
    """The rules every collected message of the kind meets."""
    met = set()
    records = entry["records"]
    if all(located(r) for r in records):
        met.add("loc")
    if all(len(r["message"].split()) >= 3 and not NOT_A_SENTENCE.search(r["message"])
           for r in records):
        met.add("what")
    if HINT.search(kind) and all(HINT.search(kind_of(r["message"])) for r in records):
        met.add("fix")
    return met


def render(kinds: dict[str, dict]) -> str:
    lines = [f"# {len(kinds)} kind(s) of error message; per kind: the number of tests that gave",
             "# it (at most 50 counted per exact message), its sources, the rules it meets",
             "# (tests/message_review.py), one test and one message as given", ""]
    for kind, entry in kinds.items():
        tests = sorted(entry["tests"])
        met = rules_met(kind, entry)
        marks = " ".join(r if r in met else "-" * len(r) for r in RULES)
        example = next((t for t in tests if not t.startswith("<")), tests[0] if tests else "")
        lines.append(f"{marks} | {kind}")
        count = f"{len(tests)} test{'s' if len(tests) != 1 else ''}"
        lines.append(f"    {count}, {'+'.join(sorted(entry['sources']))} "
                     f"({'/'.join(sorted(entry['types']))}), e.g. {example}")
        lines.append(f"    e.g. {entry['records'][0]['message']}")
    return "\n".join(lines) + "\n"


def read_reviewed(path: Path) -> dict[str, set[str]]:
    """kind -> the rules marked for it."""
    reviewed = {}
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip() or line.startswith("#"):
            continue
        marks, sep, kind = line.partition(" | ")
        rules = set(marks.split()) - {"-", "--", "---", "----"}
        if not sep or not rules <= set(RULES):
            raise ValueError(f"{path.name}:{number}: expected `loc what fix | kind`, got {line!r}")
        reviewed[kind.strip()] = rules
    return reviewed


def matching(kind: str, reviewed: dict[str, set[str]]) -> str | None:
    if kind in reviewed:
        return kind
    for known in reviewed:
        if known.endswith(" ...") and kind.startswith(known[:-3]):
            return known
    return None


def check(kinds: dict[str, dict],
          reviewed_path: Path) -> tuple[list[str], list[str], list[str]]:
    """(problems, reviewed kinds not collected, listed): a kind not reviewed, a kind that breaks
    a rule its line marks, a kind that does not say what is wrong. A kind not reviewed that
    only tests with drawn inputs produced (their texts follow the draws) is listed, not a
    problem, if it says what is wrong."""
    reviewed = read_reviewed(reviewed_path)
    problems, used, listed = [], set(), []
    for kind, entry in kinds.items():
        example = next(iter(sorted(entry["tests"])), "")
        known = matching(kind, reviewed)
        met = rules_met(kind, entry)
        if known is None and entry["tests"] <= entry.get("drawn", set()) and "what" in met:
            listed.append(f"DRAWN, NOT REVIEWED: {kind}\n    (from {example}, whose input "
                          f"is drawn at random: listed, not gated)")
            continue
        if known is None:
            problems.append(f"NOT REVIEWED: {kind}\n    (from {example}; add it to "
                            f"{reviewed_path.name} with the rules it meets, after reading it)")
            continue
        used.add(known)
        missing = (reviewed[known] | {"what"}) - met
        for rule in sorted(missing, key=RULES.index):
            bad = next((r for r in entry["records"]
                        if rule not in rules_met(kind, {"records": [r]})), entry["records"][0])
            problems.append(f"BREAKS `{rule}`: {kind}\n    e.g. {bad['message']!r} "
                            f"(loc {bad['loc']}) from {sorted(bad['tests'])[:1]}")
    unused = sorted(set(reviewed) - used)
    return problems, unused, listed


def update(kinds: dict[str, dict], reviewed_path: Path) -> int:
    """Append the kinds the list lacks, marked with the rules they meet now; returns how many."""
    reviewed = read_reviewed(reviewed_path) if reviewed_path.exists() else {}
    new = [f"{' '.join(r for r in RULES if r in rules_met(k, e)) or '-'} | {k}"
           for k, e in kinds.items() if matching(k, reviewed) is None]
    if new:
        text = reviewed_path.read_text() if reviewed_path.exists() else ""
        reviewed_path.write_text(text + "\n".join(new) + "\n")
    return len(new)


if __name__ == "__main__":
    records = json.loads(Path(sys.argv[1]).read_text())
    kinds = merge(records)
    reviewed_file = Path(__file__).with_name("error_messages_reviewed.txt")
    if "--update" in sys.argv:
        print(f"{update(kinds, reviewed_file)} kinds added to {reviewed_file}")
    else:
        print(render(kinds))
        if reviewed_file.exists():
            problems, unused, _ = check(kinds, reviewed_file)
            print("\n".join(problems))
            print(f"{len(problems)} problems, {len(unused)} reviewed kinds not collected")
