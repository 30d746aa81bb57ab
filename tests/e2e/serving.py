"""A real `hri-lab serve` for a test file: `lab = served_lab("--exercises")` at a module's top gives
its tests a module-scoped fixture `lab`, the server process (app/serving/launch.py: `url`, `port`),
started once for the file and stopped after it. (tests/conftest.py's `lab`, which a file without
this line gets, is the in-process app's Lab.)"""

import pytest

from app.serving.launch import running_server


def served_lab(*args: str):
    """The fixture `lab`: `hri-lab serve --view none ARGS` on a free port."""

    @pytest.fixture(scope="module")
    def lab():
        with running_server("--view", "none", *args) as server:
            yield server

    return lab
