# `make run` and `make test` each set everything up (idempotent) and then run.
# The interpreter the venv is made from: the system's own python3 (Debian's and Ubuntu's are built
# with profile-guided optimization and link-time optimization) when it is 3.11 or newer and can make
# a venv, else python3 on PATH (pyenv builds without them by default; what it costs:
# docs/getting-started.md#the-interpreter); `make PYTHON=/path/to/python3` picks another. The venv is
# made again when it was made from another.
SYSTEM_PYTHON := /usr/bin/python3
ifeq ($(origin PYTHON),undefined)
PYTHON := $(shell $(SYSTEM_PYTHON) -c 'import sys, venv, ensurepip; sys.exit(sys.version_info < (3, 11))' 2>/dev/null && echo $(SYSTEM_PYTHON) || echo python3)
endif
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
PYTHON_HOME := $(shell $(PYTHON) -c 'import os, sys; print(os.path.dirname(sys._base_executable))' 2>/dev/null)
VENV_MADE_FROM := $(shell sed -n 's/^home = //p' $(VENV)/pyvenv.cfg 2>/dev/null)
# pyproject's extras the venv gets (the container image: hub,nodes)
EXTRAS ?= test
# Debian's packages beside the venv (scripts/system-deps.sh): apt-get runs only when one is missing
# and we are root; otherwise the script prints the `sudo apt-get install ...` line and stops.
DEPS   := scripts/system-deps.sh

.PHONY: run test test-fast experiment bench clean chromium bubblewrap egl openmp ros1 docs lint system-deps setup image-test

# uv installs the venv (pyproject's pins as they are): 67 s against pip's 430 s on a busy 2-core machine;
# byte-compiled at install, as pip does: where PYTHONDONTWRITEBYTECODE is set (container images set it)
# no process writes a .pyc, and each would compile every module it imports (a lab's start: 2.3 s of CPU, 1.1 s with them)
UV_VERSION := $(shell sed -n 's/^UV = "uv==\(.*\)".*/\1/p' app/cli/autograder.py)  # one pin: the Gradescope bundle's (app/cli/autograder.py)
UV := $(BIN)/uv pip install --quiet --compile-bytecode --python $(BIN)/python
$(STAMP): pyproject.toml
	$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || { echo "hri-lab needs Python >= 3.11: $(PYTHON) is $$($(PYTHON) --version 2>&1)"; exit 1; }
	test -x $(BIN)/python && test "$(VENV_MADE_FROM)" = "$(PYTHON_HOME)" || $(PYTHON) -m venv --clear $(VENV)
	$(BIN)/python -m pip install --quiet uv==$(UV_VERSION)
	$(UV) -e '.[$(EXTRAS)]'
	touch $(STAMP)
ifneq ($(VENV_MADE_FROM),$(PYTHON_HOME))
.PHONY: $(STAMP)  # made from another interpreter: made again
endif

# JupyterHub's proxy (npm's configurable-http-proxy), beside the venv, for the hub test (tests/e2e/test_jupyterhub.py)
CHP := $(VENV)/chp/node_modules/.bin/configurable-http-proxy
$(CHP):
	npm install --silent --no-audit --no-fund --prefix $(VENV)/chp configurable-http-proxy@5.3.0

# the documentation site's and the linters' tools (pyproject's docs and lint groups), for make docs / make lint
DEV := $(VENV)/.dev
$(DEV): $(STAMP)
	$(UV) -e '.[test,docs,lint]'
	touch $@

# numba's kernels compiled at set-up (cached beside their sources), not by every first process of a run;
# again whenever a file of sim/ changed (sim/kernel_cache.py then drops the caches built from the old sources)
KERNELS := $(shell find sim -name '*.py')
$(VENV)/.kernels: $(STAMP) $(KERNELS)
	$(BIN)/python -c "from sim.warm_up import warm_up; warm_up()"
	touch $@

# the project's own modules byte-compiled likewise (again whenever one changed; a stale .pyc is never used)
SOURCES := $(shell find app sim interfaces rosclient bench tests -name '*.py')
BYTECODE := $(VENV)/.bytecode
$(BYTECODE): $(STAMP) $(SOURCES)
	$(BIN)/python -m compileall -q -j 0 app sim interfaces rosclient bench tests
	touch $@

# and the test modules as pytest rewrites their asserts (its own .pyc, written by a collection: 13 s of
# CPU once, where each of make test's three workers took 13 s to collect without them, 6.5 s with); a
# module that cannot be collected is left to the run that follows, which says why
TEST_BYTECODE := $(VENV)/.test-bytecode
$(TEST_BYTECODE): $(BYTECODE)
	env -u PYTHONDONTWRITEBYTECODE $(BIN)/python -m pytest --collect-only -q -p no:cacheprovider > /dev/null || true
	touch $@

# without bubblewrap the lab starts anyway, unsandboxed (the script says what that loses)
run: egl openmp $(STAMP) $(BYTECODE) $(VENV)/.kernels
	@$(DEPS) --optional bubblewrap
	$(BIN)/hri-lab serve $(SERVE_ARGS)

# the browser tests drive Debian's chromium-headless-shell (playwright cannot download browsers here)
chromium:
	@$(DEPS) chromium

# the camera renders offscreen with OpenGL through EGL (Mesa's software renderer, llvmpipe, without a GPU)
egl:
	@$(DEPS) egl

# the OpenMP runtime that the compiled kernels' libraries load
openmp:
	@$(DEPS) openmp

# students' controllers run sandboxed in bubblewrap (hri-lab grade, serve/experiment --controller FILE)
bubblewrap:
	@$(DEPS) bubblewrap

# everything `make run` needs, and the venv with its kernels: the container image's set-up (Containerfile)
system-deps:
	@$(DEPS) python make egl openmp bubblewrap
setup: $(STAMP) $(BYTECODE) $(VENV)/.kernels

# opt-in, slow (minutes; root): the container image built from a Debian base made by mmdebstrap, and its
# lab's /health answered (scripts/image-test.sh); not part of make test
image-test:
	scripts/image-test.sh

# real ROS 1 (Debian's roscore and rospy): the tests that hold the lab's emulation to it (bench/ros1_oracle.py)
ros1:
	@$(DEPS) ros1

test: chromium bubblewrap egl openmp ros1 $(STAMP) $(TEST_BYTECODE) $(VENV)/.kernels $(CHP)
	$(BIN)/python -m pytest -q -n 3 --dist loadfile --no-loadscope-reorder

# the inner loop: no browser, no other programs (servers, nodes, sandboxed controllers); make test runs everything
test-fast: egl openmp $(STAMP) $(TEST_BYTECODE) $(VENV)/.kernels
	$(BIN)/python -m pytest -q -n 2 --dist loadfile -m "not e2e and not browser"

# the documentation site (mkdocs.yml) in site/; its reference pages are generated from the code (docs/hooks/)
docs: $(DEV) $(VENV)/.kernels
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

# what CI checks before the tests (.ci/run): ruff, mypy (its files: pyproject's [tool.mypy]), the site without a broken link.
lint: $(DEV) $(VENV)/.kernels
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	cd rosclient/site && $(CURDIR)/$(BIN)/mypy --config-file $(CURDIR)/pyproject.toml -p rospy -p actionlib -p cv_bridge -p genpy -p rostest -p sensor_msgs
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

experiment: $(STAMP) $(BYTECODE) $(VENV)/.kernels bubblewrap
	$(BIN)/hri-lab experiment

bench: $(STAMP) $(BYTECODE) $(VENV)/.kernels chromium bubblewrap egl
	@$(DEPS) wrk
	$(BIN)/python -m bench.sim_speed
	$(BIN)/python -m bench.startup
	$(BIN)/python -m bench.service_latency
	$(BIN)/python -m bench.loop_latency
	$(BIN)/python -m bench.view_cost
	$(BIN)/python -m bench.page_responsiveness
	$(BIN)/python -m bench.rosbridge
	$(BIN)/python -m bench.recording
	$(BIN)/python -m bench.grade_time
	$(BIN)/python -m bench.margin_sweep
	$(BIN)/python -m bench.camera

clean:
	rm -rf $(VENV) *.egg-info site
