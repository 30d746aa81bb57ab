"""The rosbridge v2 endpoint: a WebSocket at `/` on the lab's own port (roslibpy's
`Ros(host, port)` connects to ws://host:port/). The HTTP page stays at `/`: Starlette matches a
route by the scope's type, so GET / is the page and a WebSocket upgrade on / is rosbridge.

One more front end onto the same service registry, parameters, topics and actions as the HTTP
API and the dashboard. Access follows the API's rules: with a token set, every mutating op needs
it (the upgrade's `Authorization: Bearer <token>` or `X-HRI-Lab-Token` header, or rosauth's
`{"op": "auth", "mac": "<token>"}`); reading is open.

This module is rosbridge's public face: what the composition root (app/serving/compose.py) builds
(the Bridge, what every session shares: bridge.py) and mounts (the route). Layout
(rosbridge_suite's): this route; session.py, one connection; ops.py, the ops by name from
capabilities/ (one module per op family, a capability object per client); managers/, the shared
state, one manager per concern (topics, services, actions, tf, windows, sessions); ports.py, what a
capability may call of its session and of each manager; services.py, the one table of services a client
calls (the lab's, the nodes', rosapi's, /republish_tfs); internal/, the streams and the programs'
frames; protocol.py, frames; rosapi.py, the rosapi services.
"""

from __future__ import annotations

from fastapi import APIRouter, WebSocket

from app.rosbridge.bridge import Bridge
from app.rosbridge.session import Session

__all__ = ["Bridge", "router"]


def router(bridge: Bridge) -> APIRouter:
    r = APIRouter()

    @r.websocket("/")
    async def rosbridge(websocket: WebSocket) -> None:
        """rosbridge v2 (JSON over WebSocket)."""
        await Session(bridge, websocket).run()

    return r
