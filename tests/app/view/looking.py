"""A browser looking at a viser view, as viser counts one: its WebSocket with the protocol's
version, then its first message, the camera it views from (a browser sends it once the scene is
shown)."""

from contextlib import contextmanager

import msgspec
import viser
from viser._messages import ViewerCameraMessage
from websockets.sync.client import connect
from websockets.typing import Subprotocol

from tests.waiting import wait_for


@contextmanager
def a_browser(server: viser.ViserServer):
    """Connected and counted by `server` (get_clients) inside the block; gone from it after."""
    address = f"ws://127.0.0.1:{server.get_port()}"
    with connect(address, subprotocols=[Subprotocol(f"viser-v{viser.__version__}")]) as browser:
        camera = ViewerCameraMessage((1, 0, 0, 0), (1, 1, 1), 0.8, 0.01, 100.0, 600, 800, (0, 0, 0), (0, 0, 1))
        browser.send(msgspec.msgpack.encode(camera.as_serializable_dict()))
        wait_for(server.get_clients)
        yield
    wait_for(lambda: not server.get_clients())
