"""call_service: any service of the lab's registry (the lab's, rosapi's, other nodes', the tf
republisher's), answered
with service_response {values, result}; a failed call is `result: false` with the reason as its
values (and an error status)."""

from __future__ import annotations

import asyncio
from typing import Any

from app.ros.messages import BadArguments, message_from_args
from app.ros.services import ServiceFailure
from app.rosbridge import rosapi, tf_republisher
from app.rosbridge.capabilities.op import Op
from app.rosbridge.protocol import BadFrame, name_field

MAX_CALLS_IN_FLIGHT = 64  # per client: service calls and goals being served at once
READ_ONLY = rosapi.READ_ONLY | {tf_republisher.SERVICE}  # callable without the token


async def call_service(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "service")
    args = message.get("args")
    if args is not None and not isinstance(args, (dict, list)):
        raise BadFrame("call_service: field 'args' must be an object (or a list of the request's fields in order)")
    if name in rosapi.WRITING or (name not in READ_ONLY and not name.startswith("/rosapi/")):
        if not session.authorized:
            raise BadFrame(
                f"call_service {name}: this lab needs a token for changes (op auth, or the Authorization header)"
            )
    if session.in_flight >= MAX_CALLS_IN_FLIGHT:
        raise BadFrame(f"call_service: {MAX_CALLS_IN_FLIGHT} calls of this client are already in flight")
    session.in_flight += 1
    session.spawn(_call(session, name, args, id_))


async def _call(session: Any, name: str, args: Any, id_: Any) -> None:
    try:
        ok, values = await serve(session, name, args)
    finally:
        session.in_flight -= 1
    response = {"op": "service_response", "service": name, "values": values, "result": ok}
    if id_ is not None:
        response["id"] = id_
    await session.send(response)
    if not ok:
        await session.report("error", f"call_service {name}: {values}", id_)


async def serve(session: Any, name: str, args: Any) -> tuple[bool, Any]:
    """(True, the response's values) or (False, the reason)."""
    bridge = session.bridge
    try:
        if name.startswith("/rosapi/"):
            return True, await asyncio.to_thread(
                rosapi.call, bridge, session, name, args if isinstance(args, dict) else {}
            )
        if name == tf_republisher.SERVICE:
            return True, tf_republisher.republish(session, args if isinstance(args, dict) else {})
        service = bridge.services.get(name)
        if service is None:
            return False, f"service {name} does not exist"
        try:
            request = message_from_args(service.request, args)
        except BadArguments as bad:
            return False, str(bad)
        if bridge.nodes.goes_to_node(name):
            response = await bridge.nodes.call_async(name, request)
        else:
            response = await asyncio.to_thread(service.handler, session.lab, request)
        return True, response.model_dump(by_alias=True)
    except ServiceFailure as failure:
        return False, str(failure)
    except Exception as exc:  # noqa: BLE001 - a handler bug is a failed call
        return False, f"{type(exc).__name__}: {exc}"


OPS = {"call_service": Op(call_service)}
