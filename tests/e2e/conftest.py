"""What the tests under tests/e2e/ share: a real `hri-lab serve` for a test file, and a roslibpy client
connected to it. A file asks for other server arguments with a module-level `LAB_ARGS`."""

import pytest
import roslibpy

from app.cli.launch import running_server

LAB_ARGS = ("--view", "none")


@pytest.fixture(scope="module")
def lab(request):
    """A real server process on a free port (app/cli/launch.py), stopped after the file's tests."""
    with running_server(*getattr(request.module, "LAB_ARGS", LAB_ARGS)) as server:
        yield server


@pytest.fixture(scope="module")
def ros(lab):
    """roslibpy, unchanged, connected to the lab's rosbridge endpoint."""
    client = roslibpy.Ros("127.0.0.1", lab.port, transport="asyncio")
    client.run()
    yield client
    client.close()
    client.terminate()
