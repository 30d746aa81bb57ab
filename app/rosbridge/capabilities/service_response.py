"""service_response: a node's answer to a call of a service it provides (app/ros/node_services.py
holds the calls waiting for one)."""

from __future__ import annotations

import json

from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id
from app.rosbridge.protocol import field


class ServiceResponse(Capability):
    """A provider's answers: the calls waiting for them are the registry's (nothing of its own)."""

    async def service_response(self, message: dict, id_: Id) -> None:
        ok = field(message, "result", bool, True)
        values = message.get("values")
        if not self.bridge.services.answer(self.session, message.get("id"), ok, values):
            await self.session.report(
                "warning",
                f"service_response: no call with id {json.dumps(message.get('id'))[:80]} waits for this client's answer",
                id_,
            )


OPS: Ops = {"service_response": Op(ServiceResponse, ServiceResponse.service_response, mutating=True)}
