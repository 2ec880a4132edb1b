# floebreak — the set-up contract: `make demo` and `make test` work on a fresh machine with Python 3.11.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.floebreak-installed

.PHONY: demo test lint bench test-slow validate clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	$(BIN)/python -c "from floebreak.mechanics import compile_kernels; compile_kernels()"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/floebreak demo --out demo-output --overwrite

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks scripts validation

# one BLAS/OpenMP thread per process: the physics is not BLAS-bound, and extra threads only oversubscribe the cores
# (pytest-xdist workers, benchmarks measured on one core)
test: $(STAMP) lint
	OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q

test-slow: $(STAMP)
	OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q -m slow

validate: $(STAMP)
	OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q -m validation

bench: $(STAMP)
	@for script in $(filter-out benchmarks/compare.py,$(wildcard benchmarks/*.py)); do echo "== $$script"; OMP_NUM_THREADS=1 $(BIN)/python $$script || exit 1; done

clean:
	rm -rf $(VENV) demo-output .pytest_cache
