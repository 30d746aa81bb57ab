#!/usr/bin/env python3
"""A MultiThreadedExecutor with the callback groups of ROS 2's executors tutorial: two timers in one
MutuallyExclusiveCallbackGroup, each callback 0.2 s long, never run at once; a service in a
ReentrantCallbackGroup is answered while they run. Prints how many of the group's callbacks ran at
the same time, at most, when it is called."""

import threading
import time

import rclpy
from example_interfaces.srv import Trigger
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node


class GroupsNode(Node):
    def __init__(self):
        super().__init__("groups_node")
        exclusive = MutuallyExclusiveCallbackGroup()
        self.lock = threading.Lock()
        self.running = 0
        self.most = 0
        self.calls = 0
        self.timer_a = self.create_timer(0.05, self.slow_callback, callback_group=exclusive)
        self.timer_b = self.create_timer(0.05, self.slow_callback, callback_group=exclusive)
        self.create_service(Trigger, "group_report", self.report, callback_group=ReentrantCallbackGroup())
        self.get_logger().info("groups ready")

    def slow_callback(self):
        with self.lock:
            self.running += 1
            self.most = max(self.most, self.running)
            self.calls += 1
        time.sleep(0.2)
        with self.lock:
            self.running -= 1

    def report(self, request, response):
        with self.lock:
            response.success = True
            response.message = "exclusive group: %d callbacks, at most %d at once" % (self.calls, self.most)
        return response


def main(args=None):
    rclpy.init(args=args)
    node = GroupsNode()
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    try:
        executor.spin()
    except KeyboardInterrupt:
        pass
    executor.shutdown()
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
