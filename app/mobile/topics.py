"""The mobile world's topics (sim/mobile/messages.py) as the server serves them, with the robot's
URDF on /robot_description (std_msgs/String, latched as robot_state_publisher's) and the trial's
monitor on /wall_following; how often each is sent at most (s)."""

from __future__ import annotations

from sim.messages import Topic, header_at
from sim.mobile.messages import CMD_VEL
from sim.mobile.messages import TOPICS as MOBILE_TOPICS
from sim.mobile.urdf import burger_urdf
from sim.mobile.world import MobileSnapshot

ROBOT_DESCRIPTION = "/robot_description"
COMMAND_TOPIC = CMD_VEL


def wall_following(s: MobileSnapshot) -> dict:
    """The wall-following trial's state (sim/mobile/monitor.py), judged from the true pose."""
    w = s.wall
    return {
        "header": header_at(s.time, "odom"),
        "elapsed": w.elapsed,
        "distance": w.distance,
        "circuit_deg": w.circuit * 57.29577951308232,
        "outside_band": w.outside_band,
        "contact": s.contact,
        "done": w.done,
        "passed": w.passed,
        "verdict": w.verdict or "",
    }


def clock(s: MobileSnapshot) -> dict:
    """rosgraph_msgs/Clock: the simulated time, as Gazebo publishes it (for `use_sim_time`)."""
    return {"clock": header_at(s.time, "")["stamp"]}


def pose_2d(s: MobileSnapshot) -> dict:
    """The base's true pose in the arena (geometry_msgs/Pose2D): Gazebo's ground truth."""
    return {"x": float(s.pose[0]), "y": float(s.pose[1]), "theta": float(s.pose[2])}


TOPICS = [
    *MOBILE_TOPICS,
    Topic(ROBOT_DESCRIPTION, "std_msgs/String", lambda s: {"data": burger_urdf()}),
    Topic("/ground_truth_pose", "geometry_msgs/Pose2D", pose_2d),
    Topic("/wall_following", "hri_lab/WallFollowing", wall_following),
    Topic("/clock", "rosgraph_msgs/Clock", clock),
]
# at most this often to one subscriber (s): turtlebot3_node's odometry and joint states at 30 Hz
MIN_PERIOD_S = {
    "/scan": 0.05,
    "/odom": 1 / 30,
    "/joint_states": 1 / 30,
    "/tf": 1 / 30,
    "/tf_static": 0.1,
    ROBOT_DESCRIPTION: 1.0,
    "/clock": 0.01,
}
# sent only when the message changed: each scan once (5 Hz), the latched ones (transient local)
LATCHED = {"/scan", "/tf_static", ROBOT_DESCRIPTION}
