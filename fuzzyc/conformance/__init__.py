"""Conformance with the tools users come from: every example file of fuzzylite 6 (FLL, FCL, FIS),
pyfuzzylite 8 and the Octave fuzzy-logic-toolkit, imported by fuzzyc and compared with the
numbers of the tool itself (run live where it is installed, else the reference data it ships).

`python -m fuzzyc.conformance` prints the table (`make conformance`); `suites` says where the
files are, `oracles` runs the tools, `check` compares one file.
"""
