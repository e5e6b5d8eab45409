# Two entry points for a fresh machine: `make demo` and `make test`.
# Both create .venv when it is missing and (re)install the package when pyproject.toml changes.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench proofs c-proofs loop-proofs fuzz explore clean conformance

$(STAMP): pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV) || { echo "python3 -m venv failed: on Debian install python3-venv (apt-get install python3-venv)"; exit 1; }
	$(PY) -m pip install -q --disable-pip-version-check --upgrade pip setuptools wheel
	$(PY) -m pip install -q --disable-pip-version-check -e '.[test,dask,gym]'
	@touch $(STAMP)

demo: $(STAMP)
	$(PY) -m fuzzyc.demo

test: $(STAMP)
	$(PY) -m pytest -q -n 2 --dist loadfile -rs

# What CI proves beyond `make test`: every header of the corpora under EVA, and every shipped
# closed loop on sets at a tenth of its horizon (box budget 8; a smoke run of the machinery).
proofs: c-proofs
	$(PY) benchmarks/bench_verify.py --proofs-only --quick

# Frama-C EVA over the corpora's headers (tests/test_c_proofs.py, marker `proofs`, left out of
# the default selection in pyproject.toml; the shipped rule bases' headers are proved in
# `make test`); skipped without frama-c.
c-proofs: $(STAMP)
	$(PY) -m pytest -q -n 2 --dist loadfile -m proofs -rs tests/test_c_proofs.py

# pyfuzzylite 8 pins numpy < 2: a venv of its own, for its example files and as a live oracle.
PYFL_VENV := .venv-pyfuzzylite
$(PYFL_VENV)/.installed:
	$(PYTHON) -m venv $(PYFL_VENV)
	$(PYFL_VENV)/bin/python -m pip install -q --disable-pip-version-check pyfuzzylite==8.0.6
	@touch $@

# The conformance table (every example file of fuzzylite 6, pyfuzzylite 8 and the Octave
# toolkit against the tools themselves), then the live oracle tests.
conformance: $(STAMP) $(PYFL_VENV)/.installed
	$(PY) -m fuzzyc.conformance
	$(PY) -m pytest -q -m conformance -rs

# 10,000 hostile inputs (docs/fuzzing.md); fails on any traceback or unlocated rejection
fuzz: $(STAMP)
	$(PY) -m tests.fuzz --inputs 10000

# The property tests (fixed examples in `make test`) with fresh random seeds, 10 rounds:
# a search for new counterexamples, not a gate (docs/fuzzing.md)
PROPERTY_TESTS = $(shell grep -l "@given" tests/test_*.py)
explore: $(STAMP)
	for round in 1 2 3 4 5 6 7 8 9 10; do \
	  FUZZYC_EXPLORE=1 $(PY) -m pytest -q -n 2 --dist loadfile \
	    $(PROPERTY_TESTS) || exit 1; done

bench: $(STAMP)
	$(PY) benchmarks/run_all.py

# the closed-loop proofs of every shipped rule base at full horizon beside the search
# (docs/proofs.md's table; tens of minutes on one core: the EDM loops dominate)
loop-proofs: $(STAMP)
	$(PY) benchmarks/bench_verify.py --proofs-only

clean:
	rm -rf $(VENV) $(PYFL_VENV) build *.egg-info out
