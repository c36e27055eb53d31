# Two entry points: `make demo` and `make test`. Each creates .venv when missing.
PYTHON ?= python3.11
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench clean

$(BIN)/python:
	@command -v $(PYTHON) >/dev/null 2>&1 || { echo "need $(PYTHON) on PATH (or run: make PYTHON=python3 ...)"; exit 1; }
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --upgrade pip >/dev/null

$(VENV)/.installed-demo: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -e . 
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -e ".[test]"
	touch $@

demo: $(VENV)/.installed-demo
	$(BIN)/frictionkit demo --out out/demo

# The report's browser test (tests/cli/test_report.py) opens the page in Debian's chromium.
# Installed once when missing; if the system cannot install it, that one test is skipped (said so).
$(VENV)/.installed-browser: | $(BIN)/python
	@command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || { \
	  echo "make test: installing Debian's chromium (browser test of the HTML report)"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  { $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq chromium >/dev/null; } \
	    || echo "make test: WARNING: could not install chromium; the browser test will be skipped"; }
	touch $@

test: $(VENV)/.installed-test $(VENV)/.installed-browser
	$(BIN)/python -m pytest -n 2 --dist loadgroup -q

# numbalsoda (the compiled-LSODA peers of benchmarks/peers.py) builds LSODA from Fortran
# source: on Debian/Ubuntu it needs `apt-get install gfortran` first. Only `make bench` needs it.
$(VENV)/.installed-bench: pyproject.toml | $(BIN)/python
	@command -v gfortran >/dev/null 2>&1 || { \
	  echo "make bench: installing Debian's gfortran (numbalsoda builds LSODA from Fortran)"; \
	  if [ "$$(id -u)" = 0 ]; then apt-get install -y gfortran; else sudo apt-get install -y gfortran; fi; }
	$(BIN)/python -m pip install -e ".[bench]"
	touch $@

bench: $(VENV)/.installed-bench
	$(BIN)/python benchmarks/simulate.py
	$(BIN)/python benchmarks/peers.py
	$(BIN)/python benchmarks/machines.py --quick

clean:
	rm -rf $(VENV) out .pytest_cache
