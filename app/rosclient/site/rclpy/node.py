"""rclpy.node.Node over the lab's rosbridge endpoint.

Publishers, subscriptions, services, clients and timers as rclpy has them; every callback waits in
the node's work queue and runs inside spin()/spin_once() (rclpy/executors.py). Parameters are
declared with descriptors, checked as rclcpp checks them (type, read-only, ranges, the
on-set callbacks) and served to the lab with the standard rcl_interfaces services
/<node>/get_parameters, set_parameters, list_parameters, describe_parameters, get_parameter_types
and set_parameters_atomically, so `hri-lab param set /node name value` reaches the running node.
"""
from __future__ import annotations

import math
import threading
import time
from collections import deque
from typing import Any, Callable

from app.rosclient import process
from app.rosclient.interfaces import Message, full_text
from rclpy import executors
from rclpy.clock import Clock
from rclpy.exceptions import (
    InvalidParameterTypeException,
    InvalidParameterValueException,
    ParameterAlreadyDeclaredException,
    ParameterNotDeclaredException,
    ServiceCallFailed,
)
from rclpy.logging import get_logger
from rclpy.parameter import Parameter, from_value_msg
from rclpy.qos import profile
from rclpy.task import Future

PARAMETER_SERVICES = {  # service suffix -> rcl_interfaces type
    "describe_parameters": "DescribeParameters", "get_parameters": "GetParameters",
    "get_parameter_types": "GetParameterTypes", "list_parameters": "ListParameters",
    "set_parameters": "SetParameters", "set_parameters_atomically": "SetParametersAtomically",
}


def _type_name(cls: Any, kind: str) -> str:
    """The ROS 2 type name of a message/service/action class ('pkg/srv/Name')."""
    return getattr(cls, "_ros2_type", "") or cls._type


class Publisher:
    def __init__(self, node: "Node", msg_type: type, topic: str, qos: Any) -> None:
        if not (isinstance(msg_type, type) and issubclass(msg_type, Message)):
            raise TypeError(f"create_publisher: msg_type must be a message class, got {msg_type!r}")
        self.node, self.msg_type, self.qos_profile = node, msg_type, profile(qos)
        self.topic_name = node.resolve_topic_name(topic)
        self.type = _type_name(msg_type, "msg")
        process.advertise_once(self.topic_name, self.type, msg_type)

    @property
    def topic(self) -> str:
        return self.topic_name

    def publish(self, msg: Any) -> None:
        if not isinstance(msg, self.msg_type):
            raise TypeError(f"Expected {self.msg_type.__module__}.{self.msg_type.__name__}, got {type(msg)}")
        process.publish(self.topic_name, self.type, msg.to_json())

    def get_subscription_count(self) -> int:
        return 1

    def destroy(self) -> None:
        process.connection().send({"op": "unadvertise", "topic": self.topic_name})


class Subscription:
    """Messages wait in a queue of the QoS depth (full: the oldest goes) until spin takes them."""

    def __init__(self, node: "Node", msg_type: type, topic: str, callback: Callable, qos: Any,
                 raw: bool = False) -> None:
        if not (isinstance(msg_type, type) and issubclass(msg_type, Message)):
            raise TypeError(f"create_subscription: msg_type must be a message class, got {msg_type!r}")
        self.node, self.msg_type, self.callback = node, msg_type, callback
        self.qos_profile = profile(qos)
        self.topic_name = node.resolve_topic_name(topic)
        depth = self.qos_profile.queue_length
        self.queue: deque = deque(maxlen=depth or None)
        self.received = 0
        self._sid = process.connection().subscribe(self.topic_name, _type_name(msg_type, "msg"), self._offer,
                                                   queue_length=depth)

    def _offer(self, data: dict) -> None:
        with executors.WAKE:
            self.received += 1
            self.queue.append(data)
        executors.post(self.node, self._take)

    def _take(self) -> None:
        with executors.WAKE:
            if not self.queue:
                return  # dropped: a newer message took its place
            data = self.queue.popleft()
        self.callback(self.msg_type.from_json(data))

    @property
    def topic(self) -> str:
        return self.topic_name

    def destroy(self) -> None:
        process.connection().unsubscribe(self.topic_name, self._sid, self._offer)


class Service:
    def __init__(self, node: "Node", srv_type: Any, name: str, callback: Callable) -> None:
        if not hasattr(srv_type, "Request"):
            raise TypeError(f"create_service: srv_type must be a service type, got {srv_type!r}")
        self.node, self.srv_type, self.callback = node, srv_type, callback
        self.service_name = node.resolve_service_name(name)
        process.connection().advertise_service(
            self.service_name, _type_name(srv_type, "srv"), self._on_call, full_text(srv_type)
        )

    def _on_call(self, message: dict) -> None:
        executors.post(self.node, lambda: self._serve(message))

    def _serve(self, message: dict) -> None:
        connection = process.connection()
        try:
            request = self.srv_type.Request.from_json(message.get("args") or {})
            response = self.callback(request, self.srv_type.Response())
            if not isinstance(response, self.srv_type.Response):
                raise TypeError(f"the callback of service {self.service_name} returned {response!r}, "
                                f"not a {self.srv_type.Response._type}")
            connection.service_response(message.get("id"), self.service_name, response.to_json(), True)
        except Exception as exc:
            # rclpy lets the exception end spin(); the caller in the lab hears why first
            connection.service_response(message.get("id"), self.service_name, f"{type(exc).__name__}: {exc}", False)
            raise

    def destroy(self) -> None:
        process.connection().send({"op": "unadvertise_service", "service": self.service_name})


class Client:
    def __init__(self, node: "Node", srv_type: Any, name: str) -> None:
        if not hasattr(srv_type, "Request"):
            raise TypeError(f"create_client: srv_type must be a service type, got {srv_type!r}")
        self.node, self.srv_type = node, srv_type
        self.srv_name = node.resolve_service_name(name)

    def service_is_ready(self) -> bool:
        return self.srv_name in process.service_names()

    def wait_for_service(self, timeout_sec: float | None = None) -> bool:
        return process.wait_until(self.service_is_ready, timeout_sec)

    def call_async(self, request: Any) -> Future:
        """A Future completed inside spin with the response (or the reason the call failed)."""
        if not isinstance(request, self.srv_type.Request):
            raise TypeError(f"Expected {self.srv_type.Request._type}, got {type(request)}")
        future = Future()
        pending = process.connection().call_service_async(self.srv_name, request.to_json())
        pending.add_done_callback(lambda done: executors.post(self.node, lambda: self._complete(future, done)))
        return future

    def _complete(self, future: Future, done: Any) -> None:
        if future.done():
            return
        ok, values = done.result()
        if not ok:
            future.set_exception(ServiceCallFailed(f"service {self.srv_name} failed: {values}"))
            return
        try:
            future.set_result(self.srv_type.Response.from_json(values if values is not None else {}))
        except (TypeError, ValueError) as exc:
            future.set_exception(ServiceCallFailed(f"service {self.srv_name} answered with a bad response: {exc}"))

    def call(self, request: Any, timeout_sec: float | None = None) -> Any:
        """Blocks until the response (does not need another thread spinning, unlike rclpy)."""
        if not isinstance(request, self.srv_type.Request):
            raise TypeError(f"Expected {self.srv_type.Request._type}, got {type(request)}")
        ok, values = process.connection().call_service_async(self.srv_name, request.to_json()).result(timeout_sec)
        if not ok:
            raise ServiceCallFailed(f"service {self.srv_name} failed: {values}")
        return self.srv_type.Response.from_json(values if values is not None else {})

    def remove_pending_request(self, future: Future) -> None:
        future.cancel()

    def destroy(self) -> None:
        pass


class Timer:
    def __init__(self, node: "Node", period_sec: float, callback: Callable) -> None:
        if not period_sec > 0:
            raise ValueError("create_timer: timer_period_sec must be > 0")
        self.node, self.callback = node, callback
        self.timer_period_ns = int(period_sec * 1e9)
        self._canceled = False
        self._due = time.monotonic() + period_sec

    def _fire(self) -> None:
        period = self.timer_period_ns / 1e9
        now = time.monotonic()
        self._due += period
        if self._due < now:  # late: skip the missed periods, keep the phase
            self._due += math.ceil((now - self._due) / period) * period
        self.callback()

    def cancel(self) -> None:
        self._canceled = True

    def is_canceled(self) -> bool:
        return self._canceled

    def reset(self) -> None:
        self._canceled = False
        self._due = time.monotonic() + self.timer_period_ns / 1e9
        executors.WAKE.acquire()
        executors.WAKE.notify_all()
        executors.WAKE.release()

    def is_ready(self) -> bool:
        return not self._canceled and time.monotonic() >= self._due

    def time_until_next_call(self) -> int:
        return int(max(self._due - time.monotonic(), 0.0) * 1e9)

    def destroy(self) -> None:
        self.cancel()


class Rate:
    def __init__(self, frequency: float) -> None:
        self.period = 1.0 / frequency
        self.next = time.monotonic() + self.period

    def sleep(self) -> None:
        wait = self.next - time.monotonic()
        if wait > 0:
            process.shutdown_event.wait(wait)
        self.next = max(self.next + self.period, time.monotonic())

    def destroy(self) -> None:
        pass


class Node:
    def __init__(self, node_name: str, *, context: Any = None, cli_args: list[str] | None = None,
                 namespace: str | None = None, use_global_arguments: bool = True, enable_rosout: bool = True,
                 start_parameter_services: bool = True, parameter_overrides: list[Parameter] | None = None,
                 allow_undeclared_parameters: bool = False,
                 automatically_declare_parameters_from_overrides: bool = False, **other: Any) -> None:
        import rclpy

        if not rclpy.ok():
            from rclpy.exceptions import NotInitializedException

            raise NotInitializedException()
        if not node_name or "/" in node_name or not node_name.replace("_", "a").isalnum() or node_name[0].isdigit():
            raise ValueError(f"Invalid node name: {node_name!r} (letters, digits and underscores; not starting "
                             f"with a digit)")
        arguments = rclpy._arguments(cli_args, use_global_arguments)
        self._name = arguments.remapped_name or node_name
        self._namespace = "/" + (namespace or arguments.namespace or "").strip("/")
        self._work: deque = deque()
        self._timers: list[Timer] = []
        self.executor: Any = None
        self._parameters: dict[str, Parameter] = {}
        self._descriptors: dict[str, Any] = {}
        self._set_callbacks: list[Callable] = []
        self._allow_undeclared = allow_undeclared_parameters
        self._overrides: dict[str, Any] = arguments.parameters_for(self.get_fully_qualified_name(), self._name)
        for parameter in parameter_overrides or []:
            self._overrides[parameter.name] = parameter.value
        self._logger = get_logger(self._name)
        self._clock = Clock()
        self._lock = threading.RLock()
        self._entities: list[Any] = []
        if automatically_declare_parameters_from_overrides:
            for name, value in self._overrides.items():
                self.declare_parameter(name, value)
        if start_parameter_services:
            from rcl_interfaces import srv

            for suffix, type_name in PARAMETER_SERVICES.items():
                self._entities.append(Service(self, getattr(srv, type_name), f"~/{suffix}",
                                              getattr(self, f"_{suffix}")))

    # --- names -------------------------------------------------------------------------------
    def get_name(self) -> str:
        return self._name

    def get_namespace(self) -> str:
        return self._namespace

    def get_fully_qualified_name(self) -> str:
        return process.resolve(self._name, "", self._namespace)

    def resolve_topic_name(self, topic: str, *, only_expand: bool = False) -> str:
        if topic.startswith("~"):
            return self.get_fully_qualified_name() + ("/" + topic[1:].strip("/") if topic[1:].strip("/") else "")
        return process.resolve(topic, self._name, self._namespace)

    resolve_service_name = resolve_topic_name

    def get_logger(self):
        return self._logger

    def get_clock(self) -> Clock:
        return self._clock

    # --- entities ----------------------------------------------------------------------------
    def create_publisher(self, msg_type: type, topic: str, qos_profile: Any, *, callback_group: Any = None,
                         event_callbacks: Any = None, **other: Any) -> Publisher:
        publisher = Publisher(self, msg_type, topic, qos_profile)
        self._entities.append(publisher)
        return publisher

    def create_subscription(self, msg_type: type, topic: str, callback: Callable, qos_profile: Any, *,
                            callback_group: Any = None, event_callbacks: Any = None, raw: bool = False,
                            **other: Any) -> Subscription:
        subscription = Subscription(self, msg_type, topic, callback, qos_profile, raw)
        self._entities.append(subscription)
        return subscription

    def create_service(self, srv_type: Any, srv_name: str, callback: Callable, *, qos_profile: Any = None,
                       callback_group: Any = None) -> Service:
        service = Service(self, srv_type, srv_name, callback)
        self._entities.append(service)
        return service

    def create_client(self, srv_type: Any, srv_name: str, *, qos_profile: Any = None,
                      callback_group: Any = None) -> Client:
        client = Client(self, srv_type, srv_name)
        self._entities.append(client)
        return client

    def create_timer(self, timer_period_sec: float, callback: Callable, callback_group: Any = None,
                     clock: Any = None, autostart: bool = True) -> Timer:
        timer = Timer(self, timer_period_sec, callback)
        if not autostart:
            timer.cancel()
        with executors.WAKE:
            self._timers.append(timer)
            executors.WAKE.notify_all()
        return timer

    def create_rate(self, frequency: float, clock: Any = None) -> Rate:
        return Rate(frequency)

    def destroy_timer(self, timer: Timer) -> bool:
        timer.cancel()
        return True

    def destroy_publisher(self, publisher: Publisher) -> bool:
        publisher.destroy()
        return True

    def destroy_subscription(self, subscription: Subscription) -> bool:
        subscription.destroy()
        return True

    def destroy_service(self, service: Service) -> bool:
        service.destroy()
        return True

    def destroy_client(self, client: Client) -> bool:
        return True

    def destroy_node(self) -> None:
        if not process.connected() or process.shutdown_event.is_set():
            return
        for timer in self._timers:
            timer.cancel()
        for entity in self._entities:
            if isinstance(entity, (Service, Subscription)):
                try:
                    entity.destroy()
                except Exception:  # noqa: BLE001 - the connection may be going
                    pass
        self._entities.clear()

    def count_publishers(self, topic_name: str) -> int:
        return 0

    def count_subscribers(self, topic_name: str) -> int:
        return 0

    def get_node_names(self) -> list[str]:
        return [n.strip("/") for n in process.connection().call_service("/rosapi/nodes", {}).get("nodes", [])]

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        return [(name, []) for name in sorted(process.service_names())]

    # --- parameters --------------------------------------------------------------------------
    def declare_parameter(self, name: str, value: Any = None, descriptor: Any = None,
                          ignore_override: bool = False) -> Parameter:
        return self.declare_parameters("", [(name, value, descriptor)], ignore_override)[0]

    def declare_parameters(self, namespace: str, parameters: list, ignore_override: bool = False) -> list[Parameter]:
        from rcl_interfaces.msg import ParameterDescriptor

        declared = []
        for entry in parameters:
            entry = tuple(entry) if isinstance(entry, (tuple, list)) else (entry,)
            name = f"{namespace}.{entry[0]}" if namespace else entry[0]
            value = entry[1] if len(entry) > 1 else None
            if isinstance(value, Parameter.Type):
                value = None
            descriptor = entry[2] if len(entry) > 2 and entry[2] is not None else ParameterDescriptor()
            if not name or not isinstance(name, str):
                raise ValueError("a parameter name must be a non-empty string")
            if name in self._parameters:
                raise ParameterAlreadyDeclaredException([name])
            if name in self._overrides and not ignore_override:
                value = self._overrides[name]
            type_ = Parameter.Type.from_parameter_value(value)
            descriptor.name = name
            if not descriptor.dynamic_typing:
                if descriptor.type == 0:
                    descriptor.type = type_.value
                elif value is not None and descriptor.type != type_.value:
                    raise InvalidParameterTypeException(Parameter(name, type_, value),
                                                        Parameter.Type(descriptor.type).name)
            reason = _range_refusal(name, value, descriptor)
            if reason:
                raise InvalidParameterValueException(name, value, reason)
            parameter = Parameter(name, type_, value)
            result = self._run_callbacks([parameter])
            if not result.successful:
                raise InvalidParameterValueException(name, value, result.reason)
            self._parameters[name] = parameter
            self._descriptors[name] = descriptor
            declared.append(parameter)
        return declared

    def undeclare_parameter(self, name: str) -> None:
        if name not in self._parameters:
            raise ParameterNotDeclaredException([name])
        del self._parameters[name]
        del self._descriptors[name]

    def has_parameter(self, name: str) -> bool:
        return name in self._parameters

    def get_parameter(self, name: str) -> Parameter:
        with self._lock:
            if name in self._parameters:
                return self._parameters[name]
        if self._allow_undeclared:
            return Parameter(name, Parameter.Type.NOT_SET, None)
        raise ParameterNotDeclaredException([name])

    def get_parameter_or(self, name: str, alternative_value: Parameter | None = None) -> Parameter:
        if alternative_value is None:
            alternative_value = Parameter(name, Parameter.Type.NOT_SET)
        return self._parameters.get(name, alternative_value)

    def get_parameters(self, names: list[str]) -> list[Parameter]:
        return [self.get_parameter(n) for n in names]

    def get_parameters_by_prefix(self, prefix: str) -> dict[str, Parameter]:
        start = prefix + "." if prefix else ""
        return {n[len(start):]: p for n, p in self._parameters.items() if n.startswith(start)}

    def describe_parameter(self, name: str) -> Any:
        if name not in self._descriptors:
            raise ParameterNotDeclaredException([name])
        return self._descriptors[name]

    def set_parameters(self, parameter_list: list[Parameter]) -> list[Any]:
        """One SetParametersResult per parameter; an undeclared one raises, as in rclpy."""
        for parameter in parameter_list:
            if parameter.name not in self._parameters and not self._allow_undeclared:
                raise ParameterNotDeclaredException([parameter.name])
        return [self._set([parameter]) for parameter in parameter_list]

    def set_parameters_atomically(self, parameter_list: list[Parameter]) -> Any:
        return self._set(parameter_list)

    def add_on_set_parameters_callback(self, callback: Callable) -> None:
        self._set_callbacks.insert(0, callback)

    def remove_on_set_parameters_callback(self, callback: Callable) -> None:
        self._set_callbacks.remove(callback)

    def _run_callbacks(self, parameters: list[Parameter]) -> Any:
        from rcl_interfaces.msg import SetParametersResult

        for callback in self._set_callbacks:
            result = callback(parameters)
            if not result.successful:
                return result
        return SetParametersResult(successful=True)

    def _set(self, parameters: list[Parameter]) -> Any:
        """Check every parameter as rclcpp does (declared, read-only, type, range), then the
        on-set callbacks; all are set or none."""
        from rcl_interfaces.msg import SetParametersResult

        with self._lock:
            for parameter in parameters:
                reason = self._refusal(parameter)
                if reason:
                    return SetParametersResult(successful=False, reason=reason)
            result = self._run_callbacks(parameters)
            if not result.successful:
                return result
            for parameter in parameters:
                if parameter.type_ == Parameter.Type.NOT_SET:
                    self._parameters.pop(parameter.name, None)
                    self._descriptors.pop(parameter.name, None)
                    continue
                if parameter.name not in self._descriptors:
                    from rcl_interfaces.msg import ParameterDescriptor

                    self._descriptors[parameter.name] = ParameterDescriptor(name=parameter.name,
                                                                            type=parameter.type_.value)
                self._parameters[parameter.name] = parameter
        return SetParametersResult(successful=True)

    def _refusal(self, parameter: Parameter) -> str:
        name = parameter.name
        descriptor = self._descriptors.get(name)
        if descriptor is None:
            if self._allow_undeclared:
                return ""
            return f"parameter '{name}' cannot be set because it was not declared"
        if descriptor.read_only:
            return f"parameter '{name}' cannot be set because it is read-only"
        if parameter.type_ == Parameter.Type.NOT_SET:
            return ""
        if not descriptor.dynamic_typing and descriptor.type not in (0, parameter.type_.value):
            return (f"Wrong parameter type, parameter {{{name}}} is of type {{{Parameter.Type(descriptor.type).ros_name}}}"
                    f", setting it to {{{parameter.type_.ros_name}}} is not allowed.")
        return _range_refusal(name, parameter.value, descriptor)

    # --- the parameter services (run inside spin, like every callback) --------------------------
    def _get_parameters(self, request: Any, response: Any) -> Any:
        from rcl_interfaces.msg import ParameterValue

        response.values = [self._parameters[n].get_parameter_value() if n in self._parameters else ParameterValue()
                           for n in request.names]
        return response

    def _get_parameter_types(self, request: Any, response: Any) -> Any:
        response.types = bytes(self._parameters[n].type_.value if n in self._parameters else 0 for n in request.names)
        return response

    def _set_parameters(self, request: Any, response: Any) -> Any:
        response.results = [self._set([Parameter(p.name, Parameter.Type(p.value.type), from_value_msg(p.value))])
                            for p in request.parameters]
        return response

    def _set_parameters_atomically(self, request: Any, response: Any) -> Any:
        response.result = self._set([Parameter(p.name, Parameter.Type(p.value.type), from_value_msg(p.value))
                                     for p in request.parameters])
        return response

    def _list_parameters(self, request: Any, response: Any) -> Any:
        names = sorted(self._parameters)
        if request.prefixes:
            names = [n for n in names if any(n == p or n.startswith(p + ".") for p in request.prefixes)]
        if request.depth:
            names = [n for n in names if n.count(".") < request.depth]
        response.result.names = names
        response.result.prefixes = sorted({n.rsplit(".", 1)[0] for n in names if "." in n})
        return response

    def _describe_parameters(self, request: Any, response: Any) -> Any:
        from rcl_interfaces.msg import ParameterDescriptor

        response.descriptors = [self._descriptors.get(n, ParameterDescriptor(name=n)) for n in request.names]
        return response


def _range_refusal(name: str, value: Any, descriptor: Any) -> str:
    """rclcpp's refusal of a value outside the descriptor's range ('' when inside)."""
    if value is None or isinstance(value, bool):
        return ""
    for ranges, kind in ((descriptor.floating_point_range, "floating point"), (descriptor.integer_range, "integer")):
        if not ranges or not isinstance(value, (int, float)):
            continue
        r = ranges[0]
        low, high, step = r.from_value, r.to_value, r.step
        tolerance = 1e-9 * max(1.0, abs(low), abs(high))
        inside = low - tolerance <= value <= high + tolerance
        on_step = (not step or math.isclose(value, high, abs_tol=tolerance)
                   or abs((value - low) / step - round((value - low) / step)) * step <= tolerance)
        if not (inside and on_step):
            return f"Parameter {{{name}}} doesn't comply with {kind} range."
    return ""

