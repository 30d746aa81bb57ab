"""rosbridge's one service table: every service a client may call by name, each entry with one
access flag (`writes`: with a token set, the caller must have presented it) and called by one
path (`ServiceTable.call`). Its entries: the lab's registry (the lab's own services and the ones
nodes provide, app/ros/node_services.py: each may change the lab), rosapi's (app/rosbridge/rosapi.py)
and tf2_web_republisher's /republish_tfs (app/rosbridge/tf_republisher.py)."""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
from dataclasses import dataclass

from app.ros.messages import BadArguments, message_from_args
from app.ros.node_services import NodeServices
from app.ros.services import Service, ServiceFailure
from app.rosbridge import rosapi, tf_republisher
from app.rosbridge.ports import Caller

Args = dict | list | None  # a call's args: an object, or the request's fields in order
Header = dict[str, str] | None  # the extra fields of the caller's connection header (call_service's `headers`)
# answer(the caller: a client's call_service capability, its args, its header) -> the response's values
Answer = Callable[[Caller, Args, Header], Awaitable[object]]


@dataclass(frozen=True)
class ServiceEntry:
    name: str
    type: str
    answer: Answer  # raises ServiceFailure with the reason of a failed call
    writes: bool = True  # with a token set, the caller must have presented it


def _fields(args: Args) -> dict:
    """A service of rosbridge's own takes its args by name only (a list is no request of it)."""
    return args if isinstance(args, dict) else {}


def _rosapi_entry(service: rosapi.RosapiService) -> ServiceEntry:
    async def answer(
        caller: Caller, args: Args, header: Header
    ) -> object:  # in a worker thread: parameters ask the simulation
        return await asyncio.to_thread(service.handler, caller.bridge, _fields(args))

    return ServiceEntry(service.name, service.type, answer, service.writes)


async def _republish(caller: Caller, args: Args, header: Header) -> object:
    return tf_republisher.republish(caller, _fields(args))


REPUBLISH = ServiceEntry(tf_republisher.SERVICE, tf_republisher.TYPE, _republish, writes=False)


class ServiceTable:
    """The services of the lab's registry (looked up at call time: nodes come and go), then
    rosbridge's own: rosapi's, by name, and /republish_tfs."""

    def __init__(self, nodes: NodeServices) -> None:
        self.nodes = nodes
        own = [_rosapi_entry(s) for s in sorted(rosapi.SERVICES, key=lambda s: s.name)] + [REPUBLISH]
        self.own = {entry.name: entry for entry in own}

    def get(self, name: str) -> ServiceEntry | None:
        entry = self.own.get(name)
        if entry is not None:
            return entry
        service = self.nodes.registry.get(name)
        return None if service is None else self._lab_entry(service)

    def answers_itself(self, name: str) -> bool:
        """rosbridge answers `name` itself (rosapi's, /republish_tfs): no node may provide it."""
        return name in self.own

    def names(self) -> list[str]:
        """What `/rosapi/services` lists: the lab's services somebody answers now, then rosbridge's own."""
        return [s.name for s in self.nodes.registry if self.nodes.offered(s.name)] + list(self.own)

    def _lab_entry(self, service: Service) -> ServiceEntry:
        nodes = self.nodes

        async def answer(caller: Caller, args: Args, header: Header) -> object:
            try:
                request = message_from_args(service.request, args)
            except BadArguments as bad:
                raise ServiceFailure(str(bad)) from None
            if nodes.goes_to_node(service.name):  # from this loop: a node answers on it, told who calls
                response = await nodes.call_async(
                    service.name, request, {"callerid": caller.session.name, **(header or {})}
                )
            else:
                response = await asyncio.to_thread(service.handler, nodes.lab, request)
            return response.model_dump(by_alias=True)

        return ServiceEntry(service.name, service.type, answer, writes=True)

    def provider(self, name: str) -> str | None:
        """The node that answers `name` now (None: the lab or rosbridge itself)."""
        return None if name in self.own else self.nodes.node_of(name)

    async def call(self, caller: Caller, name: str, args: Args, header: Header = None) -> tuple[bool, object]:
        """(True, the response's values) or (False, the reason)."""
        entry = self.get(name)
        if entry is None:
            return False, f"service {name} does not exist"
        try:
            return True, await entry.answer(caller, args, header)
        except ServiceFailure as failure:
            return False, str(failure)
        except Exception as exc:  # noqa: BLE001 - a handler bug is a failed call, the connection goes on
            return False, f"{type(exc).__name__}: {exc}"
