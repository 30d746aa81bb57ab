#!/usr/bin/env python3
"""A RELIABLE listener of qos_chatter, named by its first argument: prints "heard: DATA" for each
message, and its incompatible-QoS, liveliness-changed and matched events as the quality_of_service
demos print them, or (a second argument `--default`) leaves them to rclpy's default callbacks."""

import sys

import rclpy
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.node import Node
from rclpy.qos import QoSProfile
from std_msgs.msg import String


class Listener(Node):
    def __init__(self, name: str, default: bool):
        super().__init__(name)
        callbacks = (
            SubscriptionEventCallbacks()
            if default
            else SubscriptionEventCallbacks(
                incompatible_qos=self.incompatible, liveliness=self.liveliness, matched=self.matched
            )
        )
        self.create_subscription(
            String,
            "qos_chatter",
            lambda msg: print(f"heard: {msg.data}", flush=True),
            QoSProfile(depth=10),
            event_callbacks=callbacks,
        )
        print("listening", flush=True)

    def incompatible(self, event):
        print(
            f"Requested incompatible qos - total {event.total_count} delta {event.total_count_change} "
            f"last_policy_kind: {event.last_policy_kind}",
            flush=True,
        )

    def liveliness(self, event):
        print(
            f"liveliness alive={event.alive_count} change={event.alive_count_change} not_alive={event.not_alive_count}",
            flush=True,
        )

    def matched(self, event):
        print(f"matched current={event.current_count} change={event.current_count_change}", flush=True)


def main():
    args = rclpy.utilities.remove_ros_args(sys.argv)[1:]
    rclpy.init()
    try:
        rclpy.spin(Listener(args[0], "--default" in args))
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
