"""Access: the server binds 127.0.0.1 by default. Binding any other address requires a token (at
least MIN_TOKEN_LENGTH characters), which every state-changing request (POST, PUT, PATCH, DELETE)
must carry as `Authorization: Bearer <token>` (or `X-HRI-Lab-Token: <token>`); reading (GET, topic
streams) and the 3D view stay open, and the view's controls are turned off when a token is set.

The token is compared as bytes in constant time (any header bytes are a 401, never a 500); wrong
tokens from one client address are answered one at a time, each after a delay that doubles per
failure (0.1 s up to 2 s), so guessing is slow. Cross-site requests are refused before this
(app/security.py). The token's rules and checks are app/tokens.py's."""

from __future__ import annotations

import asyncio
import hmac
import ipaddress
import json
import socket

from app.tokens import Throttle, presented_token

__all__ = ["Throttle", "TokenMiddleware", "is_loopback"]

MUTATING = {"POST", "PUT", "PATCH", "DELETE"}


def is_loopback(host: str) -> bool:
    """True for 127.0.0.0/8, ::1 and names that resolve only to them (localhost)."""
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        pass
    try:
        addresses = {info[4][0] for info in socket.getaddrinfo(host, None)}
    except OSError:
        return False
    return bool(addresses) and all(ipaddress.ip_address(str(a).split("%")[0]).is_loopback for a in addresses)


class TokenMiddleware:
    """ASGI middleware: state-changing requests without the right token are a 401."""

    def __init__(self, app, token: str) -> None:
        self.app = app
        self.token = token.encode("utf-8")
        self.throttle = Throttle()

    async def __call__(self, scope, receive, send) -> None:
        if scope["type"] != "http" or scope["method"] not in MUTATING:
            return await self.app(scope, receive, send)
        client = (scope.get("client") or ("?", 0))[0]
        if hmac.compare_digest(presented_token(scope["headers"]), self.token):
            self.throttle.succeed(client)
            return await self.app(scope, receive, send)
        async with self.throttle.lock(client):  # one wrong guess at a time per client
            delay = self.throttle.fail(client)
            await asyncio.sleep(delay)
        body = json.dumps(
            {"detail": "this server needs a token for changes: send 'Authorization: Bearer <token>'"}
        ).encode()
        await send(
            {
                "type": "http.response.start",
                "status": 401,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"content-length", str(len(body)).encode()),
                    (b"www-authenticate", b"Bearer"),
                    (b"retry-after", str(max(1, round(delay))).encode()),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})
