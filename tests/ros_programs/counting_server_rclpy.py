"""The counting action (rclpy, the workspace's cpp_package/Counting.action): counts to the goal, one
number per `delay` parameter (default 1 s), with feedback; cancellable."""

import time

import rclpy
from cpp_package.action import Counting
from rclpy.action import ActionServer, CancelResponse
from rclpy.node import Node


class CountingServer(Node):
    def __init__(self):
        super().__init__("counting_server")
        self.declare_parameter("delay", 1.0)
        self._server = ActionServer(
            self, Counting, "counting", self.execute, cancel_callback=lambda goal: CancelResponse.ACCEPT
        )
        self.get_logger().info("counting server ready")

    def execute(self, goal_handle):
        feedback, result = Counting.Feedback(), Counting.Result()
        for _ in range(goal_handle.request.count):
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                self.get_logger().info("counting preempted at %d" % feedback.current)
                result.reached = feedback.current
                return result
            time.sleep(self.get_parameter("delay").value)
            feedback.current += 1
            goal_handle.publish_feedback(feedback)
        goal_handle.succeed()
        result.reached = feedback.current
        return result


def main():
    rclpy.init()
    node = CountingServer()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
