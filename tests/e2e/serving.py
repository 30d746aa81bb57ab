"""A real `hri-lab serve` for a test: `running_server(ARGS)` (a context manager), and `lab =
served_lab("--exercises")` at a module's top, which gives its tests a module-scoped fixture `lab`,
started once for the file and stopped after it (the server: app/serving/launch.py's `url`, `port`,
`proc`). (tests/conftest.py's `lab`, which a file without this line gets, is the in-process app's Lab.)

The lab is forked from the suite's warm zygote (tests/lab_zygote.py: the server's modules imported
and the kernels loaded once per pytest process), then runs `hri-lab serve ARGS` as the command does."""

import os
from contextlib import AbstractContextManager

import pytest

from app.serving import launch
from app.serving.launch import ServerProcess
from tests.lab_zygote import ForkedServer

# HRI_LAB_TEST_LABS=command: each lab started as the command (`python -m app.cli serve`), to compare
STARTED = ServerProcess if os.environ.get("HRI_LAB_TEST_LABS") == "command" else ForkedServer


def running_server(*args: str) -> AbstractContextManager[ServerProcess]:
    return launch.running_server(*args, started=STARTED)


def served_lab(*args: str):
    """The fixture `lab`: `hri-lab serve --view none ARGS` on a free port."""

    @pytest.fixture(scope="module")
    def lab():
        with running_server("--view", "none", *args) as server:
            yield server

    return lab
