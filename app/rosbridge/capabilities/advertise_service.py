"""advertise_service / unadvertise_service: a client provides a service
(app/rosbridge/internal/node_services.py); every caller reaches it through the lab's registry."""

from __future__ import annotations

from typing import Any

from app.ros.names import node_name
from app.ros.services import ServiceFailure
from app.rosbridge.capabilities.op import Op
from app.rosbridge.internal.node_params import SERVICES as PARAMETER_SERVICES
from app.rosbridge.protocol import BadFrame, field, name_field


async def advertise_service(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "service")
    type_name = field(message, "type", str)
    text = field(message, "definition", str, None)  # the lab's own client carries the .srv text (not rosbridge_suite's)
    if name.startswith("/rosapi/"):
        raise BadFrame(f"advertise_service: {name} is the lab's")
    node, _, service = name.rpartition("/")
    if service in PARAMETER_SERVICES and node_name(node) in {n for n, _ in session.bridge.lab.params.declarations}:
        raise BadFrame(f"advertise_service: {name} is a parameter service of the lab's own node /{node_name(node)}")
    try:
        warning = session.bridge.nodes.advertise(name, type_name, session, text)
    except ServiceFailure as failure:
        raise BadFrame(f"advertise_service: {failure}") from None
    session.services.add(name)
    await session.report("info", f"advertise_service: {name} [{type_name}] is provided by {session.name}", id_)
    if warning:
        await session.report("warning", f"advertise_service: {warning}", id_)


async def unadvertise_service(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "service")
    if not session.bridge.nodes.unadvertise(name, session):
        await session.report("warning", f"unadvertise_service: {name} is not provided by this client", id_)
    session.services.discard(name)


OPS = {
    "advertise_service": Op(advertise_service, mutating=True),
    "unadvertise_service": Op(unadvertise_service, mutating=True),
}
