"""rosbridge clients in memory, for the unit tests of app/rosbridge: a real Session on the lab's
real Bridge (built by the composition root, app/serving/compose.py, around a Lab that is never started:
its parameters, log and first snapshot are there, its simulation does not run), whose WebSocket is
a list. A test sends frames with `op` and reads what the client was sent."""

from __future__ import annotations

import asyncio
import json
from typing import Any

from app.lab.lab import Lab
from app.lab.world import LIFTING
from app.rosbridge.session import Session
from app.serving.compose import Parts, build


class Socket:
    """The WebSocket a Session reads its headers from and sends to: what it sent, in order."""

    def __init__(self, headers: list[tuple[bytes, bytes]] | None = None) -> None:
        self.scope = {"headers": headers or []}
        self.sent: list[dict] = []

    async def send_text(self, text: str) -> None:
        self.sent.append(json.loads(text))


def parts(token: str | None = None, replay: bool = False) -> Parts:
    """A lab's registries and rosbridge state, wired as `hri-lab serve` wires them (replay: no lab
    topics, so no snapshot is sampled)."""
    return build(LIFTING, Lab(), token=token, replay=replay)


async def connect(parts: Parts, token: str | None = None) -> Session:
    """A connected client (as Session.run makes it), optionally presenting `token`."""
    headers = [(b"authorization", f"Bearer {token}".encode())] if token else []
    session = Session(parts.bridge, Socket(headers))  # type: ignore[arg-type]  # a WebSocket's two members
    session.loop = asyncio.get_running_loop()
    parts.bridge.sessions.join(session)
    return session


async def op(session: Session, **frame: Any) -> list[dict]:
    """Send one frame; what the client was sent while it was handled (and its calls answered)."""
    socket: Socket = session.ws  # type: ignore[assignment]
    before = len(socket.sent)
    await session.handle(json.dumps(frame))
    if session.tasks:  # a call or a goal: served in a task of its own
        await asyncio.wait_for(asyncio.gather(*session.tasks, return_exceptions=True), 30)
    return socket.sent[before:]


def run(coroutine: Any) -> Any:
    return asyncio.run(coroutine)


async def until(predicate: Any, what: str, timeout: float = 30.0) -> Any:
    """predicate()'s first truthy value, looked for while the event loop runs the client's tasks;
    AssertionError naming `what` when none came within `timeout` s (a bound, never a measurement)."""
    loop = asyncio.get_running_loop()
    end = loop.time() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if loop.time() > end:
            raise AssertionError(f"{what}: not within {timeout:g} s")
        await asyncio.sleep(0.005)


def sent(session: Session, kind: str) -> list[dict]:
    """The messages of op `kind` the client was sent so far."""
    socket: Socket = session.ws  # type: ignore[assignment]
    return [m for m in socket.sent if m.get("op") == kind]
