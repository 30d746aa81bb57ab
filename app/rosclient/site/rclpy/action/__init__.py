"""rclpy.action: ActionServer and ActionClient over rosbridge's ROS 2 action ops
(app/rosclient/actions.py). A goal's execute callback runs on a thread of its own (so a cancel
request reaches it while it sleeps); the client's futures and feedback callbacks complete inside
spin, as in rclpy."""
from rclpy.action.client import ActionClient, ClientGoalHandle
from rclpy.action.server import ActionServer, CancelResponse, GoalResponse, ServerGoalHandle

__all__ = ["ActionClient", "ActionServer", "CancelResponse", "ClientGoalHandle", "GoalResponse", "ServerGoalHandle"]
