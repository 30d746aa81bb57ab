#!/usr/bin/env python3
"""The ROS 2 tf2 tutorials' listener: looks up `plate_marker` in `panda_link0` (a program's static
frame below the lab's plate) and `carrot` in `plate_marker` every 0.5 s and prints them."""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.time import Time
from tf2_ros import TransformException
from tf2_ros.buffer import Buffer
from tf2_ros.transform_listener import TransformListener


class FrameListener(Node):
    def __init__(self):
        super().__init__("frame_listener")
        self.tf_buffer = Buffer()
        self.tf_listener = TransformListener(self.tf_buffer, self)
        self.timer = self.create_timer(0.5, self.on_timer)

    def on_timer(self):
        try:
            marker = self.tf_buffer.lookup_transform("panda_link0", "plate_marker", Time())
            carrot = self.tf_buffer.lookup_transform("plate_marker", "carrot", Time())
        except TransformException as ex:
            self.get_logger().info(f"Could not transform: {ex}")
            return
        m, c = marker.transform.translation, carrot.transform.translation
        print(f"plate_marker in panda_link0: {m.x:.4f} {m.y:.4f} {m.z:.4f}", flush=True)
        print(f"carrot radius: {(c.x**2 + c.y**2) ** 0.5:.4f}", flush=True)


def main():
    try:
        with rclpy.init():
            rclpy.spin(FrameListener())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
