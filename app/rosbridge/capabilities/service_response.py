"""service_response: a node's answer to a call of a service it provides."""

from __future__ import annotations

import json
from typing import Any

from app.rosbridge.capabilities.op import Op
from app.rosbridge.protocol import field


async def service_response(session: Any, message: dict, id_: Any) -> None:
    ok = field(message, "result", bool, True)
    values = message.get("values")
    if not session.bridge.nodes.answer(session, message.get("id"), ok, values):
        await session.report(
            "warning",
            f"service_response: no call with id {json.dumps(message.get('id'))[:80]} waits for this client's answer",
            id_,
        )


OPS = {"service_response": Op(service_response, mutating=True)}
