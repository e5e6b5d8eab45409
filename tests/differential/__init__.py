"""The differential fuzzer: random rule bases in each tool's own format, evaluated by fuzzyc
(under the tool's `--semantics`) and by the tool itself, compared output by output.

`cd tests && python -m differential --per-tool 200 --seed 0` (issue 28).  Modules:
- spec: the tool-neutral random rule base (`System`) and its seeded generator, per tool the
  shapes, norms, hedges and defuzzifiers the tool has;
- render: a System as FLL (fuzzylite 6, pyfuzzylite 8), fuzzylite's FCL, or an Octave .fis;
- tools: the tools run live, many files per process (Octave starts slowly);
- compare: fuzzyc's numbers against the tool's, and the file's class (refused, crashed, ...);
- shrink: a disagreement or crash made small while it persists;
- cases: the kept cases under cases/ (replayed by tests/test_differential_cases.py).
- roundtrip: each imported file through `.fz` and back, the same numbers under every
  semantics (tests/test_fz_round_trip_random.py; the campaign's `.fz round trip` column).
"""
