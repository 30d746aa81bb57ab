"""advertise_service / unadvertise_service: a client provides a service
(app/ros/node_services.py); every caller reaches it through the lab's registry.

A node that takes over one of the lab's own services (a name the lab answers itself: e.g.
/add_two_ints in a lab started without --exercises) is warned whatever its status level, and the
warning is on /rosout (the page's console): its answers replace the lab's until it leaves."""

from __future__ import annotations

import asyncio

from app.ros.names import node_name
from app.ros.node_params import SERVICES as PARAMETER_SERVICES
from app.ros.node_services import models_of
from app.ros.services import ServiceFailure
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import MAX_CLIENT_SERVICES, BadFrame, field, name_field, status


class AdvertiseService(Capability):
    """The services this client provides (in the lab's registry while it is connected)."""

    DETAILS = "services"

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.services: set[str] = set()

    def names(self) -> list[str]:
        return list(self.services)

    async def advertise_service(self, message: dict, id_: Id) -> None:
        session, bridge = self.session, self.bridge
        name = name_field(message, "service")
        type_name = field(message, "type", str)
        text = field(
            message, "definition", str, None
        )  # the lab's own client carries the .srv text (not rosbridge_suite's)
        if bridge.services.answers_itself(name):  # rosapi's, /republish_tfs
            raise BadFrame(f"advertise_service: {name} is the lab's")
        node, _, service = name.rpartition("/")
        if service in PARAMETER_SERVICES and node_name(node) in {n for n, _ in bridge.lab.params.declarations}:
            raise BadFrame(f"advertise_service: {name} is a parameter service of the lab's own node /{node_name(node)}")
        self._room_for(name)
        try:  # the models of a carried text are built in a worker thread: the event loop goes on
            models = None if text is None else await asyncio.to_thread(models_of, type_name, text)
            if session.closed:  # the client went while they were built: nothing of it is kept
                return
            self._room_for(name)  # another op may have taken the last place meanwhile
            replaces = bridge.services.replaces_lab(name)
            warning = bridge.services.advertise(name, type_name, session, text, models)
        except ServiceFailure as failure:
            raise BadFrame(f"advertise_service: {failure}") from None
        self.services.add(name)
        await session.report("info", f"advertise_service: {name} [{type_name}] is provided by {session.name}", id_)
        if warning:
            await session.report("warning", f"advertise_service: {warning}", id_)
        if replaces:
            note = replaced_warning(name, session.name)
            bridge.lab.rosout.log("service", note, "WARN")
            await session.send(status("warning", f"advertise_service: {note}", id_))

    def _room_for(self, name: str) -> None:
        """BadFrame naming the cap when `name` would be one service too many (protocol.py's caps)."""
        if name in self.services:
            return
        if len(self.services) >= MAX_CLIENT_SERVICES:
            raise BadFrame(
                f"advertise_service: at most {MAX_CLIENT_SERVICES} services per client (unadvertise one first)"
            )
        self.bridge.services.room_for(name, "advertise_service")

    async def unadvertise_service(self, message: dict, id_: Id) -> None:
        name = name_field(message, "service")
        if not self.bridge.services.unadvertise(name, self.session):
            await self.session.report("warning", f"unadvertise_service: {name} is not provided by this client", id_)
        self.services.discard(name)

    def finish(self) -> None:
        self.bridge.services.drop(self.session)  # its services go with it (their calls in flight fail)
        self.services.clear()


def replaced_warning(name: str, node: str) -> str:
    return (
        f"{name} is one of the lab's own services: node {node} replaces it while connected (the lab's answers "
        "come back when the node leaves). For the handout's exercises start the lab with `hri-lab serve "
        "--exercises`, which leaves them to your node"
    )


OPS: Ops = {
    "advertise_service": Op(AdvertiseService, AdvertiseService.advertise_service, mutating=True),
    "unadvertise_service": Op(AdvertiseService, AdvertiseService.unadvertise_service, mutating=True),
}
