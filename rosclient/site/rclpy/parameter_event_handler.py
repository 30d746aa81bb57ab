"""rclpy.parameter_event_handler (as rclpy has it since Iron): a subscription to /parameter_events
(the rcl_interfaces/ParameterEvent every node publishes when its parameters are declared, set or
deleted: rclpy/node.py) that calls, newest first, the callbacks of one node's parameter with its
rcl_interfaces/Parameter message, and the callbacks of every event."""

from __future__ import annotations

import threading
from collections import defaultdict
from collections.abc import Callable, Iterable, Iterator
from itertools import chain
from typing import TYPE_CHECKING, Any

from rclpy.qos import QoSProfile, qos_profile_parameter_events

if TYPE_CHECKING:
    from rclpy.callback_groups import CallbackGroup
    from rclpy.node import Node


class ParameterCallbackHandle:
    def __init__(self, parameter_name: str, node_name: str, callback: Callable[[Any], None]) -> None:
        self.parameter_name, self.node_name, self.callback = parameter_name, node_name, callback
        self.mutex = threading.Lock()


class ParameterEventCallbackHandle:
    def __init__(self, callback: Callable[[Any], None]) -> None:
        self.callback = callback
        self.mutex = threading.Lock()


class ParameterEventHandler:
    class Callbacks:
        def __init__(self) -> None:
            self.parameter_callbacks: dict[tuple[str, str], list[ParameterCallbackHandle]] = defaultdict(list)
            self.event_callbacks: list[ParameterEventCallbackHandle] = []
            self.mutex = threading.RLock()

        def event_callback(self, event: Any) -> None:
            with self.mutex:
                for (param_name, node_name), handles in list(self.parameter_callbacks.items()):
                    parameter = ParameterEventHandler.get_parameter_from_event(event, param_name, node_name)
                    if parameter:
                        for handle in list(handles):
                            with handle.mutex:
                                handle.callback(parameter)
                for event_handle in list(self.event_callbacks):
                    with event_handle.mutex:
                        event_handle.callback(event)

        def add_parameter_callback(self, parameter_name: str, node_name: str,
                                   callback: Callable[[Any], None]) -> ParameterCallbackHandle:
            handle = ParameterCallbackHandle(parameter_name, node_name, callback)
            with self.mutex:
                self.parameter_callbacks[(parameter_name, node_name)].insert(0, handle)
            return handle

        def remove_parameter_callback(self, handle: ParameterCallbackHandle) -> None:
            with self.mutex:
                key = (handle.parameter_name, handle.node_name)
                if handle not in self.parameter_callbacks.get(key, []):
                    raise RuntimeError("Callback doesn't exist")
                self.parameter_callbacks[key].remove(handle)
                if not self.parameter_callbacks[key]:
                    self.parameter_callbacks.pop(key)

        def add_parameter_event_callback(self, callback: Callable[[Any], None]) -> ParameterEventCallbackHandle:
            handle = ParameterEventCallbackHandle(callback)
            with self.mutex:
                self.event_callbacks.insert(0, handle)
            return handle

        def remove_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> None:
            with self.mutex:
                if handle not in self.event_callbacks:
                    raise RuntimeError("Callback doesn't exist")
                self.event_callbacks.remove(handle)

    def __init__(self, node: Node, qos_profile: QoSProfile | int = qos_profile_parameter_events,
                 callback_group: CallbackGroup | None = None, event_callbacks: Any = None,
                 qos_overriding_options: Any = None, raw: bool = False) -> None:
        from rcl_interfaces.msg import ParameterEvent

        self.node, self.qos_profile = node, qos_profile
        self._callbacks = ParameterEventHandler.Callbacks()
        self.parameter_event_subscription = node.create_subscription(
            ParameterEvent, "/parameter_events", self._callbacks.event_callback, qos_profile,
            callback_group=callback_group, event_callbacks=event_callbacks,
            qos_overriding_options=qos_overriding_options, raw=raw)

    def destroy(self) -> None:
        self.node.destroy_subscription(self.parameter_event_subscription)

    @staticmethod
    def get_parameter_from_event(event: Any, parameter_name: str, node_name: str) -> Any:
        """The rcl_interfaces/Parameter of `parameter_name` new or changed in `event` of node `node_name`; None."""
        if event.node == node_name:
            for parameter in chain(event.new_parameters, event.changed_parameters):
                if parameter.name == parameter_name:
                    return parameter
        return None

    @staticmethod
    def get_parameters_from_event(event: Any) -> Iterable[Any]:
        parameters: Iterator[Any] = chain(event.new_parameters, event.changed_parameters)
        yield from parameters

    def add_parameter_callback(self, parameter_name: str, node_name: str,
                               callback: Callable[[Any], None]) -> ParameterCallbackHandle:
        return self._callbacks.add_parameter_callback(parameter_name, self._resolve_path(node_name), callback)

    def remove_parameter_callback(self, handle: ParameterCallbackHandle) -> None:
        self._callbacks.remove_parameter_callback(handle)

    def add_parameter_event_callback(self, callback: Callable[[Any], None]) -> ParameterEventCallbackHandle:
        return self._callbacks.add_parameter_event_callback(callback)

    def remove_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> None:
        self._callbacks.remove_parameter_event_callback(handle)

    def _resolve_path(self, node_path: str | None = None) -> str:
        """A node's full name: its own node's when none is given, in its namespace when relative."""
        if not node_path:
            return self.node.get_fully_qualified_name()
        if node_path.startswith("/"):
            return node_path
        resolved = "/".join([self.node.get_namespace().lstrip("/"), node_path])
        return resolved if resolved.startswith("/") else f"/{resolved}"
