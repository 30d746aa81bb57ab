"""One rosbridge connection (rosbridge_suite's Protocol): reads frames, dispatches each to its op
(app/rosbridge/ops.py) on this client's object of the op's capability, and sends answers. What the
client has open (its subscriptions, advertised topics and services, goals ...) is its capabilities'
to hold; when the client goes, the session calls each one's `finish()` and knows nothing else.

Every refusal is a `status` message naming the op and the field; the connection goes on, except
for a frame beyond MAX_FRAME (closed with 1009).
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import Awaitable

from fastapi import WebSocket

from app.rosbridge.capabilities.capability import Capability
from app.rosbridge.capabilities.endpoints import Endpoints
from app.rosbridge.ops import CAPABILITIES, OPS
from app.rosbridge.ports import BridgeLike, C, Id
from app.rosbridge.protocol import LEVELS, MAX_CONNECTIONS, MAX_FRAME, BadFrame, parse, status
from app.tokens import presented_token, token_matches

DETAILS = ("subscribing", "publishing", "services")  # rosapi's node_details, in its order
TOO_MANY = f"this lab serves at most {MAX_CONNECTIONS} rosbridge connections at once: try again later"


class Session:
    def __init__(self, bridge: BridgeLike, websocket: WebSocket) -> None:
        self.bridge, self.ws = bridge, websocket
        self.client_name = bridge.sessions.next_name()  # its name until it names its node (op node)
        self.node_names: list[str] = []  # the nodes it runs, in the order it named them
        self.loop: asyncio.AbstractEventLoop | None = None
        token = bridge.token
        self.address = str((websocket.scope.get("client") or ("?", 0))[0])  # its wrong tokens are slowed by it
        self.authorized = token is None or token_matches(presented_token(websocket.scope["headers"]), token)
        self.level = "error"
        self.tasks: set[asyncio.Task] = set()
        self.in_flight = 0  # its service calls and goals being served (capabilities/call_service.py)
        self.capabilities: dict[type, Capability] = {kind: kind(self) for kind in CAPABILITIES}
        self.closed = False
        self._send_lock = asyncio.Lock()

    @property
    def name(self) -> str:
        """The node errors and the lab name this client by: its (first) node's, else /rosbridge_client_N."""
        return self.node_names[0] if self.node_names else self.client_name

    # --- connection -------------------------------------------------------------------------
    async def run(self) -> None:
        await self.ws.accept()
        if not self.bridge.sessions.join(self):  # MAX_CONNECTIONS: told why, then closed: "try again later"
            self.closed = True
            try:
                await self.ws.send_text(json.dumps(status("error", TOO_MANY)))
                await self.ws.close(code=1013, reason="too many rosbridge connections")
            except Exception:  # noqa: BLE001 - the client went away already
                pass
            return
        self.loop = asyncio.get_running_loop()
        self.bridge.tf.start()
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
        self.bridge.sessions.leave(self)
        for capability in self.capabilities.values():
            capability.finish()
        for task in list(self.tasks):
            task.cancel()

    async def send(self, message: dict) -> None:
        await self.send_text(json.dumps(message))

    async def send_text(self, text: str) -> None:
        """A frame already encoded (a topic's message shared by its streams: internal/shared.py)."""
        if self.closed:
            return
        async with self._send_lock:
            try:
                await self.ws.send_text(text)
            except Exception:  # noqa: BLE001 - the client went away; run() ends the session
                pass

    async def report(self, level: str, msg: str, id_: Id = None) -> None:
        """A status message, if the client's level shows it (rosbridge's default: errors)."""
        order = LEVELS.index
        if self.level != "none" and order(level) >= order(self.level):
            await self.send(status(level, msg, id_))

    def spawn(self, coroutine: Awaitable[object]) -> None:
        task = asyncio.ensure_future(coroutine)
        self.tasks.add(task)
        task.add_done_callback(self.tasks.discard)

    def capability(self, kind: type[C]) -> C:
        """This client's object of a capability (one capability may read another's: publish, advertise's)."""
        capability = self.capabilities[kind]
        if not isinstance(capability, kind):
            raise TypeError(f"{kind.__name__} is not a capability of this session")
        return capability

    def endpoints(self, kind: str, name: str) -> list[dict]:
        """What rosapi's extension `endpoints` shows of this client: its entities of `kind` on `name`."""
        return self.capability(Endpoints).of(kind, name)

    def details(self) -> dict[str, list[str]]:
        """What rosapi's node_details shows of this client: the names its capabilities hold."""
        details: dict[str, list[str]] = {key: [] for key in DETAILS}
        for capability in self.capabilities.values():
            if capability.DETAILS is not None:
                details[capability.DETAILS] += capability.names()
        return details

    # --- dispatch ---------------------------------------------------------------------------
    async def handle(self, text: str) -> None:
        id_: Id = None
        try:
            message = parse(text)
            id_ = message.get("id") if isinstance(message.get("id"), (str, int)) else None
            op = message["op"]
            entry = OPS.get(op)
            if entry is None:
                raise BadFrame(f"unknown op '{op[:40]}'")
            if entry.mutating and not (self.authorized or self.bridge.graded):
                raise BadFrame(
                    f"{op}: this lab needs a token for changes: connect with 'Authorization: Bearer "
                    f'<token>\' or send {{"op": "auth", "mac": "<token>"}}'
                )
            await entry.handler(self.capabilities[entry.capability], message, id_)
        except BadFrame as bad:
            await self.report("error", str(bad), id_)
        except Exception as exc:  # noqa: BLE001 - a bug here is reported, the connection goes on
            await self.report("error", f"internal error: {type(exc).__name__}: {exc}", id_)
