# `make run` and `make test` each set everything up (idempotent) and then run.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: run test experiment bench clean chromium

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/hri-lab serve

# the browser test drives Debian's chromium (playwright cannot download browsers here)
chromium:
	@command -v chromium >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; }

test: $(STAMP) chromium
	$(BIN)/python -m pytest -q

experiment: $(STAMP)
	$(BIN)/hri-lab experiment

bench: $(STAMP) chromium
	@command -v wrk >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq wrk >/dev/null; }
	$(BIN)/python -m bench.sim_speed
	$(BIN)/python -m bench.startup
	$(BIN)/python -m bench.service_latency
	$(BIN)/python -m bench.loop_latency
	$(BIN)/python -m bench.view_cost
	$(BIN)/python -m bench.rosbridge
	$(BIN)/python -m bench.recording

clean:
	rm -rf $(VENV) *.egg-info
