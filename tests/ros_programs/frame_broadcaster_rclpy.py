#!/usr/bin/env python3
"""The ROS 2 tf2 tutorials' broadcasters in one node: a static frame `plate_marker` 5 cm in front of
the lab's `plate`, and a dynamic frame `carrot` circling `plate_marker` (0.1 m, 1 rad/s), sent at
20 Hz; with `--ros-args -p steal:=true` it also sends the lab's `box` frame (refused by the lab)."""

import math

import rclpy
from geometry_msgs.msg import TransformStamped
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from tf2_ros import StaticTransformBroadcaster, TransformBroadcaster


class FramePublisher(Node):
    def __init__(self):
        super().__init__("frame_publisher")
        self.declare_parameter("steal", False)
        self.tf_static_broadcaster = StaticTransformBroadcaster(self)
        self.tf_broadcaster = TransformBroadcaster(self)
        marker = TransformStamped()
        marker.header.stamp = self.get_clock().now().to_msg()
        marker.header.frame_id = "plate"
        marker.child_frame_id = "plate_marker"
        marker.transform.translation.z = 0.05
        marker.transform.rotation.w = 1.0
        self.tf_static_broadcaster.sendTransform(marker)
        self.timer = self.create_timer(0.05, self.broadcast_timer_callback)
        self.get_logger().info("frames ready")

    def broadcast_timer_callback(self):
        seconds = self.get_clock().now().nanoseconds / 1e9
        t = TransformStamped()
        t.header.stamp = self.get_clock().now().to_msg()
        t.header.frame_id = "plate_marker"
        t.child_frame_id = "carrot"
        t.transform.translation.x = 0.1 * math.sin(seconds)
        t.transform.translation.y = 0.1 * math.cos(seconds)
        t.transform.rotation.w = 1.0
        transforms = [t]
        if self.get_parameter("steal").value:
            stolen = TransformStamped()
            stolen.header.frame_id = "panda_link0"
            stolen.child_frame_id = "box"
            stolen.transform.rotation.w = 1.0
            transforms.append(stolen)
        self.tf_broadcaster.sendTransform(transforms)


def main():
    try:
        with rclpy.init():
            rclpy.spin(FramePublisher())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
