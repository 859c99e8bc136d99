# bemcontact: the README's commands.  Each target installs what it needs into
# a local virtual environment (.venv) first, so a fresh clone needs only
# CPython >= 3.11, a C++17 compiler and cmake.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
CPP_SRC := $(shell find cpp -name '*.cpp' -o -name '*.hpp' -o -name '*.hpp.in')
# The editable build here is tuned for this machine (-march=native); NATIVE=OFF
# builds the portable binary that wheels and plain `pip install .` get.
NATIVE ?= ON
BUILD_DEPS := scikit-build-core>=0.10 nanobind>=2.0
# what the demo needs (make demo installs only these) ...
RUN_DEPS := numpy scipy meshio threadpoolctl rich matplotlib
# ... and what the tests need besides: gmsh (generated meshes), Dask (sweeps), scikit-fem and
# cvxopt and pymetis (finite-element bodies), the docs'
# builder (the API reference is generated from the docstrings: make docs, tests/test_docs.py)
TEST_DEPS := gmsh pytest pytest-xdist hypothesis mkdocs dask distributed scikit-fem cvxopt pymetis
DOC_DEPS := "mkdocstrings[python]>=1.0"

.PHONY: all install demo test test-all test-wheel wheel bench docs clean FORCE

all: install

# Progress: a line per stage, then pip's own lines (a few per package) while it installs.
$(VENV)/.deps: pyproject.toml
	@echo "== [1/2] $(VENV): the Python dependencies from PyPI (about a minute the first time)"
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --progress-bar off "scikit-build-core>=0.10" "nanobind>=2.0" $(RUN_DEPS)
	touch $@

$(VENV)/.testdeps: $(VENV)/.deps Makefile
	@echo "== $(VENV): what the tests need besides (gmsh, pytest, Dask, the docs' builder)"
	$(PY) -m pip install --progress-bar off $(TEST_DEPS) $(DOC_DEPS)
	touch $@

# rewritten only when NATIVE changes, so that a change rebuilds
$(VENV)/.native: FORCE
	@mkdir -p $(VENV)
	@echo "$(NATIVE)" | cmp -s - $@ || echo "$(NATIVE)" > $@

$(VENV)/.built: $(VENV)/.deps $(VENV)/.native $(CPP_SRC) CMakeLists.txt pyproject.toml
	@echo "== [2/2] building the C++ core into $(VENV) (cmake; about a minute the first time)"
	$(PY) -m pip install --quiet --no-build-isolation --no-deps -e . \
		--config-settings=cmake.define.BEMCONTACT_NATIVE=$(NATIVE)
	@echo "== built: $$($(PY) -c 'import bemcontact; print("bemcontact", bemcontact.__version__)')"
	touch $@

install: $(VENV)/.built

demo: install
	$(PY) examples/compress_cube.py
	$(VENV)/bin/bemcontact run examples/two_cubes_similar.toml --out out/similar
	$(VENV)/bin/bemcontact run examples/two_cubes_dissimilar.toml --out out/dissimilar
	$(PY) examples/two_cubes_figure.py out/similar out/dissimilar out/two_cubes_figure1.png

# The default suite leaves out the cases marked slow (a minute or more each);
# test-all runs them too.  It runs in two worker processes (pytest-xdist, a
# module's tests in the same worker, so its fixtures are computed once) with
# single-threaded BLAS: much of the suite is Python or one-threaded work, and
# two BLAS threads per worker would only contend (measured on a 2-core AMD
# EPYC: 9.7 minutes, 18.7 serial).  A run ended by a signal (an abort prints
# no summary) names the test it was in: BEMCONTACT_TEST_TRACE=FILE has the
# test now starting written to FILE (tests/conftest.py); under pytest-xdist
# each worker writes its own, FILE suffixed with its PYTEST_XDIST_WORKER
# (.current-test.gw0, .current-test.gw1; trace.txt would be trace.gw0.txt),
# and FILE is the controller's (the test last started in any worker).
TRACE = $(VENV)/.current-test
PYTEST_RUN = BEMCONTACT_TEST_TRACE=$(TRACE) $(PY) -m pytest -q
PARALLEL = OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
SIGNALLED = { rc=$$?; if [ $$rc -gt 128 ]; then \
	echo "pytest ended by signal $$((rc - 128)) in $$(cat $(TRACE))"; \
	for f in $(TRACE).gw*; do [ -f "$$f" ] && echo "  worker $${f\#\#*.}: $$(cat "$$f")"; done; \
	fi; exit $$rc; }

test: install $(VENV)/.testdeps
	@rm -f $(TRACE) $(TRACE).gw*
	@$(PARALLEL) $(PYTEST_RUN) -n 2 --dist loadscope -m "not slow and not packaging" || $(SIGNALLED)

test-all: install $(VENV)/.testdeps
	@rm -f $(TRACE) $(TRACE).gw*
	@$(PYTEST_RUN) || $(SIGNALLED)

# the packaging test: the wheel built, installed into a fresh venv (dependencies
# from PyPI) and run there (minutes; not part of `make test`)
test-wheel: install $(VENV)/.testdeps
	$(PY) -m pytest -q -m packaging tests/test_packaging.py

# A portable wheel into dist/ (baseline instruction set, no -march=native; its own
# build directory, so the editable build here is not reconfigured):
# pip install dist/bemcontact-*.whl on any machine of the same platform.
wheel: $(VENV)/.deps
	$(PY) -m pip wheel --no-build-isolation --no-deps --wheel-dir dist . \
		--config-settings=cmake.define.BEMCONTACT_NATIVE=OFF \
		--config-settings=build-dir=build/wheel/{wheel_tag}

bench: install $(VENV)/.testdeps
	$(PY) benchmarks/bem_one_body_N500_5000.py
	$(PY) benchmarks/scaling.py

# The documentation site (MkDocs, built-in theme, nothing fetched at build or view
# time) goes into site/; open site/index.html.  Needs mkdocs and mkdocstrings (the API
# reference reads the sources without importing them), not the C++ build.
docs: $(VENV)/.deps
	$(PY) -c "import mkdocs, mkdocstrings" 2>/dev/null || $(PY) -m pip install --quiet mkdocs $(DOC_DEPS)
	$(VENV)/bin/mkdocs build --strict

clean:
	rm -rf build dist site $(VENV)
