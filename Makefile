# pfeie: every target creates .venv on first use.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
export OMP_NUM_THREADS ?= 1
export OPENBLAS_NUM_THREADS ?= 1
export MKL_NUM_THREADS ?= 1
# the test files spread over the cores (one thread each), a file's tests on one worker so
# that its module fixtures are built once; XDIST= runs them in this process
XDIST  ?= -n auto --maxprocesses 4 --dist loadfile

.PHONY: demo test test-slow verify lint bench bench-quick clean

$(STAMP): pyproject.toml
	@$(PYTHON) -m venv $(VENV) 2>/dev/null || { \
	  echo "python3 -m venv failed; installing Debian's python3-venv"; \
	  apt-get update -qq && apt-get install -y -qq python3-venv && $(PYTHON) -m venv $(VENV); }
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e ".[fast,io,plot,study,dev]"
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/pfeie run examples/koyna/koyna.toml
	$(VENV)/bin/pfeie plot examples/koyna/results/results.h5
	$(VENV)/bin/pfeie report examples/koyna/results/results.h5

test: $(STAMP)
	$(PY) -m pytest $(XDIST) -m "not slow" --doctest-modules src tests examples

test-slow: $(STAMP)
	$(PY) -m pytest $(XDIST) -m slow tests

verify: $(STAMP)
	$(VENV)/bin/pfeie verify --manual docs/verification

lint: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check src
	$(VENV)/bin/mypy

bench: $(STAMP)
	$(PY) benchmarks/run.py
	$(PY) benchmarks/interfaces.py
	$(PY) benchmarks/study.py
	@$(PY) -c "import openseespy.opensees" 2>/dev/null || { \
	  $(PY) -m pip install -q -e ".[bench]"; \
	  [ -e /usr/lib/x86_64-linux-gnu/libblas.so.3 ] || { apt-get update -qq && \
	    apt-get install -y -qq libblas3 liblapack3; }; }
	$(PY) benchmarks/opensees.py

bench-quick: $(STAMP)
	$(PY) benchmarks/run.py --quick
	$(PY) benchmarks/interfaces.py --quick

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache build src/*.egg-info
