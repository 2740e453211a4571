# worldpaint: set up, build, test, demo, benchmark and package.
# Every target installs what it needs into virtual environments, one per Blender the add-on is tested on:
#   .venv      bpy 4.5 LTS, Python 3.11 (also builds the engine, lints, runs the demo and the benchmarks)
#   .venv-5.2  bpy 5.2 LTS, Python 3.13
#   .venv-5.3  bpy 5.3, Python 3.13 (the newest 5.x; raise it when a newer one is released)

# A Python of that minor version: on PATH, else under pyenv (whose shims fail for versions that are not global).
comma := ,
find_python = $(shell for p in python$(1) $$(pyenv root 2>/dev/null)/versions/$(1).*/bin/python$(1) \
	$(HOME)/.pyenv/versions/$(1).*/bin/python$(1); do \
	"$$p" -c "import sys; sys.exit(sys.version_info[:2] != ($(subst .,$(comma),$(1))))" 2>/dev/null \
	&& { command -v "$$p"; break; }; done)
PYTHON311 ?= $(call find_python,3.11)
PYTHON313 ?= $(call find_python,3.13)
PYTHON311 := $(PYTHON311)
PYTHON313 := $(PYTHON313)

VENV := .venv
PY := $(VENV)/bin/python
BLENDERS := 4.5 5.2 5.3
venv_of = $(if $(filter 4.5,$(1)),$(VENV),$(VENV)-$(1))
python_of = $(if $(filter 4.5,$(1)),$(PYTHON311),$(PYTHON313))
# The engine wheel: abi3 (imports under Python 3.11 and 3.13) and linked against glibc 2.28 by zig, Blender's own
# Linux baseline, so it installs on every distribution Blender supports.
MANYLINUX := 2_28
WHEEL_DIR := build/wheels

.PHONY: venv venvs wheel engine test test-rust test-blender lint demo bench extension clean

# The 4.5 venv also builds the wheel (maturin, zig) and lints (ruff; mypy, which `lint` also adds to a venv made
# before it was listed here).
MYPY := "mypy>=1.15,<2"
BUILD_TOOLS := "maturin>=1.5,<2" ziglang ruff $(MYPY)

# One Blender's environment: bpy and pytest (the engine wheel is installed into it by test-blender).
define blender_venv
$(call venv_of,$(1))/.installed:
	@test -n "$(call python_of,$(1))" || { echo "No Python for bpy $(1): put it on PATH or under pyenv"; exit 1; }
	$(call python_of,$(1)) -m venv $(call venv_of,$(1))
	$(call venv_of,$(1))/bin/python -m pip install --quiet --upgrade pip
	$(call venv_of,$(1))/bin/python -m pip install --quiet "bpy==$(1).*" pytest pyyaml "dask[distributed]" $(if $(filter 4.5,$(1)),$(BUILD_TOOLS))
	touch $$@
endef
$(foreach b,$(BLENDERS),$(eval $(call blender_venv,$(b))))

venv: $(VENV)/.installed
venvs: $(foreach b,$(BLENDERS),$(call venv_of,$(b))/.installed)

# Builds the engine wheel (maturin finds zig in the venv, so the venv's bin comes first on PATH).
wheel: venv
	rm -rf $(WHEEL_DIR)
	PATH="$(abspath $(VENV))/bin:$$PATH" $(VENV)/bin/maturin build --release --quiet --zig \
		--compatibility manylinux_$(MANYLINUX) --interpreter $(PY) --out $(WHEEL_DIR)

# Installs the engine into the 4.5 venv (the add-on imports it as worldpaint_engine).
engine: wheel
	$(PY) -m pip install --quiet --force-reinstall --no-deps $(WHEEL_DIR)/worldpaint_engine-*.whl

lint: venv
	cargo fmt --all -- --check
	cargo clippy --workspace --all-targets --release -- -D warnings
	RUSTDOCFLAGS="-D rustdoc::broken_intra_doc_links -D rustdoc::private_intra_doc_links" \
		cargo doc --no-deps --quiet -p worldpaint-core -p worldpaint-py
	$(VENV)/bin/ruff check addon blender_tests assets rust/worldpaint-py/python
	@test -x $(VENV)/bin/mypy || $(PY) -m pip install --quiet $(MYPY)
	$(VENV)/bin/mypy

# The tests that measure against real data are ignored by default (they say why); they run here where the data is.
REAL_DATA := ../shared/data/real
test-rust:
	cargo test -p worldpaint-core --release
	@if [ -d $(REAL_DATA) ]; then \
		cargo test -p worldpaint-core --release --test real_forest_painting --test real_village_painting \
			--test real_village_generation --test real_village_learning -- --ignored \
		&& cargo test -p worldpaint-core --release --test village_parcels -- --ignored real_cadastre; \
	else echo "real-data tests skipped: $(REAL_DATA) is absent (listed as ignored above)"; fi

# The whole bpy suite on every Blender of the matrix; all of them run, then any failure fails the target.
test-blender: wheel venvs
	@status=0; for b in $(BLENDERS); do \
		case $$b in 4.5) v=$(VENV);; *) v=$(VENV)-$$b;; esac; \
		$$v/bin/python -m pip install --quiet --force-reinstall --no-deps $(WHEEL_DIR)/worldpaint_engine-*.whl; \
		echo "== bpy $$($$v/bin/python -c 'import bpy; print(bpy.app.version_string)' 2>/dev/null | tail -1)," \
			"Python $$($$v/bin/python -c 'import platform; print(platform.python_version())')"; \
		$$v/bin/python -m pytest -q -p no:cacheprovider blender_tests || status=1; \
	done; exit $$status

test: lint test-rust test-blender

demo: engine
	$(PY) assets/demo.py --out out

bench: engine
	cargo bench -p worldpaint-core --bench synthesis
	cargo bench -p worldpaint-core --bench scale
	cargo bench -p worldpaint-core --bench table2
	cargo bench -p worldpaint-core --bench tools
	cargo bench -p worldpaint-core --bench structures
	cargo bench -p worldpaint-core --bench village
	cargo bench -p worldpaint-core --bench terrain_edit
	cargo bench -p worldpaint-core --bench waterfall
	cargo bench -p worldpaint-core --bench variety
	cargo bench -p worldpaint-core --bench arrangement
	cargo bench -p worldpaint-core --bench sketch
	$(PY) blender_tests/bench_blender.py
	$(PY) blender_tests/bench_world.py

# An installable Blender extension with the engine wheel inside; needs no Blender binary.
extension: wheel
	$(PY) assets/package_extension.py --platform linux-x64 --wheels $(WHEEL_DIR) --out dist

clean:
	rm -rf build dist out target $(VENV) $(foreach b,$(BLENDERS),$(call venv_of,$(b)))
