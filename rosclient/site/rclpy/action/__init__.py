"""rclpy.action: ActionServer and ActionClient over rosbridge's ROS 2 action ops
(rosclient/actions.py), waitables of their node whose requests, feedback and results are taken
inside spin (rclpy/action/server.py, client.py)."""

from rclpy.action.client import ActionClient, ClientGoalHandle
from rclpy.action.server import ActionServer, CancelResponse, GoalResponse, ServerGoalHandle

__all__ = ["ActionClient", "ActionServer", "CancelResponse", "ClientGoalHandle", "GoalResponse", "ServerGoalHandle"]
