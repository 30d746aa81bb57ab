#!/usr/bin/env python3
"""ros2/examples' single-goal action server: a new goal aborts the one executing (in
handle_accepted_callback); the aborted goal's execute callback sees it is no longer active."""

import threading
import time

import rclpy
from example_interfaces.action import Fibonacci
from rclpy.action import ActionServer
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node


class MinimalActionServer(Node):
    def __init__(self):
        super().__init__("single_goal_action_server")
        self._goal_handle = None
        self._goal_lock = threading.Lock()
        self._action_server = ActionServer(
            self,
            Fibonacci,
            "fibonacci",
            execute_callback=self.execute_callback,
            handle_accepted_callback=self.handle_accepted_callback,
        )

    def handle_accepted_callback(self, goal_handle):
        with self._goal_lock:
            if self._goal_handle is not None and self._goal_handle.is_active:
                self.get_logger().info("Aborting previous goal")
                self._goal_handle.abort()
            self._goal_handle = goal_handle
        goal_handle.execute()

    def execute_callback(self, goal_handle):
        self.get_logger().info("Executing goal of order %d" % goal_handle.request.order)
        sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            if not goal_handle.is_active:
                self.get_logger().info("Goal aborted")
                return Fibonacci.Result()
            sequence.append(sequence[i] + sequence[i - 1])
            goal_handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
            time.sleep(0.2)
        with self._goal_lock:
            if not goal_handle.is_active:
                return Fibonacci.Result()
            goal_handle.succeed()
        return Fibonacci.Result(sequence=sequence)


def main(args=None):
    try:
        with rclpy.init(args=args):
            rclpy.spin(MinimalActionServer(), executor=MultiThreadedExecutor())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
