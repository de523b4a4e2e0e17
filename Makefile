# Two commands on a fresh clone: `make demo` and `make test`.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: demo test test-all regress lint bench figures install clean

$(BIN)/uma: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[dev,webrtc]'
	# numba's kernels compiled into their cache once, not in each process's first call; the
	# package's bytecode written once, as a non-editable install would (see `test`).
	$(BIN)/python -m uma.bench.warm
	env -u PYTHONDONTWRITEBYTECODE $(BIN)/python -m compileall -q uma
	touch $@

install: $(BIN)/uma

demo: install
	$(BIN)/uma run

# The fast suite (at most two minutes); the 15 slowest tests are listed at the end. It runs on
# TEST_WORKERS processes (pytest-xdist; `auto`: one per core), each test file on one of them so
# a module's fixtures are computed once; `make test TEST_WORKERS=0` runs it in this process.
# Python's bytecode caches are written even where PYTHONDONTWRITEBYTECODE is set: otherwise every
# worker and every `uma` subprocess of the suite compiles each module (and pytest rewrites each
# test file's asserts) from source again.
TEST_WORKERS ?= auto
test: install
	env -u PYTHONDONTWRITEBYTECODE $(BIN)/python -m pytest -q -m "not slow" -n $(TEST_WORKERS) \
		--dist loadfile --durations=15

# The regression gate on the repository's baselines: eight short scenarios (about 35 s).
regress: install
	$(BIN)/uma regress tests/baselines/suite.yaml

test-all: install
	$(BIN)/python -m pytest -q --durations=15

lint: install
	$(BIN)/ruff check uma tests
	$(BIN)/ruff format --check uma tests

bench: install
	$(BIN)/uma bench sim
	$(BIN)/uma bench init
	$(BIN)/uma bench codec

# README.md's measured figures, regenerated from the bench records in docs/results/ (written by
# scripts/record_bench.py; docs/measured.md says which benches to record, in order).
figures: install
	$(BIN)/python scripts/readme_tables.py write

clean:
	rm -rf $(VENV) results
