"""Lifespan (rclpy), as ros2/demos' lifespan demo: two TRANSIENT_LOCAL publishers each publish three
messages, one with a lifespan of 0.2 s, one of an hour; once 0.2 s have passed since the lab had
them (a volatile subscription heard the short-lived ones back), a late TRANSIENT_LOCAL subscription
of each topic prints what it hears (the short-lived ones are gone); the node then stays up for
`topic info -v`."""

import time

import rclpy
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import String

SHORT_S = 0.2


class Lifespan(Node):
    def __init__(self):
        super().__init__("lifespan_talker")
        self.echoes: list[float] = []  # when the lab relayed each short-lived message back
        self.create_subscription(String, "short_lived", lambda m: self.echoes.append(time.monotonic()), 10)
        for topic, seconds in (("short_lived", SHORT_S), ("long_lived", 3600.0)):
            qos = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL, lifespan=Duration(seconds=seconds))
            publisher = self.create_publisher(String, topic, qos)
            for i in range(3):
                publisher.publish(String(data=f"{topic} {i}"))
        self.late = self.create_timer(0.05, self.subscribe_late)

    def subscribe_late(self):
        if len(self.echoes) < 3 or time.monotonic() < self.echoes[-1] + SHORT_S:
            return
        self.destroy_timer(self.late)
        qos = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        for topic in ("short_lived", "long_lived"):
            self.create_subscription(String, topic, lambda m: print(f"heard: {m.data}", flush=True), qos)
        print("late subscriptions made", flush=True)


def main():
    rclpy.init()
    try:
        rclpy.spin(Lifespan())
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
