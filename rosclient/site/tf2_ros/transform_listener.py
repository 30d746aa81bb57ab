"""tf2_ros.TransformListener: fills a Buffer from /tf and /tf_static (the lab's frames and every
program's). rclpy's `TransformListener(buffer, node)` and ROS 1's `TransformListener(buffer)` both
work; the transforms reach the buffer as they arrive, whether or not the program spins (as rclpy's
listener with its own thread, and rospy's, do)."""

from __future__ import annotations

from typing import Any

from rosclient import process
from tf2_ros.buffer import Buffer

TYPE = "tf2_msgs/TFMessage"


class TransformListener:
    def __init__(self, buffer: Buffer, node: Any = None, *, spin_thread: bool = False, qos: Any = None,
                 static_qos: Any = None, **_: Any) -> None:
        self.buffer = buffer
        connection = process.connection()
        self._subscriptions = [
            (topic, connection.subscribe(topic, TYPE, buffer._offer_message)) for topic in ("/tf", "/tf_static")
        ]

    def unregister(self) -> None:
        connection = process.connection()
        for topic, sid in self._subscriptions:
            connection.unsubscribe(topic, sid, self.buffer._offer_message)
        self._subscriptions = []

    def __del__(self) -> None:
        pass
