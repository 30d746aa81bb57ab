#!/usr/bin/env python3
"""ros2/examples' minimal action server: an `async def` execute callback that publishes the Fibonacci
sequence as feedback, one number a second (-p period:=...), on a MultiThreadedExecutor; goals are
accepted, cancels too unless `-p accept_cancel:=false`."""

import time

import rclpy
from example_interfaces.action import Fibonacci
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node


class MinimalActionServer(Node):
    def __init__(self):
        super().__init__("minimal_action_server")
        self.declare_parameter("accept_cancel", True)
        self.declare_parameter("period", 1.0)
        self._action_server = ActionServer(
            self,
            Fibonacci,
            "fibonacci",
            execute_callback=self.execute_callback,
            callback_group=ReentrantCallbackGroup(),
            goal_callback=self.goal_callback,
            cancel_callback=self.cancel_callback,
        )

    def destroy(self):
        self._action_server.destroy()
        super().destroy_node()

    def goal_callback(self, goal_request):
        self.get_logger().info("Received goal request")
        return GoalResponse.ACCEPT

    def cancel_callback(self, goal_handle):
        if self.get_parameter("accept_cancel").value:
            self.get_logger().info("Received cancel request: accepted")
            return CancelResponse.ACCEPT
        self.get_logger().info("Received cancel request: rejected")
        return CancelResponse.REJECT

    async def execute_callback(self, goal_handle):
        self.get_logger().info("Executing goal...")
        feedback_msg = Fibonacci.Feedback()
        feedback_msg.sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                self.get_logger().info("Goal canceled")
                return Fibonacci.Result()
            feedback_msg.sequence.append(feedback_msg.sequence[i] + feedback_msg.sequence[i - 1])
            self.get_logger().info("Publishing feedback: {0}".format(feedback_msg.sequence))
            goal_handle.publish_feedback(feedback_msg)
            time.sleep(self.get_parameter("period").value)
        goal_handle.succeed()
        result = Fibonacci.Result()
        result.sequence = feedback_msg.sequence
        self.get_logger().info("Returning result: {0}".format(result.sequence))
        return result


def main(args=None):
    try:
        with rclpy.init(args=args):
            minimal_action_server = MinimalActionServer()
            executor = MultiThreadedExecutor()
            rclpy.spin(minimal_action_server, executor=executor)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
