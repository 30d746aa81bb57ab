"""The connection's own ops: auth (rosauth's, with the lab's token as the mac), set_level; the
ops this lab does not support (fragment, png) refused with the reason."""

from __future__ import annotations

from typing import Any

from app.rosbridge.capabilities.op import Op
from app.rosbridge.protocol import LEVELS, BadFrame, field
from app.tokens import token_matches


async def auth(session: Any, message: dict, id_: Any) -> None:
    if session.bridge.token is None:
        return
    session.authorized = token_matches(field(message, "mac", str), session.bridge.token)
    if not session.authorized:
        raise BadFrame("auth: wrong token")


async def set_level(session: Any, message: dict, id_: Any) -> None:
    level = field(message, "level", str)
    if level in LEVELS:  # rosbridge drops a bad level silently
        session.level = level


async def fragment(session: Any, message: dict, id_: Any) -> None:
    raise BadFrame("fragment: fragmented messages are not supported by this lab; send the whole message")


async def png(session: Any, message: dict, id_: Any) -> None:
    raise BadFrame("png: PNG-compressed messages are not supported by this lab")


OPS = {"auth": Op(auth), "set_level": Op(set_level), "fragment": Op(fragment), "png": Op(png)}
