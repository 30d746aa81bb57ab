"""rospy.impl.tcpros_service: Service, ServiceProxy and wait_for_service over the lab's rosbridge
endpoint. A service's every call runs its handler on a thread of its own; a name this program or
another node already provides is a ServiceException, as rospy raises for a name registered twice.

Connection headers as TCPROS has them: a ServiceProxy's `headers` (and `persistent`'s
`persistent: 1`) go with each call (call_service's `headers`, the lab's extension); the request a
handler gets has `_connection_header`, the client's header (`service`, `md5sum`, `callerid`: the
calling node, or the lab's own for a call from HTTP or the CLI, then the client's fields), and the
response the proxy returns has the server's (`service`, `type`, `md5sum`, `callerid`)."""

from __future__ import annotations

import json
import threading
import traceback
from collections.abc import Callable
from typing import Any

from genpy import TVal

from interfaces.md5sum import md5sum
from interfaces.messages import Message
from interfaces.packages import full_text
from rosclient import process
from rospy import core, names
from rospy.exceptions import ROSException, ROSInterruptException
from rospy.service import ServiceException

_provided: dict[str, Service] = {}  # name -> this program's Service of it
_provided_lock = threading.Lock()


def _service_class(service_class: Any, what: str) -> Any:
    if not hasattr(service_class, "_request_class"):
        raise ValueError(
            f"{what}: service_class must be a service type (e.g. from my_pkg.srv import AddTwoInts), "
            f"got {service_class!r}"
        )
    return service_class


def wait_for_service(service: str, timeout: float | TVal | None = None) -> None:
    """Block until the service is advertised in the lab; ROSException after `timeout` s."""
    name = names.resolve_name(service)
    seconds = timeout.to_sec() if isinstance(timeout, TVal) else timeout
    if not process.wait_until(lambda: name in process.service_names(), seconds):
        if process.shutdown_event.is_set():
            raise ROSInterruptException("rospy shutdown")
        raise ROSException(f"timeout exceeded while waiting for service {name}")


class ServiceProxy:
    def __init__(self, name: str, service_class: Any, persistent: bool = False, headers: Any = None) -> None:
        self.service_class = _service_class(service_class, "rospy.ServiceProxy")
        self.resolved_name = names.resolve_name(name)
        self.request_class = service_class._request_class
        self.response_class = service_class._response_class
        self.persistent = persistent
        # TCPROSServiceClient's extra header fields, written as text (`key=value` on the wire)
        self.headers = {str(k): str(v) for k, v in (headers or {}).items()}
        if persistent:
            self.headers["persistent"] = "1"

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        return self.call(*args, **kwds)

    def call(self, *args: Any, **kwds: Any) -> Any:
        if len(args) == 1 and not kwds and isinstance(args[0], self.request_class):
            request = args[0]
        else:
            request = self.request_class(*args, **kwds)
        # rospy's callerid (its node's name, /unnamed before init_node), which the proxy's own may replace
        headers = {"callerid": names.get_caller_id(), **self.headers}
        wire = process.connection().call_service_async(self.resolved_name, request.to_json(), headers)
        ok, values, server = wire.result()
        if not ok:
            reason = values if isinstance(values, str) else json.dumps(values)
            raise ServiceException(f"service [{self.resolved_name}] failed: {reason}")
        try:
            response = self.response_class.from_json(values if values is not None else {})
        except (TypeError, ValueError) as exc:
            raise ServiceException(f"service [{self.resolved_name}] answered with a bad response: {exc}") from None
        response._connection_header = {  # TCPService's header fields
            "service": self.resolved_name,
            "type": self.service_class._type,
            "md5sum": md5sum(self.service_class),
            **{str(k): str(v) for k, v in server.items()},
        }
        return response

    def wait_for_service(self, timeout: float | TVal | None = None) -> None:
        wait_for_service(self.resolved_name, timeout)

    def close(self) -> None:
        pass


class Service:
    """A service this node provides."""

    def __init__(
        self,
        name: str,
        service_class: Any,
        handler: Callable[[Any], Any],
        buff_size: int = 65536,
        error_handler: Callable[..., Any] | None = None,
    ) -> None:
        self.service_class = _service_class(service_class, "rospy.Service")
        self.resolved_name = names.resolve_name(name)
        self.handler, self.error_handler = handler, error_handler
        self.done = False  # shut down (spin() returns)
        with _provided_lock:
            if self.resolved_name in _provided:
                raise ServiceException(f"service [{self.resolved_name}] already registered")
            _provided[self.resolved_name] = self
        refused = process.connection().advertise_service(
            self.resolved_name, service_class._type, self._on_call, full_text(service_class), check=True
        )
        if refused is not None:
            with _provided_lock:
                _provided.pop(self.resolved_name, None)
            raise ServiceException(f"service [{self.resolved_name}] cannot be provided: {refused}")

    def _on_call(self, message: dict[str, Any]) -> None:
        threading.Thread(target=self._serve, args=(message,), daemon=True, name="rospy-service").start()

    def _serve(self, message: dict[str, Any]) -> None:
        with process.callbacks:
            self._answer(message)

    def _answer(self, message: dict[str, Any]) -> None:
        connection = process.connection()
        try:
            request = self.service_class._request_class.from_json(message.get("args") or {})
            relayed = message.get("connection_header")
            request._connection_header = {  # TCPROSServiceClient's header fields, then the client's
                "service": self.resolved_name,
                "md5sum": md5sum(self.service_class),
                **{str(k): str(v) for k, v in (relayed if isinstance(relayed, dict) else {}).items()},
            }
            response = _as_response(self.service_class._response_class, self.handler(request))
            connection.service_response(message.get("id"), self.resolved_name, response.to_json(), True)
        except ServiceException as exc:
            connection.service_response(message.get("id"), self.resolved_name, str(exc), False)
        except Exception as exc:  # noqa: BLE001 - rospy: "error processing request", logged
            if self.error_handler is not None:
                self.error_handler(exc, type(exc), exc.__traceback__)
            else:
                core.logerr("Error processing request: %s\n%s", exc, traceback.format_exc())
            connection.service_response(
                message.get("id"), self.resolved_name, f"error processing request: {exc}", False
            )

    def shutdown(self, reason: str = "") -> None:
        self.done = True
        with _provided_lock:
            if _provided.get(self.resolved_name) is self:
                del _provided[self.resolved_name]
        process.connection().send({"op": "unadvertise_service", "service": self.resolved_name})

    def spin(self) -> None:
        """Until the node or this service shuts down (rospy's ServiceImpl.spin); Ctrl+C ends it too."""
        try:
            while not process.shutdown_event.wait(0.2) and not self.done:
                pass
        except KeyboardInterrupt:
            core.logdebug("keyboard interrupt, shutting down")


ServiceImpl = Service


def _as_response(response_class: Any, value: Any) -> Message:
    """What a handler may return, as rospy takes it: the response, a dict of its fields, a tuple or
    list of them in order, or the value of a single-field response."""
    if isinstance(value, response_class):
        return value
    if value is None:
        raise ServiceException("service handler returned None")
    if isinstance(value, Message):
        raise ServiceException(f"service handler returned a {value._type}, not a {response_class._type}")
    if isinstance(value, dict):
        result: Message = response_class(**value)
        return result
    if isinstance(value, (list, tuple)):
        result = response_class(*value)
        return result
    if len(response_class._fields) == 1:
        result = response_class(value)
        return result
    raise ServiceException(f"service handler returned {value!r}, not a {response_class._type}")
