"""rclpy.node.Node over the lab's rosbridge endpoint.

A node makes its publishers, subscriptions, services, clients, timers and guard conditions
(rclpy.publisher, subscription, service, client, timer, guard_condition) in its callback groups (the
default one is mutually exclusive, as in rclpy); an executor runs their callbacks (rclpy/executors.py).
Parameters are declared with descriptors, checked as rclcpp checks them (type, read-only, ranges,
the on-set callbacks) and served with the standard rcl_interfaces services (rclpy/parameter_service.py).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from rosclient import process
from rclpy import _endpoints, _graph
from rclpy import context as _context
from rclpy.callback_groups import CallbackGroup, MutuallyExclusiveCallbackGroup
from rclpy.client import Client
from rclpy.clock import Clock
from rclpy.context import Context, default_context
from rclpy.exceptions import (
    InvalidParameterTypeException,
    InvalidParameterValueException,
    NotInitializedException,
    ParameterAlreadyDeclaredException,
    ParameterNotDeclaredException,
)
from rclpy.event_handler import (
    PublisherEventCallbacks,
    SubscriptionEventCallbacks,
    publisher_handlers,
    subscription_handlers,
    tell_incompatible,
)
from rclpy.guard_condition import GuardCondition
from rclpy.logging import RcutilsLogger, get_logger
from rclpy.parameter import Parameter, range_refusal
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile
from rclpy.service import Service
from rclpy.subscription import Subscription
from rclpy.timer import Rate, Timer
from rclpy.waitable import Waitable

if TYPE_CHECKING:
    from rclpy.executors import Executor


class Node:
    def __init__(self, node_name: str, *, context: Context | None = None, cli_args: list[str] | None = None,
                 namespace: str | None = None, use_global_arguments: bool = True, enable_rosout: bool = True,
                 start_parameter_services: bool = True, parameter_overrides: list[Parameter] | None = None,
                 allow_undeclared_parameters: bool = False,
                 automatically_declare_parameters_from_overrides: bool = False, enable_logger_service: bool = False,
                 **other: Any) -> None:
        from rclpy._arguments import arguments_for

        self._context = context or default_context()
        if not self._context.ok():
            raise NotInitializedException()
        if not node_name or "/" in node_name or not node_name.replace("_", "a").isalnum() or node_name[0].isdigit():
            raise ValueError(f"Invalid node name: {node_name!r} (letters, digits and underscores; not starting "
                             f"with a digit)")
        arguments = arguments_for(cli_args, use_global_arguments)
        self._name = arguments.remapped_name or node_name
        self._namespace = "/" + (namespace or arguments.namespace or "").strip("/")
        self._executor: Executor | None = None
        self.default_callback_group: CallbackGroup = MutuallyExclusiveCallbackGroup()
        self.callback_groups: list[CallbackGroup] = [self.default_callback_group]
        self.publishers: list[Publisher] = []
        self.subscriptions: list[Subscription] = []
        self.services: list[Service] = []
        self.clients: list[Client] = []
        self.timers: list[Timer] = []
        self.guards: list[GuardCondition] = []
        self.waitables: list[Waitable] = []
        self._parameters: dict[str, Parameter] = {}
        self._descriptors: dict[str, Any] = {}
        self._set_callbacks: list[Callable[..., Any]] = []
        self._pre_set_callbacks: list[Callable[[list[Parameter]], list[Parameter]]] = []
        self._post_set_callbacks: list[Callable[[list[Parameter]], None]] = []
        self._allow_undeclared = allow_undeclared_parameters
        self._overrides: dict[str, Any] = arguments.parameters_for(self.get_fully_qualified_name(), self._name)
        for parameter in parameter_overrides or []:
            self._overrides[parameter.name] = parameter.value
        self._logger = get_logger(self._name)
        self._clock = Clock()
        self._lock = threading.RLock()
        self._parameter_event_publisher: Publisher | None = None
        self._destroyed_parameter_events = False
        process.declare_node(self.get_fully_qualified_name())  # the name the lab shows (rosapi, errors, /rosout)
        if automatically_declare_parameters_from_overrides:
            for name, value in self._overrides.items():
                self.declare_parameter(name, value)
        if start_parameter_services:
            from rclpy.parameter_service import ParameterService

            self._parameter_service = ParameterService(self)
        if enable_logger_service:
            from rclpy.logging_service import LoggingService

            self._logging_service = LoggingService(self)

    @property
    def context(self) -> Context:
        return self._context

    @property
    def executor(self) -> Executor | None:
        return self._executor

    @executor.setter
    def executor(self, new_executor: Executor | None) -> None:
        current = self._executor
        if current is new_executor:
            return
        if current is not None:
            current.remove_node(self)
        self._executor = new_executor
        if new_executor is not None:
            new_executor.add_node(self)

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

    def resolve_service_name(self, service: str, *, only_expand: bool = False) -> str:
        return self.resolve_topic_name(service, only_expand=only_expand)

    def get_logger(self) -> RcutilsLogger:
        return self._logger

    def get_clock(self) -> Clock:
        return self._clock

    # --- entities ----------------------------------------------------------------------------
    def _group(self, callback_group: CallbackGroup | None) -> CallbackGroup:
        group = callback_group or self.default_callback_group
        if group not in self.callback_groups:
            self.callback_groups.append(group)
        return group

    def _added(self, kind: list[Any], entity: Any) -> Any:
        with _context.CONDITION:
            kind.append(entity)
        _context.wake()
        return entity

    def add_waitable(self, waitable: Waitable) -> None:
        self._added(self.waitables, waitable)

    def remove_waitable(self, waitable: Waitable) -> None:
        with _context.CONDITION:
            if waitable in self.waitables:
                self.waitables.remove(waitable)

    def create_publisher(self, msg_type: type, topic: str, qos_profile: QoSProfile | int, *,
                         callback_group: CallbackGroup | None = None, event_callbacks: Any = None,
                         **other: Any) -> Publisher:
        options = other.get("qos_overriding_options")
        if options is not None:  # the QoS as parameters (rclpy/qos_overriding_options.py)
            from rclpy.qos import profile
            from rclpy.qos_overriding_options import _declare_qos_parameters

            qos_profile = profile(qos_profile)
            _declare_qos_parameters("publisher", self, self.resolve_topic_name(topic), qos_profile, options)
        publisher = Publisher(self, msg_type, topic, qos_profile)
        self.publishers.append(publisher)
        publisher.event_handlers = publisher._endpoint.handlers = publisher_handlers(
            event_callbacks or PublisherEventCallbacks(), self._group(callback_group), topic, publisher._endpoint,
            self._logger.name)
        for handler in publisher.event_handlers:
            self.add_waitable(handler)
        tell_incompatible(publisher._incompatible + _endpoints.ready(publisher._endpoint))
        return publisher

    def create_subscription(self, msg_type: type, topic: str, callback: Callable[..., Any],
                            qos_profile: QoSProfile | int, *, callback_group: CallbackGroup | None = None,
                            event_callbacks: Any = None, raw: bool = False, **other: Any) -> Subscription:
        group = self._group(callback_group)
        options = other.get("qos_overriding_options")
        if options is not None:  # the QoS as parameters (rclpy/qos_overriding_options.py)
            from rclpy.qos import profile
            from rclpy.qos_overriding_options import _declare_qos_parameters

            qos_profile = profile(qos_profile)
            _declare_qos_parameters("subscription", self, self.resolve_topic_name(topic), qos_profile, options)
        subscription = self._added(self.subscriptions, Subscription(self, msg_type, topic, callback, qos_profile,
                                                                    group, raw))
        subscription.event_handlers = subscription._endpoint.handlers = subscription_handlers(
            event_callbacks or SubscriptionEventCallbacks(), group, topic, subscription._endpoint, self._logger.name)
        for handler in subscription.event_handlers:
            self.add_waitable(handler)
        tell_incompatible(subscription._incompatible + _endpoints.ready(subscription._endpoint))
        return subscription

    def create_service(self, srv_type: Any, srv_name: str, callback: Callable[..., Any], *,
                       qos_profile: QoSProfile | None = None, callback_group: CallbackGroup | None = None) -> Service:
        return self._added(self.services, Service(self, srv_type, srv_name, callback, self._group(callback_group)))

    def create_client(self, srv_type: Any, srv_name: str, *, qos_profile: QoSProfile | None = None,
                      callback_group: CallbackGroup | None = None) -> Client:
        return self._added(self.clients, Client(self, srv_type, srv_name, self._group(callback_group)))

    def create_timer(self, timer_period_sec: float, callback: Callable[..., Any] | None,
                     callback_group: CallbackGroup | None = None, clock: Any = None,
                     autostart: bool = True) -> Timer:
        return self._added(self.timers, Timer(callback, self._group(callback_group), int(timer_period_sec * 1e9),
                                              clock or self._clock, autostart=autostart))

    def create_guard_condition(self, callback: Callable[[], Any] | None,
                               callback_group: CallbackGroup | None = None) -> GuardCondition:
        return self._added(self.guards, GuardCondition(callback, self._group(callback_group)))

    def create_rate(self, frequency: float, clock: Any = None) -> Rate:
        return Rate(frequency, clock)

    def _removed(self, kind: list[Any], entity: Any) -> bool:
        with _context.CONDITION:
            if entity not in kind:
                return False
            kind.remove(entity)
        try:
            entity.destroy()
        except Exception:  # noqa: BLE001 - the connection may be going
            pass
        return True

    def destroy_publisher(self, publisher: Publisher) -> bool:
        self._drop_events(publisher)
        return self._removed(self.publishers, publisher)

    def destroy_subscription(self, subscription: Subscription) -> bool:
        self._drop_events(subscription)
        return self._removed(self.subscriptions, subscription)

    def _drop_events(self, entity: Publisher | Subscription) -> None:
        for handler in entity.event_handlers:
            self.remove_waitable(handler)
            handler.destroy()

    def destroy_service(self, service: Service) -> bool:
        return self._removed(self.services, service)

    def destroy_client(self, client: Client) -> bool:
        return self._removed(self.clients, client)

    def destroy_timer(self, timer: Timer) -> bool:
        return self._removed(self.timers, timer)

    def destroy_guard_condition(self, guard: GuardCondition) -> bool:
        return self._removed(self.guards, guard)

    def destroy_rate(self, rate: Rate) -> bool:
        return True

    def destroy_node(self) -> None:
        self._destroyed_parameter_events = True  # no parameter event makes its publisher again
        for timer in self.timers:
            timer.cancel()
        if process.connected() and not process.shutdown_event.is_set():
            sent: list[list[Any]] = [self.waitables, self.subscriptions, self.services, self.publishers, self.clients]
            for kind in sent:
                for entity in list(kind):
                    self._removed(kind, entity)
        with _context.CONDITION:
            held: list[list[Any]] = [self.waitables, self.timers, self.subscriptions, self.guards, self.clients,
                                     self.services]
            for entities in held:
                entities.clear()
        if self._executor is not None:
            self._executor.remove_node(self)

    def count_publishers(self, topic_name: str) -> int:
        """The publishers of the topic in the graph (rclpy/_graph.py)."""
        return _graph.count_publishers(self.resolve_topic_name(topic_name))

    def count_subscribers(self, topic_name: str) -> int:
        """The subscriptions of the topic in the graph (rclpy/_graph.py)."""
        return _graph.count_subscriptions(self.resolve_topic_name(topic_name))

    def get_node_names(self) -> list[str]:
        return [n.strip("/") for n in process.connection().call_service("/rosapi/nodes", {}).get("nodes", [])]

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        """Every service of the graph with its type, as ROS 2 names it (pkg/srv/Name), sorted."""
        return _graph.service_names_and_types()

    def get_topic_names_and_types(self, no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        """Every topic of the graph with its type, as ROS 2 names it (pkg/msg/Name), sorted."""
        return _graph.topic_names_and_types()

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        return [_graph.split_node(n) for n in _graph.node_names()]

    def get_node_names_and_namespaces_with_enclaves(self) -> list[tuple[str, str, str]]:
        return [(*_graph.split_node(n), "/") for n in _graph.node_names()]

    def get_fully_qualified_node_names(self) -> list[str]:
        return _graph.node_names()

    def get_publisher_names_and_types_by_node(self, node_name: str, node_namespace: str,
                                              no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        return _graph.by_node(node_name, node_namespace, "publishing")

    def get_subscriber_names_and_types_by_node(self, node_name: str, node_namespace: str,
                                               no_demangle: bool = False) -> list[tuple[str, list[str]]]:
        return _graph.by_node(node_name, node_namespace, "subscribing")

    def get_service_names_and_types_by_node(self, node_name: str, node_namespace: str) -> list[tuple[str, list[str]]]:
        return _graph.by_node(node_name, node_namespace, "services")

    def get_client_names_and_types_by_node(self, node_name: str, node_namespace: str) -> list[tuple[str, list[str]]]:
        return []  # the lab's graph does not know a node's clients

    def __enter__(self) -> Node:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy_node()

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
            reason = range_refusal(name, value, descriptor)
            if reason:
                raise InvalidParameterValueException(name, value, reason)
            parameter = Parameter(name, type_, value)
            result = self._run_callbacks([parameter])
            if not result.successful:
                raise InvalidParameterValueException(name, value, result.reason)
            self._parameters[name] = parameter
            self._descriptors[name] = descriptor
            declared.append(parameter)
        self._parameter_event(new=declared)
        return declared

    def _parameter_event(self, new: Sequence[Parameter] = (), changed: Sequence[Parameter] = (),
                         deleted: Sequence[Parameter] = ()) -> None:
        """rcl_interfaces/ParameterEvent on /parameter_events, as rclpy publishes it when parameters are
        declared, set or deleted (its publisher made with the node's first parameter, where rclpy
        makes it with the node: a node without parameters adds nothing to the graph)."""
        if not (new or changed or deleted) or self._destroyed_parameter_events:
            return
        from rcl_interfaces.msg import ParameterEvent

        if self._parameter_event_publisher is None:
            from rclpy.qos import qos_profile_parameter_events

            self._parameter_event_publisher = self.create_publisher(
                ParameterEvent, "/parameter_events", qos_profile_parameter_events)
        self._parameter_event_publisher.publish(ParameterEvent(
            stamp=self._clock.now().to_msg(), node=self.get_fully_qualified_name(),
            new_parameters=[p.to_parameter_msg() for p in new],
            changed_parameters=[p.to_parameter_msg() for p in changed],
            deleted_parameters=[p.to_parameter_msg() for p in deleted]))

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

    def add_pre_set_parameters_callback(self, callback: Callable[[list[Parameter]], list[Parameter]]) -> None:
        """`callback(parameters) -> parameters` before a set is checked: it may add or change some."""
        self._pre_set_callbacks.append(callback)

    def remove_pre_set_parameters_callback(self, callback: Callable[[list[Parameter]], list[Parameter]]) -> None:
        self._pre_set_callbacks.remove(callback)

    def add_post_set_parameters_callback(self, callback: Callable[[list[Parameter]], None]) -> None:
        """`callback(parameters)` once a set succeeded."""
        self._post_set_callbacks.append(callback)

    def remove_post_set_parameters_callback(self, callback: Callable[[list[Parameter]], None]) -> None:
        self._post_set_callbacks.remove(callback)

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
        on-set callbacks; all are set or none. The pre-set callbacks may change the list first (each
        one's list is added to the one checked, as rclpy does); the post-set ones hear of a success."""
        from rcl_interfaces.msg import SetParametersResult

        if self._pre_set_callbacks:
            parameters = [p for callback in self._pre_set_callbacks for p in callback(parameters)]
            if not parameters:
                return SetParametersResult(
                    successful=False,
                    reason="parameter list cannot be empty, this might be due to pre_set_parameters_callback "
                    "modifying the original parameters list.",
                )
        with self._lock:
            for parameter in parameters:
                reason = self._refusal(parameter)
                if reason:
                    return SetParametersResult(successful=False, reason=reason)
            result = self._run_callbacks(parameters)
            if not result.successful:
                return result
            event: dict[str, list[Parameter]] = {"new": [], "changed": [], "deleted": []}
            for parameter in parameters:
                if parameter.type_ == Parameter.Type.NOT_SET:
                    self._parameters.pop(parameter.name, None)
                    self._descriptors.pop(parameter.name, None)
                    event["deleted"].append(parameter)
                    continue
                event["changed" if parameter.name in self._parameters else "new"].append(parameter)
                if parameter.name not in self._descriptors:
                    from rcl_interfaces.msg import ParameterDescriptor

                    self._descriptors[parameter.name] = ParameterDescriptor(name=parameter.name,
                                                                            type=parameter.type_.value)
                self._parameters[parameter.name] = parameter
            self._parameter_event(**event)
        for post in self._post_set_callbacks:
            post(parameters)
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
        return range_refusal(name, parameter.value, descriptor)
