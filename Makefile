# worldpaint: set up, build, test, demo, benchmark and package.
# Every target installs what it needs into .venv (Python 3.11, bpy 4.5 LTS from PyPI).

PYTHON_BASE ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
PY := $(VENV)/bin/python
BPY_VERSION := 4.5.*
VERSION := $(shell sed -n 's/^version = "\(.*\)"/\1/p' addon/worldpaint/blender_manifest.toml)

.PHONY: venv engine test test-rust test-blender lint demo bench extension clean

$(VENV)/.installed:
	$(PYTHON_BASE) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet "bpy==$(BPY_VERSION)" "maturin>=1.5,<2" pytest ruff
	touch $@

venv: $(VENV)/.installed

# Builds the engine wheel and installs it into the venv (the add-on imports it as worldpaint_engine).
engine: venv
	rm -rf build/wheels
	$(VENV)/bin/maturin build --release --quiet --interpreter $(PY) --out build/wheels
	$(PY) -m pip install --quiet --force-reinstall --no-deps build/wheels/worldpaint_engine-*.whl

lint: venv
	cargo fmt --all -- --check
	cargo clippy --workspace --all-targets --release -- -D warnings
	$(VENV)/bin/ruff check addon blender_tests assets

test-rust:
	cargo test -p worldpaint-core --release

test-blender: engine
	$(PY) -m pytest -q blender_tests

test: lint test-rust test-blender

demo: engine
	$(PY) assets/demo.py --out out

bench: engine
	cargo bench -p worldpaint-core --bench synthesis
	cargo bench -p worldpaint-core --bench tools
	cargo bench -p worldpaint-core --bench structures
	cargo bench -p worldpaint-core --bench village
	cargo bench -p worldpaint-core --bench terrain_edit
	cargo bench -p worldpaint-core --bench waterfall
	$(PY) blender_tests/bench_blender.py

# An installable Blender extension with the engine wheel inside; needs no Blender binary.
extension: venv
	rm -rf build/extension build/wheels && mkdir -p build/extension/wheels dist
	$(VENV)/bin/maturin build --release --quiet --interpreter $(PY) --out build/wheels
	cp -r addon/worldpaint/. build/extension/
	find build/extension -name __pycache__ -prune -exec rm -rf {} +
	cp build/wheels/worldpaint_engine-*.whl build/extension/wheels/
	$(PY) assets/write_manifest_wheels.py build/extension
	cd build/extension && $(abspath $(PY)) -c "import shutil; shutil.make_archive('../../dist/worldpaint-$(VERSION)-linux-x64', 'zip', '.')"
	@echo "dist/worldpaint-$(VERSION)-linux-x64.zip"

clean:
	rm -rf build dist out target $(VENV)
