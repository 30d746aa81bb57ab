"""The connection's own ops: auth (rosauth's, with the lab's token as the mac; a wrong one answered
after the HTTP API's doubling delay, app/tokens.py's Throttle, per client address), set_level; the
ops this lab does not support (fragment, png) refused with the reason."""

from __future__ import annotations

import asyncio

from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id
from app.rosbridge.protocol import LEVELS, BadFrame, field
from app.tokens import token_matches


class Connection(Capability):
    """The client's access (its token) and the status level it asked for: the session's own."""

    async def auth(self, message: dict, id_: Id) -> None:
        token = self.bridge.token
        if token is None:
            return
        throttle, client = self.bridge.sessions.auth_throttle, self.session.address
        self.session.authorized = token_matches(field(message, "mac", str), token)
        if self.session.authorized:
            throttle.succeed(client)
            return
        async with throttle.lock(client):  # one wrong guess at a time per client address, as HTTP's
            await asyncio.sleep(throttle.fail(client))
        raise BadFrame("auth: wrong token")

    async def set_level(self, message: dict, id_: Id) -> None:
        level = field(message, "level", str)
        if level in LEVELS:  # rosbridge drops a bad level silently
            self.session.level = level

    async def fragment(self, message: dict, id_: Id) -> None:
        raise BadFrame("fragment: fragmented messages are not supported by this lab; send the whole message")

    async def png(self, message: dict, id_: Id) -> None:
        raise BadFrame("png: PNG-compressed messages are not supported by this lab")


OPS: Ops = {
    "auth": Op(Connection, Connection.auth),
    "set_level": Op(Connection, Connection.set_level),
    "fragment": Op(Connection, Connection.fragment),
    "png": Op(Connection, Connection.png),
}
