#!/usr/bin/env python3
"""ROS 2 Rolling's minimal subscriber, as ros2/examples writes it: `with rclpy.init():`, prints what
it hears on `topic`; SIGTERM (as a launch system stops it) is an ExternalShutdownException."""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import String


class MinimalSubscriber(Node):
    def __init__(self):
        super().__init__("minimal_subscriber")
        self.subscription = self.create_subscription(String, "topic", self.listener_callback, 10)
        self.subscription  # prevent unused variable warning

    def listener_callback(self, msg):
        self.get_logger().info('I heard: "%s"' % msg.data)


def main(args=None):
    try:
        with rclpy.init(args=args):
            minimal_subscriber = MinimalSubscriber()
            rclpy.spin(minimal_subscriber)
    except (KeyboardInterrupt, ExternalShutdownException):
        print("listener: shut down cleanly", flush=True)


if __name__ == "__main__":
    main()
