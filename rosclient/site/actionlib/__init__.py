"""actionlib (ROS 1) laid out as actionlib is: action_server.py and server_goal_handle.py (a
program's action server: the action's ROS 1 topics and the lab's action ops), simple_action_server.py,
action_client.py and simple_action_client.py (goals through the lab's action ops), spec.py (an
ActionSpec's classes)."""

from actionlib.action_client import ActionClient, ClientGoalHandle, CommState, get_name_of_constant
from actionlib.action_server import ActionServer, nop_cb
from actionlib.server_goal_handle import ServerGoalHandle
from actionlib.simple_action_client import SimpleActionClient, SimpleGoalState
from actionlib.simple_action_server import SimpleActionServer
from actionlib_msgs.msg import GoalStatus

__all__ = [
    "ActionClient",
    "ActionServer",
    "ClientGoalHandle",
    "CommState",
    "GoalStatus",
    "ServerGoalHandle",
    "SimpleActionClient",
    "SimpleActionServer",
    "SimpleGoalState",
    "get_name_of_constant",
    "nop_cb",
]
