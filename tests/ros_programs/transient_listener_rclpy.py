#!/usr/bin/env python3
"""A late subscriber of `kept`: a TRANSIENT_LOCAL subscription of depth 10 hears what the publisher
kept, a VOLATILE one of the same topic nothing of it."""

import rclpy
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import String


def main():
    rclpy.init()
    node = rclpy.create_node("transient_listener")
    kept, fresh = [], []
    node.create_subscription(String, "kept", fresh.append, 10)  # VOLATILE: rclpy's default
    node.create_subscription(
        String, "kept", kept.append, QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    )
    while len(kept) < 10 and rclpy.ok():
        rclpy.spin_once(node, timeout_sec=1.0)
    for _ in range(3):  # anything else that was coming
        rclpy.spin_once(node, timeout_sec=0.1)
    print("transient_local heard:", ", ".join(m.data for m in kept), flush=True)
    print("volatile heard", len(fresh), flush=True)
    rclpy.shutdown()


if __name__ == "__main__":
    main()
