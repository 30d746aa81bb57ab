"""An rclpy action client of the lab's /count: counts to 2 with feedback."""

import rclpy
from hri_lab.action import Count
from rclpy.action import ActionClient
from rclpy.node import Node


class CountClient(Node):
    def __init__(self):
        super().__init__("count_client")
        self._client = ActionClient(self, Count, "count")

    def send_goal(self, count):
        goal = Count.Goal()
        goal.count = count
        self._client.wait_for_server()
        return self._client.send_goal_async(goal, feedback_callback=self.feedback_callback)

    def feedback_callback(self, feedback_msg):
        self.get_logger().info("Received feedback: {0}".format(feedback_msg.feedback.current_number))


def main():
    rclpy.init()
    node = CountClient()
    future = node.send_goal(2)
    rclpy.spin_until_future_complete(node, future)
    goal_handle = future.result()
    if not goal_handle.accepted:
        node.get_logger().info("Goal rejected")
        return
    result_future = goal_handle.get_result_async()
    rclpy.spin_until_future_complete(node, result_future)
    print(
        "Result: final_count {0}, status {1}".format(
            result_future.result().result.final_count, result_future.result().status
        ),
        flush=True,
    )
    rclpy.shutdown()


if __name__ == "__main__":
    main()
