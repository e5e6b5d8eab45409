"""The fuzzing harness: hostile and broken input must get a located message, never a traceback.

`python -m tests.fuzz --inputs 10000` (the `make fuzz` target) mutates every shipped and corpus
file of every format, the scenario YAML files, CSV input of `eval --csv` and whole command lines,
runs each through `fuzzyc.cli.main` and prints a summary; see docs/fuzzing.md.
"""
