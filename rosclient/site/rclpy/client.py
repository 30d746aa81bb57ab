"""rclpy.client.Client: calls a service through the lab. `call_async` gives a Future completed
inside spin when the response is taken (one response per take, as rclpy's executor takes them), so
a coroutine callback may `await client.call_async(request)`. `call` blocks for the response and,
unlike rclpy, needs no other thread spinning."""

from __future__ import annotations

from collections import deque
from concurrent.futures import Future as WireFuture
from typing import TYPE_CHECKING, Any

from rosclient import process
from rclpy import _endpoints, context
from rclpy._entity import Call, Entity
from rclpy.callback_groups import CallbackGroup
from rclpy.exceptions import ServiceCallFailed
from rclpy.service_introspection import (
    REQUEST_SENT,
    RESPONSE_RECEIVED,
    Introspection,
    ServiceIntrospectionState,
    client_gid,
)
from rclpy.task import Future

if TYPE_CHECKING:
    from rclpy.node import Node


class Client(Entity):
    def __init__(self, node: Node, srv_type: Any, name: str, callback_group: CallbackGroup) -> None:
        if not hasattr(srv_type, "Request"):
            raise TypeError(f"create_client: srv_type must be a service type, got {srv_type!r}")
        self.node, self.srv_type = node, srv_type
        self.callback_group = callback_group
        callback_group.add_entity(self)
        self.srv_name = node.resolve_service_name(name)
        self._responses: deque[tuple[Future, WireFuture[Any], int]] = deque()
        self._pending: set[Future] = set()
        self._introspection = Introspection(self.srv_name, srv_type, client_gid())
        self._node_name = node.get_fully_qualified_name()
        self._destroyed = False
        _endpoints.add_client(self.srv_name, self._node_name)  # `service info` counts it

    def configure_introspection(self, clock: Any, service_event_qos_profile: Any,
                                introspection_state: ServiceIntrospectionState | int) -> None:
        """Publish this client's calls on <service>/_service_event (rclpy/service_introspection.py)."""
        self._introspection.configure(clock, service_event_qos_profile, introspection_state)

    def service_is_ready(self) -> bool:
        return self.srv_name in process.service_names()

    def wait_for_service(self, timeout_sec: float | None = None) -> bool:
        return process.wait_until(self.service_is_ready, timeout_sec)

    def _check(self, request: Any) -> None:
        if not isinstance(request, self.srv_type.Request):
            raise TypeError(f"Expected {self.srv_type.Request._type}, got {type(request)}")

    def call_async(self, request: Any) -> Future:
        """A Future completed inside spin with the response (or the reason the call failed)."""
        self._check(request)
        future = Future()
        self._pending.add(future)
        sequence = next(self._introspection.sequence)
        wire = process.connection().call_service_async(self.srv_name, request.to_json())
        self._introspection.event(REQUEST_SENT, sequence, request=request)
        wire.add_done_callback(lambda done: self._arrived(future, done, sequence))
        return future

    def _arrived(self, future: Future, done: WireFuture[Any], sequence: int) -> None:
        with context.CONDITION:
            self._responses.append((future, done, sequence))
        context.wake()

    def _is_ready(self) -> bool:
        return bool(self._responses)

    def _take(self) -> Call | None:
        with context.CONDITION:
            if not self._responses:
                return None
            future, done, sequence = self._responses.popleft()
        return lambda: self._complete(future, done, sequence)

    def _complete(self, future: Future, done: WireFuture[Any], sequence: int) -> None:
        self._pending.discard(future)
        if future.done():
            return
        executor = self.node.executor
        if executor is not None:
            future._set_executor(executor)
        ok, values = done.result()
        if not ok:
            future.set_exception(ServiceCallFailed(f"service {self.srv_name} failed: {values}"))
            return
        try:
            response = self.srv_type.Response.from_json(values if values is not None else {})
        except (TypeError, ValueError) as exc:
            future.set_exception(ServiceCallFailed(f"service {self.srv_name} answered with a bad response: {exc}"))
            return
        self._introspection.event(RESPONSE_RECEIVED, sequence, response=response)
        future.set_result(response)

    def call(self, request: Any, timeout_sec: float | None = None) -> Any:
        """The response; blocks (the lab answers on the connection's own thread)."""
        self._check(request)
        sequence = next(self._introspection.sequence)
        wire = process.connection().call_service_async(self.srv_name, request.to_json())
        self._introspection.event(REQUEST_SENT, sequence, request=request)
        ok, values = wire.result(timeout_sec)
        if not ok:
            raise ServiceCallFailed(f"service {self.srv_name} failed: {values}")
        response = self.srv_type.Response.from_json(values if values is not None else {})
        self._introspection.event(RESPONSE_RECEIVED, sequence, response=response)
        return response

    def remove_pending_request(self, future: Future) -> None:
        self._pending.discard(future)
        future.cancel()

    def destroy(self) -> None:
        self._pending.clear()
        if not self._destroyed:
            self._destroyed = True
            _endpoints.remove_client(self.srv_name, self._node_name)
