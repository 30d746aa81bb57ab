"""Services: rosbridge's one table of what a client may call (app/rosbridge/services.py: the lab's,
the nodes', rosapi's, /republish_tfs) and the services nodes provide in the lab's registry
(app/ros/node_services.py), with the lab's cap on those (MAX_SERVICES, all clients together)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from app.ros.messages import RosMessage
from app.ros.node_services import NodeClient, NodeServices
from app.ros.services import Service
from app.rosbridge.ports import Caller, ServiceEntryLike
from app.rosbridge.protocol import MAX_SERVICES, BadFrame
from app.rosbridge.services import Args, Header, ServiceTable


class ServiceManager:
    def __init__(self, nodes: NodeServices) -> None:
        self.nodes = nodes  # the lab's registry: its own services and the nodes'
        self.table = ServiceTable(nodes)  # every service a client may call

    # --- what a client calls ---
    def get(self, name: str) -> ServiceEntryLike | None:
        return self.table.get(name)

    def answers_itself(self, name: str) -> bool:
        """rosbridge answers `name` itself (rosapi's, /republish_tfs): no node may provide it."""
        return self.table.answers_itself(name)

    def names(self) -> list[str]:
        """What `/rosapi/services` lists."""
        return self.table.names()

    def provider(self, name: str) -> str | None:
        """The node that answers `name` now (None: the lab or rosbridge itself)."""
        return self.table.provider(name)

    async def call(self, caller: Caller, name: str, args: Args, header: Header = None) -> tuple[bool, object]:
        """(True, the response's values) or (False, the reason)."""
        return await self.table.call(caller, name, args, header)

    # --- the lab's registry, as rosapi shows it ---
    def registry(self) -> Iterable[Service]:
        """The lab's services and the nodes' (offered now or not)."""
        return self.nodes.registry

    def service(self, name: str) -> Service | None:
        return self.nodes.registry.get(name)

    def offered(self, name: str) -> bool:
        """Somebody answers `name` now (the lab, or a node)."""
        return self.nodes.offered(name)

    def lab_provides(self, name: str) -> bool:
        """The lab's own node answers `name`, offered now (no node provides it)."""
        return self.nodes.provided_by(name) is None and self.nodes.offered(name)

    # --- what a client provides ---
    def room_for(self, name: str, op: str) -> None:
        """BadFrame naming the cap when a node providing `name` would be one service too many."""
        providers = self.nodes.providers
        if name not in providers and len(providers) >= MAX_SERVICES:
            raise BadFrame(
                f"{op}: at most {MAX_SERVICES} services are provided by nodes already "
                "(the lab's limit, all clients together)"
            )

    def replaces_lab(self, name: str) -> bool:
        """A node advertising `name` now would replace a service the lab answers itself."""
        return self.nodes.answers_itself(name)

    def advertise(
        self,
        name: str,
        type_name: str,
        session: NodeClient,
        text: str | None = None,
        models: tuple[type[RosMessage], type[RosMessage]] | None = None,
    ) -> str | None:
        """`session` provides `name` (ServiceFailure with the reason it cannot); a warning for it, or None."""
        return self.nodes.advertise(name, type_name, session, text, models)

    def unadvertise(self, name: str, session: NodeClient) -> bool:
        return self.nodes.unadvertise(name, session)

    def drop(self, session: NodeClient) -> None:
        """`session`'s client is gone: its services go (their calls in flight fail)."""
        self.nodes.drop(session)

    def answer(self, session: NodeClient, call_id: object, ok: bool, values: Any) -> bool:
        """A provider's answer to a call waiting for it; False when none waits for it."""
        return self.nodes.answer(session, call_id, ok, values)
