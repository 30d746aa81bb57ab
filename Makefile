# `make run` and `make test` each set everything up (idempotent) and then run.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: run test test-fast experiment bench clean chromium bubblewrap egl ros1 docs lint

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

# JupyterHub's proxy (npm's configurable-http-proxy), beside the venv, for the hub test (tests/e2e/test_jupyterhub.py)
CHP := $(VENV)/chp/node_modules/.bin/configurable-http-proxy
$(CHP):
	npm install --silent --no-audit --no-fund --prefix $(VENV)/chp configurable-http-proxy@5.3.0

# the documentation site's and the linters' tools (pyproject's docs and lint groups), for make docs / make lint
DEV := $(VENV)/.dev
$(DEV): $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[test,docs,lint]'
	touch $@

# numba's kernels compiled at set-up (cached beside their sources), not by every first process of a run;
# again whenever a file of sim/ changed (sim/kernel_cache.py then drops the caches built from the old sources)
KERNELS := $(shell find sim -name '*.py')
$(VENV)/.kernels: $(STAMP) $(KERNELS)
	$(BIN)/python -c "from sim.warm_up import warm_up; warm_up()"
	touch $@

run: $(STAMP) $(VENV)/.kernels bubblewrap egl
	$(BIN)/hri-lab serve

# the browser test drives Debian's chromium (playwright cannot download browsers here)
chromium:
	@command -v chromium >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; }

# the camera renders offscreen with OpenGL through EGL (Mesa's software renderer, llvmpipe, without a GPU)
egl:
	@{ ldconfig -p | grep -q 'libEGL_mesa.so.0' && ldconfig -p | grep -q 'libGL.so.1'; } || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri >/dev/null; }

# students' controllers run sandboxed in bubblewrap (hri-lab grade, serve/experiment --controller FILE)
bubblewrap:
	@command -v bwrap >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq bubblewrap >/dev/null; }

# real ROS 1 (Debian's roscore and rospy) for the tests that check the lab's emulation against it (bench/ros1_oracle.py)
ros1:
	@{ command -v roscore >/dev/null && /usr/bin/python3 -c 'import rospy' 2>/dev/null; } || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq ros-core python3-rospy >/dev/null; }

test: $(STAMP) $(VENV)/.kernels $(CHP) chromium bubblewrap egl ros1
	$(BIN)/python -m pytest -q -n 3 --dist loadfile --no-loadscope-reorder

# the inner loop: no browser, no other programs (servers, nodes, sandboxed controllers); make test runs everything
test-fast: $(STAMP) $(VENV)/.kernels egl
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

experiment: $(STAMP) $(VENV)/.kernels bubblewrap
	$(BIN)/hri-lab experiment

bench: $(STAMP) $(VENV)/.kernels chromium bubblewrap egl
	@command -v wrk >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq wrk >/dev/null; }
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
