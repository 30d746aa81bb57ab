"""tf2_ros.TransformBroadcaster: a program's transforms on /tf join the lab's tree (a frame of the
lab's own is refused with the reason: docs/ros-programs.md). rclpy's `TransformBroadcaster(node)` and
ROS 1's `TransformBroadcaster()`; `sendTransform` takes one geometry_msgs/TransformStamped or a list."""

from __future__ import annotations

from typing import Any

from rosclient import process

TYPE = "tf2_msgs/TFMessage"


def _json(transforms: Any) -> list[dict]:
    items = transforms if isinstance(transforms, (list, tuple)) else [transforms]
    for item in items:
        if not hasattr(item, "to_json") or getattr(item, "_type", "").split("/")[-1] != "TransformStamped":
            raise TypeError(f"sendTransform takes geometry_msgs/TransformStamped (or a list of them), got {item!r}")
    return [item.to_json() for item in items]


class TransformBroadcaster:
    TOPIC = "/tf"

    def __init__(self, node: Any = None, qos: Any = None, **_: Any) -> None:
        process.advertise_once(self.TOPIC, TYPE)

    def sendTransform(self, transform: Any) -> None:  # noqa: N802 - tf2_ros' name
        process.publish(self.TOPIC, TYPE, {"transforms": _json(transform)})

    send_transform = sendTransform
