"""rclpy.service.Service: the program provides a service through the lab. Requests wait in the
service's queue; each take serves one (the callback may be `async def`); the response — or, when
the callback raised, the reason — goes back to the caller. A name already provided (by the lab or
another program) is refused by the lab: RCLError, as rclpy raises when rcl cannot create a service."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from rosclient import process
from interfaces.packages import full_text
from rclpy import context
from rclpy._entity import Call, Entity, await_or_execute
from rclpy.callback_groups import CallbackGroup
from rclpy.exceptions import RCLError
from rclpy.publisher import type_name
from rclpy.service_introspection import REQUEST_RECEIVED, RESPONSE_SENT, Introspection, ServiceIntrospectionState

if TYPE_CHECKING:
    from rclpy.node import Node


class Service(Entity):
    def __init__(self, node: Node, srv_type: Any, name: str, callback: Callable[..., Any],
                 callback_group: CallbackGroup) -> None:
        if not hasattr(srv_type, "Request"):
            raise TypeError(f"create_service: srv_type must be a service type, got {srv_type!r}")
        self.node, self.srv_type, self.callback = node, srv_type, callback
        self.callback_group = callback_group
        callback_group.add_entity(self)
        self.service_name = node.resolve_service_name(name)
        self._requests: deque[dict[str, Any]] = deque()
        self._introspection = Introspection(self.service_name, srv_type)
        refusal = process.connection().advertise_service(
            self.service_name, type_name(srv_type), self._on_call, full_text(srv_type), check=True
        )
        if refusal:
            raise RCLError(f"Failed to create service {self.service_name}: {refusal}")

    def configure_introspection(self, clock: Any, service_event_qos_profile: Any,
                                introspection_state: ServiceIntrospectionState | int) -> None:
        """Publish this service's calls on <service>/_service_event (rclpy/service_introspection.py)."""
        self._introspection.configure(clock, service_event_qos_profile, introspection_state)

    def _on_call(self, message: dict[str, Any]) -> None:
        """A request from the lab (the connection's reader thread)."""
        with context.CONDITION:
            self._requests.append(message)
        context.wake()

    def _is_ready(self) -> bool:
        return bool(self._requests)

    def _take(self) -> Call | None:
        with context.CONDITION:
            if not self._requests:
                return None
            message = self._requests.popleft()
        return lambda: self._serve(message)

    async def _serve(self, message: dict[str, Any]) -> None:
        connection = process.connection()
        try:
            request = self.srv_type.Request.from_json(message.get("args") or {})
            sequence = next(self._introspection.sequence)
            self._introspection.event(REQUEST_RECEIVED, sequence, request=request)
            response = await await_or_execute(self.callback, request, self.srv_type.Response())
            if not isinstance(response, self.srv_type.Response):
                raise TypeError(f"the callback of service {self.service_name} returned {response!r}, "
                                f"not a {self.srv_type.Response._type}")
            connection.service_response(message.get("id"), self.service_name, response.to_json(), True)
            self._introspection.event(RESPONSE_SENT, sequence, response=response)
        except Exception as exc:
            # rclpy lets the exception end spin(); the caller in the lab hears why first
            connection.service_response(message.get("id"), self.service_name, f"{type(exc).__name__}: {exc}", False)
            raise

    def send_response(self, response: Any, header: Any) -> None:
        process.connection().service_response(header.get("id"), self.service_name, response.to_json(), True)

    def destroy(self) -> None:
        process.connection().send({"op": "unadvertise_service", "service": self.service_name})
