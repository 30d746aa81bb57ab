#!/usr/bin/env python3
"""ros2/examples' queued action server: goals are accepted as they come and executed one after the
other (handle_accepted_callback queues them; the execute callback starts the next when it ends)."""

import collections
import threading
import time

import rclpy
from example_interfaces.action import Fibonacci
from rclpy.action import ActionServer
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node


class MinimalActionServer(Node):
    def __init__(self):
        super().__init__("queue_action_server")
        self._goal_queue = collections.deque()
        self._goal_queue_lock = threading.Lock()
        self._current_goal = None
        self._action_server = ActionServer(
            self,
            Fibonacci,
            "fibonacci",
            handle_accepted_callback=self.handle_accepted_callback,
            execute_callback=self.execute_callback,
        )

    def handle_accepted_callback(self, goal_handle):
        with self._goal_queue_lock:
            if self._current_goal is not None:
                self._goal_queue.append(goal_handle)
                self.get_logger().info("Goal put in the queue")
            else:
                self._current_goal = goal_handle
                self._current_goal.execute()

    def execute_callback(self, goal_handle):
        try:
            self.get_logger().info("Executing goal of order %d" % goal_handle.request.order)
            sequence = [0, 1]
            for i in range(1, goal_handle.request.order):
                sequence.append(sequence[i] + sequence[i - 1])
                goal_handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
                time.sleep(0.1)
            goal_handle.succeed()
            self.get_logger().info("Returning result of order %d" % goal_handle.request.order)
            return Fibonacci.Result(sequence=sequence)
        finally:
            with self._goal_queue_lock:
                try:
                    self._current_goal = self._goal_queue.popleft()
                    self._current_goal.execute()
                except IndexError:
                    self._current_goal = None


def main(args=None):
    try:
        with rclpy.init(args=args):
            rclpy.spin(MinimalActionServer(), executor=MultiThreadedExecutor())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
