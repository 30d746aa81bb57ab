"""One rosbridge connection (rosbridge_suite's Protocol): reads frames, dispatches each to its op
(app/rosbridge/ops.py), sends answers, and holds what this client has open — its subscriptions,
advertised topics and services, goals — which it gives back when the client goes.

Every refusal is a `status` message naming the op and the field; the connection goes on, except
for a frame beyond MAX_FRAME (closed with 1009).
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable
from typing import Any

from fastapi import WebSocket

from app.ros.actions import TERMINAL
from app.rosbridge.internal.state import Bridge
from app.rosbridge.ops import OPS
from app.rosbridge.protocol import LEVELS, MAX_FRAME, BadFrame, parse, status
from app.tokens import presented_token, token_matches


class Session:
    def __init__(self, bridge: Bridge, websocket: WebSocket) -> None:
        self.bridge, self.ws = bridge, websocket
        self.lab = bridge.lab
        self.client_name = bridge.next_name()  # its name until it names its node (op node)
        self.node_names: list[str] = []  # the nodes it runs, in the order it named them
        self.loop: asyncio.AbstractEventLoop | None = None
        token = bridge.token
        self.authorized = token is None or token_matches(presented_token(websocket.scope["headers"]), token)
        self.level = "error"
        self.streams: dict[str, Any] = {}  # topic -> app.rosbridge.internal.streams.Stream
        self.publishing: set[str] = set()
        self.services: set[str] = set()
        self.goals: dict[Any, Any] = {}  # goal id -> GoalHandle
        self.state: dict[str, Any] = {}  # a capability's own per-client state, by capability
        self.on_close: list[Callable[[], None]] = []  # what goes with the client (e.g. its tf topics)
        self.tasks: set[asyncio.Task] = set()
        self.in_flight = 0
        self.closed = False
        self._send_lock = asyncio.Lock()

    @property
    def name(self) -> str:
        """The node errors and the lab name this client by: its (first) node's, else /rosbridge_client_N."""
        return self.node_names[0] if self.node_names else self.client_name

    # --- connection -------------------------------------------------------------------------
    async def run(self) -> None:
        await self.ws.accept()
        self.loop = asyncio.get_running_loop()
        self.bridge.sessions.append(self)
        self.bridge.tf_republisher.start()
        try:
            while True:
                frame = await self.ws.receive()
                if frame["type"] == "websocket.disconnect":
                    break
                text = frame.get("text")
                if text is None:
                    data = frame.get("bytes") or b""
                    text = data.decode("utf-8", errors="replace")
                if len(text) > MAX_FRAME:
                    await self.report("error", f"frame of {len(text)} characters refused (limit {MAX_FRAME})")
                    await self.ws.close(code=1009, reason="frame too large")
                    break
                await self.handle(text)
        except Exception:  # noqa: BLE001 - a broken connection ends this session only
            pass
        finally:
            await self.close()

    async def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.bridge.sessions.remove(self)
        self.bridge.nodes.drop(self)
        self.bridge.node_actions.drop(self)
        self.bridge.frames.drop(self)
        for stream in self.streams.values():
            stream.stop()
            self.bridge.leave(stream.topic, subscription=stream)
        for topic in self.publishing:
            self.bridge.leave(topic, publisher=self)
        for handle in self.goals.values():  # the client is gone: its goals stop
            if handle.status not in TERMINAL:
                self.bridge.actions.cancel(handle)
        for task in list(self.tasks):
            task.cancel()
        for closing in self.on_close:
            closing()

    async def send(self, message: dict) -> None:
        if self.closed:
            return
        text = json.dumps(message)
        async with self._send_lock:
            try:
                await self.ws.send_text(text)
            except Exception:  # noqa: BLE001 - the client went away; run() ends the session
                pass

    async def report(self, level: str, msg: str, id_: Any = None) -> None:
        """A status message, if the client's level shows it (rosbridge's default: errors)."""
        order = LEVELS.index
        if self.level != "none" and order(level) >= order(self.level):
            await self.send(status(level, msg, id_))

    def spawn(self, coroutine) -> None:
        task = asyncio.ensure_future(coroutine)
        self.tasks.add(task)
        task.add_done_callback(self.tasks.discard)

    def details(self) -> dict:
        return {"subscribing": list(self.streams), "publishing": list(self.publishing), "services": list(self.services)}

    # --- dispatch ---------------------------------------------------------------------------
    async def handle(self, text: str) -> None:
        id_ = None
        try:
            message = parse(text)
            id_ = message.get("id") if isinstance(message.get("id"), (str, int)) else None
            op = message["op"]
            capability = OPS.get(op)
            if capability is None:
                raise BadFrame(f"unknown op '{op[:40]}'")
            if capability.mutating and not self.authorized:
                raise BadFrame(
                    f"{op}: this lab needs a token for changes: connect with 'Authorization: Bearer "
                    f'<token>\' or send {{"op": "auth", "mac": "<token>"}}'
                )
            await capability.handler(self, message, id_)
        except BadFrame as bad:
            await self.report("error", str(bad), id_)
        except Exception as exc:  # noqa: BLE001 - a bug here is reported, the connection goes on
            await self.report("error", f"internal error: {type(exc).__name__}: {exc}", id_)
