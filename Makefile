# `make demo` and `make test` each create the virtual environment when it is missing.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.sealeak-installed
EXTRAS ?= test,formats

.PHONY: demo test install bench bench-peers clean

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

test: $(STAMP)
	$(PY) -m pytest -q

bench: $(STAMP)
	@for f in benchmarks/bench_*.py; do echo "== $$f"; $(PY) $$f || exit 1; done

# the contact benchmark against tamaas and ContactMechanics (the optional `bench` extra)
bench-peers: $(STAMP)
	$(PY) -m pip install --quiet -e '.[$(EXTRAS),bench]'
	$(PY) benchmarks/bench_peers.py 256 512 1024

clean:
	rm -rf $(VENV) out build src/*.egg-info .pytest_cache
