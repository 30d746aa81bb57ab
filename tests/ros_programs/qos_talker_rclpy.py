#!/usr/bin/env python3
"""A talker whose QoS reliability is its second argument (`reliable` or `best_effort`), as the
incompatible_qos demo of ros2/demos sets it, named by its first argument: it publishes "NAME N"
on qos_chatter every 0.1 s and prints "published N"; its incompatible-QoS and matched events are
printed as the demo prints them, or (a third argument `--default`) left to rclpy's default callbacks."""

import sys

import rclpy
from rclpy.event_handler import PublisherEventCallbacks
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from std_msgs.msg import String


class Talker(Node):
    def __init__(self, name: str, reliability: str, default: bool):
        super().__init__(name)
        qos = QoSProfile(depth=10, reliability=ReliabilityPolicy[reliability.upper()])
        callbacks = (
            PublisherEventCallbacks()
            if default
            else PublisherEventCallbacks(incompatible_qos=self.incompatible, matched=self.matched)
        )
        self.publisher = self.create_publisher(String, "qos_chatter", qos, event_callbacks=callbacks)
        self.count = 0
        self.create_timer(0.1, self.publish)

    def publish(self):
        self.publisher.publish(String(data=f"{self.get_name()} {self.count}"))
        print(f"published {self.count}", flush=True)
        self.count += 1

    def incompatible(self, event):
        print(
            f"Offered incompatible qos - total {event.total_count} delta {event.total_count_change} "
            f"last_policy_kind: {event.last_policy_kind}",
            flush=True,
        )

    def matched(self, event):
        print(f"matched current={event.current_count} change={event.current_count_change}", flush=True)


def main():
    args = rclpy.utilities.remove_ros_args(sys.argv)[1:]
    rclpy.init()
    try:
        rclpy.spin(Talker(args[0], args[1], "--default" in args))
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
