"""advertise_service / unadvertise_service: a client provides a service
(app/rosbridge/internal/node_services.py); every caller reaches it through the lab's registry.

A node that takes over one of the lab's own services (a name the lab answers itself: e.g.
/add_two_ints in a lab started without --exercises) is warned whatever its status level, and the
warning is on /rosout (the page's console): its answers replace the lab's until it leaves."""

from __future__ import annotations

from typing import Any

from app.ros.names import node_name
from app.ros.services import ServiceFailure
from app.rosbridge.capabilities.op import Op
from app.rosbridge.internal.node_params import SERVICES as PARAMETER_SERVICES
from app.rosbridge.protocol import BadFrame, field, name_field, status


async def advertise_service(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "service")
    type_name = field(message, "type", str)
    text = field(message, "definition", str, None)  # the lab's own client carries the .srv text (not rosbridge_suite's)
    if name.startswith("/rosapi/"):
        raise BadFrame(f"advertise_service: {name} is the lab's")
    node, _, service = name.rpartition("/")
    if service in PARAMETER_SERVICES and node_name(node) in {n for n, _ in session.bridge.lab.params.declarations}:
        raise BadFrame(f"advertise_service: {name} is a parameter service of the lab's own node /{node_name(node)}")
    replaces = session.bridge.nodes.answers_itself(name)
    try:
        warning = session.bridge.nodes.advertise(name, type_name, session, text)
    except ServiceFailure as failure:
        raise BadFrame(f"advertise_service: {failure}") from None
    session.services.add(name)
    await session.report("info", f"advertise_service: {name} [{type_name}] is provided by {session.name}", id_)
    if warning:
        await session.report("warning", f"advertise_service: {warning}", id_)
    if replaces:
        note = replaced_warning(name, session.name)
        session.bridge.lab.rosout.log("service", note, "WARN")
        await session.send(status("warning", f"advertise_service: {note}", id_))


def replaced_warning(name: str, node: str) -> str:
    return (
        f"{name} is one of the lab's own services: node {node} replaces it while connected (the lab's answers "
        "come back when the node leaves). For the handout's exercises start the lab with `hri-lab serve "
        "--exercises`, which leaves them to your node"
    )


async def unadvertise_service(session: Any, message: dict, id_: Any) -> None:
    name = name_field(message, "service")
    if not session.bridge.nodes.unadvertise(name, session):
        await session.report("warning", f"unadvertise_service: {name} is not provided by this client", id_)
    session.services.discard(name)


OPS = {
    "advertise_service": Op(advertise_service, mutating=True),
    "unadvertise_service": Op(unadvertise_service, mutating=True),
}
