# floebreak — the set-up contract: `make demo` and `make test` work on a fresh machine with Python 3.11.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.floebreak-installed

.PHONY: demo test lint bench test-slow validate clean bytecode fuzz test-browser

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[dev,cluster]"
	$(MAKE) --no-print-directory bytecode
	$(BIN)/python -c "from floebreak.mechanics import compile_kernels; compile_kernels()"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/floebreak demo --out demo-output --overwrite

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks scripts tools validation

# one BLAS/OpenMP thread per process: the physics is not BLAS-bound, and extra threads only oversubscribe the cores
# (pytest-xdist workers, one per core; benchmarks measured on one core)
test: $(STAMP) lint
	OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q -n auto

test-slow: $(STAMP)
	OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q -m slow

# report.html of a demo run (PC5, operating profile, shaft line) in headless Chromium: every section laid out,
# every figure decoded; screenshots (whole page and one per section) kept in build/screenshots/
test-browser: $(STAMP)
	command -v chromium >/dev/null || apt-get install -y chromium
	FLOEBREAK_SCREENSHOTS=build/screenshots OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q -m browser tests/test_browser.py

# the scientific checks, among them the must-hold rows of `floebreak validate thesis` (both profiles, the choice
# sample and the holdout; docs/validation.md)
validate: $(STAMP)
	OMP_NUM_THREADS=1 $(BIN)/python -m pytest -q -m validation

# An editable install leaves src/ uncompiled, and where PYTHONDONTWRITEBYTECODE is set Python then compiles
# every floebreak module at each start (≈ 0.15 s per `floebreak` run). `pip install .` compiles at install;
# this does the same for src/ (only files changed since the last call are recompiled).
bytecode:
	$(BIN)/python -m compileall -q src

bench: $(STAMP) bytecode
	@for script in $(filter-out benchmarks/compare.py,$(wildcard benchmarks/*.py)); do echo "== $$script"; OMP_NUM_THREADS=1 $(BIN)/python $$script || exit 1; done

# fuzz campaigns (tools/fuzz): N random valid scenarios from SEED, then N adversarial ones (hostile field
# files, huge and far floes, bow CSVs and policies), checked for internal errors, area balance, valid
# polygons, peak memory and wall time; then N hostile texts per reader (deep TOML, extreme FEM tables, tiny
# and huge torque files), each read or refused by name; violations saved in fuzz-report/*/
N ?= 200
SEED ?= 1
JOBS ?= 1
fuzz: $(STAMP)
	OMP_NUM_THREADS=1 PYTHONPATH=tools $(BIN)/python -m fuzz --n $(N) --seed $(SEED) --jobs $(JOBS) --generator valid --out fuzz-report/valid
	OMP_NUM_THREADS=1 PYTHONPATH=tools $(BIN)/python -m fuzz --n $(N) --seed $(SEED) --jobs $(JOBS) --generator adversarial --out fuzz-report/adversarial
	OMP_NUM_THREADS=1 PYTHONPATH=tools $(BIN)/python -m fuzz.readers --n $(N) --seed $(SEED) --out fuzz-report/readers

clean:
	rm -rf $(VENV) demo-output .pytest_cache
