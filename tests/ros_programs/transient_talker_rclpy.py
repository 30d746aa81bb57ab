#!/usr/bin/env python3
"""A TRANSIENT_LOCAL publisher of depth 10 (ROS 2's QoS durability demo): it publishes 10 messages
at once, then stays: a subscriber that comes later hears all 10, as a DDS keeps them for it."""

import rclpy
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import String


def main():
    rclpy.init()
    node = rclpy.create_node("transient_talker")
    publisher = node.create_publisher(String, "kept", QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    for i in range(10):
        publisher.publish(String(data=f"message {i}"))
    node.get_logger().info("published 10")
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
