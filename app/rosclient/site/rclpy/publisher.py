"""rclpy.publisher.Publisher: advertises its topic to the lab once, publishes messages of its type."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from app.rosclient import process
from app.interfaces.messages import Message
from rclpy.qos import QoSProfile, profile

if TYPE_CHECKING:
    from rclpy.node import Node


def type_name(cls: Any) -> str:
    """The ROS 2 type name of a message, service or action class ('pkg/msg/Name')."""
    return str(getattr(cls, "_ros2_type", "") or cls._type)


class Publisher:
    def __init__(self, node: Node, msg_type: type, topic: str, qos: QoSProfile | int) -> None:
        if not (isinstance(msg_type, type) and issubclass(msg_type, Message)):
            raise TypeError(f"create_publisher: msg_type must be a message class, got {msg_type!r}")
        self.node, self.msg_type, self.qos_profile = node, msg_type, profile(qos)
        self.topic_name = node.resolve_topic_name(topic)
        self.type = type_name(msg_type)
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

    def wait_for_all_acked(self, timeout: Any = None) -> bool:
        return True

    def assert_liveliness(self) -> None:
        pass

    def destroy(self) -> None:
        process.connection().send({"op": "unadvertise", "topic": self.topic_name})
