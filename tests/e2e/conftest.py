"""What the tests under tests/e2e/ share: roslibpy connected to a file's real server (the file's
`lab`, from tests/e2e/serving.py)."""

import pytest
import roslibpy


@pytest.fixture(scope="module")
def ros(lab):
    """roslibpy, unchanged, connected to the lab's rosbridge endpoint."""
    client = roslibpy.Ros("127.0.0.1", lab.port, transport="asyncio")
    client.run()
    yield client
    client.close()
    client.terminate()
