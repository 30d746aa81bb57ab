"""rclpy.publisher.Publisher: advertises its topic to the lab once, publishes messages of its type."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from rosclient import process
from interfaces.messages import Message
from rclpy import _endpoints, _graph
from rclpy import context as _context
from rclpy.qos import DurabilityPolicy, QoSProfile, profile

if TYPE_CHECKING:
    from rclpy.node import Node


def type_name(cls: Any) -> str:
    """The ROS 2 type name of a message, service or action class ('pkg/msg/Name')."""
    return str(getattr(cls, "_ros2_type", "") or cls._type)


def kept_for_late_joiners(qos: QoSProfile) -> int:
    """The messages a TRANSIENT_LOCAL publisher keeps for a late subscription: its history depth
    (KEEP_ALL: all, which the lab caps: app/rosbridge/capabilities/advertise.py); none for VOLATILE."""
    if qos.durability != DurabilityPolicy.TRANSIENT_LOCAL:
        return 0
    return qos.queue_length or sys.maxsize


class Publisher:
    def __init__(self, node: Node, msg_type: type, topic: str, qos: QoSProfile | int) -> None:
        if not (isinstance(msg_type, type) and issubclass(msg_type, Message)):
            raise TypeError(f"create_publisher: msg_type must be a message class, got {msg_type!r}")
        self.node, self.msg_type, self.qos_profile = node, msg_type, profile(qos)
        self.topic_name = node.resolve_topic_name(topic)
        self.type = type_name(msg_type)
        self._destroyed = False
        self._endpoint = _endpoints.Endpoint(self.topic_name, self.qos_profile, True, node.get_fully_qualified_name())
        self._incompatible = _endpoints.add(self._endpoint)  # told once its handlers are made (node.py)
        _graph.add_publisher(self.topic_name, self.type, msg_type, kept_for_late_joiners(self.qos_profile),
                             self.qos_profile.lifespan.nanoseconds / 1e9)
        self.event_handlers: list[Any] = []  # rclpy/event_handler.py

    @property
    def topic(self) -> str:
        return self.topic_name

    def publish(self, msg: Any) -> None:
        if not isinstance(msg, self.msg_type):
            raise TypeError(f"Expected {self.msg_type.__module__}.{self.msg_type.__name__}, got {type(msg)}")
        self._endpoint.message()
        process.publish(self.topic_name, self.type, msg.to_json())

    def get_subscription_count(self) -> int:
        """rmw's count of the subscriptions matched to it: its topic's compatible ones (rclpy/_endpoints.py)."""
        return _endpoints.matched(self._endpoint)

    def wait_for_all_acked(self, timeout: Any = None) -> bool:
        return True

    def assert_liveliness(self) -> None:
        """A MANUAL_BY_TOPIC publisher alive for its lease again (rclpy/event_handler.py)."""
        self._endpoint.assert_liveliness()
        _context.wake()

    def destroy(self) -> None:
        """The topic is unadvertised when no other publisher of it is left in the program."""
        if not self._destroyed:
            self._destroyed = True
            _graph.remove_publisher(self.topic_name)  # as it was made, in reverse (subscription.py's destroy)
            _endpoints.remove(self._endpoint)
