"""call_service: any service of rosbridge's one service table (app/rosbridge/services.py: the lab's
and the nodes', rosapi's, /republish_tfs), answered with service_response {values, result}; a
failed call is `result: false` with the reason as its values (and an error status).

The lab's extension `headers` ({str: str}, bounded: protocol.headers_field; rospy's
`ServiceProxy(headers=...)`): the call reaches a node's server with the caller's connection header
(its node's name as `callerid`, then these fields), and the service_response carries the server's
(`connection_header`: `callerid`, the node that answered, or the lab's own node)."""

from __future__ import annotations

from app.ros.names import LAB_NODE
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Closing, Id, SessionLike
from app.rosbridge.protocol import BadFrame, headers_field, name_field

MAX_CALLS_IN_FLIGHT = 64  # per client: service calls and goals being served at once


class CallService(Capability):
    """This client's calls: each served in a task of its own; what a call left behind for the
    client (a /republish_tfs topic) goes with it."""

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.on_close: list[Closing] = []  # what goes with the client (app/rosbridge/tf_republisher.py)

    async def call_service(self, message: dict, id_: Id) -> None:
        name = name_field(message, "service")
        args = message.get("args")
        if args is not None and not isinstance(args, (dict, list)):
            raise BadFrame("call_service: field 'args' must be an object (or a list of the request's fields in order)")
        headers = headers_field(message)
        table = self.bridge.services
        entry = table.get(name)
        # a graded program (bridge.graded) may call what nodes provide and rosbridge's own services, not the lab's
        node_call = self.bridge.graded and (table.provider(name) is not None or table.answers_itself(name))
        if entry is not None and entry.writes and not self.session.authorized and not node_call:
            if self.bridge.graded:
                raise BadFrame(f"call_service {name}: the lab's own services are refused to a graded program")
            raise BadFrame(
                f"call_service {name}: this lab needs a token for changes (op auth, or the Authorization header)"
            )
        session = self.session
        if session.in_flight >= MAX_CALLS_IN_FLIGHT:
            raise BadFrame(f"call_service: {MAX_CALLS_IN_FLIGHT} calls of this client are already in flight")
        session.in_flight += 1
        session.spawn(self._call(name, args, id_, headers))

    async def _call(self, name: str, args: dict | list | None, id_: Id, headers: dict[str, str] | None) -> None:
        table = self.bridge.services
        server = table.provider(name) or LAB_NODE  # who answers, asked before the call (it may leave)
        try:
            ok, values = await table.call(self, name, args, headers)
        finally:
            self.session.in_flight -= 1
        response = {"op": "service_response", "service": name, "values": values, "result": ok}
        if id_ is not None:
            response["id"] = id_
        if headers is not None:  # a ROS 1 client: the server's connection header
            response["connection_header"] = {"callerid": server}
        await self.session.send(response)
        if not ok:
            await self.session.report("error", f"call_service {name}: {values}", id_)

    def finish(self) -> None:
        for closing in self.on_close:
            closing()
        self.on_close.clear()


OPS: Ops = {"call_service": Op(CallService, CallService.call_service)}
