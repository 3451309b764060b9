# `make demo` and `make test` each create the virtual environment when it is missing.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.sealeak-installed
EXTRAS ?= test,formats,dev,docs,web

.PHONY: demo test lint docs docs-check install bench bench-peers clean browser

$(STAMP): pyproject.toml
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[$(EXTRAS)]'
	@touch $(STAMP)

install: $(STAMP)

demo: $(STAMP)
	@mkdir -p out
	$(VENV)/bin/sealeak predict --example reference-experiment \
		--table out/table.txt --json out/results.json --csv out/results.csv --plots out --force

# everything CI checks: lint, the layer contracts, types, the documentation site, the test suite
# (the web app's browser tests included: they fail, not skip, when Chromium is missing); pytest runs one worker
# per core (pytest-xdist, at most 4), each test file on one worker (its module fixtures computed once)
test: lint docs-check browser
	SEALEAK_REQUIRE_BROWSER=1 $(PY) -m pytest -q -n auto --maxprocesses 4 --dist loadfile

# headless Chromium for the browser tests: Debian's package (Playwright drives it; it downloads no browser)
browser:
	@command -v chromium >/dev/null || { apt-get update && apt-get install -y --no-install-recommends chromium; }

lint: $(STAMP)
	$(VENV)/bin/ruff check src tests benchmarks tools
	$(VENV)/bin/lint-imports
	$(VENV)/bin/mypy

# the site in strict mode (a broken link, a missing page or a docstring that does not parse fails)
docs-check: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --quiet --site-dir build/docs-check

docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --site-dir site
	@echo "open site/index.html"

bench: $(STAMP)
	@for f in benchmarks/bench_*.py; do echo "== $$f"; $(PY) $$f || exit 1; done

# the contact benchmark against tamaas and ContactMechanics (the optional `bench` extra)
bench-peers: $(STAMP)
	$(PY) -m pip install --quiet -e '.[$(EXTRAS),bench]'
	$(PY) benchmarks/bench_peers.py 256 512 1024

clean:
	rm -rf $(VENV) out build site src/*.egg-info .pytest_cache
