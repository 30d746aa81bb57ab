"""The mobile world's topics as ROS messages of a MobileSnapshot (as TurtleBot3's bringup and its
Gazebo world publish them): /scan, /odom, /tf (odom -> base_footprint), /tf_static
(base_footprint -> base_link -> base_scan, the wheels' links), /joint_states of the wheels,
/clock; and Gazebo's ground truth (/ground_truth_pose), the twist the base follows
(/cmd_vel_followed) and the grader's monitor (/wall_following). The lab subscribes to /cmd_vel
and never publishes it (as Gazebo's diff-drive plugin): `topic info /cmd_vel` names only the nodes
that drive the base. The live server serves them (app/mobile/) and
recordings store them.

The frames: `odom` is the arena's frame, where the odometry starts at the robot's true start pose;
base_footprint's pose in it is the odometry's (which drifts from the true pose: sim/mobile/base.py).
"""

from __future__ import annotations

import math

from sim.messages import Topic, header_at
from sim.mobile.base import BaseSpec
from sim.mobile.lidar import LidarSpec
from sim.mobile.world import MobileSnapshot

ODOM, FOOTPRINT, BASE_LINK, SCAN_FRAME = "odom", "base_footprint", "base_link", "base_scan"
WHEEL_JOINTS = ("wheel_left_joint", "wheel_right_joint")
WHEEL_LINKS = ("wheel_left_link", "wheel_right_link")
BASE_LINK_HEIGHT = 0.010  # m, base_link above base_footprint (turtlebot3_burger.urdf)
WHEEL_Z = 0.023  # m, the wheels' axle above base_link
SCAN, ODOM_TOPIC, CMD_VEL = "/scan", "/odom", "/cmd_vel"
FOLLOWED = "/cmd_vel_followed"  # the twist the base follows: the lab's, beside the nodes' /cmd_vel

_BASE, _LIDAR = BaseSpec(), LidarSpec()


def _quaternion_z(yaw: float) -> dict:
    return {"x": 0.0, "y": 0.0, "z": math.sin(0.5 * yaw), "w": math.cos(0.5 * yaw)}


def _stamp(header: dict, zero: bool) -> dict:
    if zero:
        header["stamp"] = {"sec": 0, "nanosec": 0}
    return header


def laser_scan(s: MobileSnapshot) -> dict:
    """sensor_msgs/LaserScan of the latest scan, in base_scan, stamped when it was taken."""
    inc = _LIDAR.angle_increment
    return {
        "header": header_at(s.scan_time, SCAN_FRAME),
        "angle_min": 0.0,
        "angle_max": (_LIDAR.rays - 1) * inc,
        "angle_increment": inc,
        "time_increment": 1.0 / (_LIDAR.rate_hz * _LIDAR.rays),
        "scan_time": 1.0 / _LIDAR.rate_hz,
        "range_min": _LIDAR.range_min,
        "range_max": _LIDAR.range_max,
        "ranges": s.scan_ranges.tolist(),
        "intensities": [],
    }


def _pose_message(pose) -> dict:
    return {
        "position": {"x": float(pose[0]), "y": float(pose[1]), "z": 0.0},
        "orientation": _quaternion_z(float(pose[2])),
    }


def odometry(s: MobileSnapshot) -> dict:
    """nav_msgs/Odometry: the odometry's pose of base_footprint in odom, its twist in base_footprint."""
    return {
        "header": header_at(s.time, ODOM),
        "child_frame_id": FOOTPRINT,
        "pose": {"pose": _pose_message(s.odom_pose), "covariance": [0.0] * 36},
        "twist": {
            "twist": {
                "linear": {"x": float(s.velocity[0]), "y": 0.0, "z": 0.0},
                "angular": {"x": 0.0, "y": 0.0, "z": float(s.velocity[1])},
            },
            "covariance": [0.0] * 36,
        },
    }


def _transform(time: float, parent: str, child: str, xyz: tuple[float, float, float], yaw: float = 0.0) -> dict:
    return {
        "header": header_at(time, parent),
        "child_frame_id": child,
        "transform": {"translation": dict(zip("xyz", map(float, xyz))), "rotation": _quaternion_z(yaw)},
    }


def tf(s: MobileSnapshot) -> dict:
    """/tf: odom -> base_footprint (the odometry's pose, as turtlebot3_node broadcasts it)."""
    x, y, yaw = (float(v) for v in s.odom_pose)
    return {"transforms": [_transform(s.time, ODOM, FOOTPRINT, (x, y, 0.0), yaw)]}


def static_transforms() -> list[tuple[str, str, tuple[float, float, float]]]:
    """(parent, child, xyz) of the fixed frames (turtlebot3_burger.urdf's joints)."""
    half = 0.5 * _BASE.wheel_separation
    ox, oy = _LIDAR.offset_xy
    return [
        (FOOTPRINT, BASE_LINK, (0.0, 0.0, BASE_LINK_HEIGHT)),
        (BASE_LINK, SCAN_FRAME, (ox, oy, _LIDAR.height - BASE_LINK_HEIGHT)),
        (BASE_LINK, WHEEL_LINKS[0], (0.0, half, WHEEL_Z)),
        (BASE_LINK, WHEEL_LINKS[1], (0.0, -half, WHEEL_Z)),
    ]


def tf_static(s: MobileSnapshot) -> dict:
    """/tf_static: the fixed frames, stamped 0 (they hold at any time). The wheels' links are given
    at angle 0 here; their angles are on /joint_states."""
    return {"transforms": [_stamp(_transform(0.0, p, c, xyz), True) for p, c, xyz in static_transforms()]}


def joint_state(s: MobileSnapshot) -> dict:
    """sensor_msgs/JointState of the wheels: angle (rad) and rate (rad/s), left then right."""
    return {
        "header": header_at(s.time, ""),
        "name": list(WHEEL_JOINTS),
        "position": [float(s.wheels[0]), float(s.wheels[1])],
        "velocity": [float(s.wheels[2]), float(s.wheels[3])],
        "effort": [],
    }


def followed_twist(s: MobileSnapshot) -> dict:
    """The twist the base follows now, of the last /cmd_vel within its limits (0 once the watchdog
    stopped it)."""
    return {
        "linear": {"x": float(s.command[0]), "y": 0.0, "z": 0.0},
        "angular": {"x": 0.0, "y": 0.0, "z": float(s.command[1])},
    }


def clock(s: MobileSnapshot) -> dict:
    """rosgraph_msgs/Clock: the simulated time, as Gazebo publishes it (for `use_sim_time`)."""
    return {"clock": header_at(s.time, "")["stamp"]}


def pose_2d(s: MobileSnapshot) -> dict:
    """The base's true pose in the arena (geometry_msgs/Pose2D): Gazebo's ground truth."""
    return {"x": float(s.pose[0]), "y": float(s.pose[1]), "theta": float(s.pose[2])}


def wall_following(s: MobileSnapshot) -> dict:
    """The wall-following trial's state (sim/mobile/monitor.py), judged from the true pose."""
    w = s.wall
    return {
        "header": header_at(s.time, ODOM),
        "elapsed": w.elapsed,
        "distance": w.distance,
        "circuit_deg": math.degrees(w.circuit),
        "outside_band": w.outside_band,
        "contact": s.contact,
        "done": w.done,
        "passed": w.passed,
        "verdict": w.verdict or "",
    }


# Gazebo's ground truth and the grader's monitor: a graded trial serves neither to its program
# (app/mobile/lab.py), which gets what a node on the real robot gets; the grader reads them in-process
GRADER_TOPICS = ("/ground_truth_pose", "/wall_following")
TOPICS = [
    Topic(SCAN, "sensor_msgs/LaserScan", laser_scan),
    Topic(ODOM_TOPIC, "nav_msgs/Odometry", odometry),
    Topic("/joint_states", "sensor_msgs/JointState", joint_state),
    Topic(FOLLOWED, "geometry_msgs/Twist", followed_twist),
    Topic("/tf", "tf2_msgs/TFMessage", tf),
    Topic("/tf_static", "tf2_msgs/TFMessage", tf_static),
    Topic("/ground_truth_pose", "geometry_msgs/Pose2D", pose_2d),
    Topic("/wall_following", "hri_lab/WallFollowing", wall_following),
    Topic("/clock", "rosgraph_msgs/Clock", clock),
]
