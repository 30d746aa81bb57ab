"""A node's connection as app/ros's registries of node services, parameters and actions reach it (their
NodeClient): a real event loop on a thread of its own, and what the lab sends the node kept in order
for the test to read, or answered at once by the node's own service handlers."""

from __future__ import annotations

import asyncio
import queue
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from app.ros.node_services import NodeServices
from app.ros.rosout import Rosout


class Lab:
    """What the registries use of the lab: its /rosout."""

    def __init__(self) -> None:
        self.rosout = Rosout()

    def logged(self, text: str) -> bool:
        return any(text in line.msg for line in self.rosout.recent())


@contextmanager
def event_loop() -> Iterator[asyncio.AbstractEventLoop]:
    """A running event loop on its own thread, stopped and closed after."""
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    try:
        yield loop
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(30)
        loop.close()


class Node:
    """A node's connection: `sent` has what the lab sent it; a call of a service in `serves`
    (name -> args -> (ok, values)) is answered at once, as the node's server would."""

    def __init__(self, name: str, loop: asyncio.AbstractEventLoop | None, services: NodeServices | None = None) -> None:
        self._name, self._loop, self.services = name, loop, services
        self.sent: queue.Queue[dict] = queue.Queue()
        self.serves: dict[str, Callable[[dict], tuple[bool, Any]]] = {}

    @property
    def name(self) -> str:
        return self._name

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None:
        return self._loop

    async def send(self, message: dict) -> None:
        serve = self.serves.get(str(message.get("service"))) if message.get("op") == "call_service" else None
        if serve is not None and self.services is not None:
            ok, values = serve(message["args"])
            self.services.answer(self, message["id"], ok, values)
            return
        self.sent.put(message)

    def next(self, op: str) -> dict:
        """The next message the lab sent this node (it must be an `op`)."""
        message = self.sent.get(timeout=30)
        assert message["op"] == op, message
        return message
