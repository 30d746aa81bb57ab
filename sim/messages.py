"""The lab's topics as ROS messages of a world Snapshot: one declaration per topic (name, type,
builder(snapshot) -> dict shaped like the ROS message it mirrors). The live server serves them
(app/lab/topics.py, app/api/topics.py) and recordings store them (sim/recording)."""

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin
import pybase64

from sim import camera
from sim.robot.panda import ARM_JOINTS
from sim.world import Snapshot

F_EXT = "/franka_state_controller/F_ext"


def header(s: Snapshot, frame_id: str) -> dict:
    return header_at(s.time, frame_id)


def header_at(time: float, frame_id: str) -> dict:
    sec = int(time)
    return {"stamp": {"sec": sec, "nanosec": int(round((time - sec) * 1e9))}, "frame_id": frame_id}


def vector3(v) -> dict:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def pose(position, rotation) -> dict:
    q = pin.Quaternion(np.asarray(rotation))  # ROS orders x, y, z, w
    return {"position": vector3(position), "orientation": {"x": q.x, "y": q.y, "z": q.z, "w": q.w}}


def wrench_stamped(s: Snapshot) -> dict:
    return wrench_stamped_at(s.time, s.wrench_ee)


def wrench_stamped_at(time: float, wrench_ee) -> dict:
    """F_ext at `time` (s): franka_ros's K_F_ext_hat_K, in the EE frame panda_K."""
    return {
        "header": header_at(time, "panda_K"),
        "wrench": {"force": vector3(wrench_ee[:3]), "torque": vector3(wrench_ee[3:])},
    }


def joint_state(s: Snapshot) -> dict:
    return {
        "header": header(s, ""),
        "name": list(ARM_JOINTS),
        "position": s.q.tolist(),
        "velocity": s.qdot.tolist(),
        "effort": [],
    }


def twist(s: Snapshot) -> dict:
    return {"linear": vector3(s.twist_command[:3]), "angular": vector3(s.twist_command[3:])}


def object_pose(s: Snapshot) -> dict:
    return {"header": header(s, "panda_link0"), "pose": pose(s.box_position, s.box_rotation)}


def hand_pose(s: Snapshot) -> dict:
    return {"header": header(s, "panda_link0"), "pose": pose(s.palm_position, s.palm_rotation)}


def contact_state(s: Snapshot) -> dict:
    plate, palm = s.plate, s.palm
    mu = s.lifting.mu
    return {
        "header": header(s, "panda_link0"),
        "normal_force": plate.normal_force,
        "tangential_force": vector3(plate.tangential_force),
        "friction_ratio": plate.friction_ratio / mu if mu > 0 else 0.0,
        "centre_of_pressure": {"x": float(plate.centre_of_pressure[0]), "y": float(plate.centre_of_pressure[1])},
        "robot_contact": plate.points_in_contact > 0,
        "robot_slipping": plate.points_slipping > 0,
        "human_contact": palm.points_in_contact > 0,
        "human_slipping": palm.points_slipping > 0,
        "human_normal_force": palm.normal_force,
    }


def lifting_state(s: Snapshot) -> dict:
    return {
        "header": header(s, ""),
        "started": s.lifting.running,
        "f_n_min": s.lifting.f_n_min,
        "f_n_max": s.lifting.f_n_max,
        "error": s.error or "",
        "human_phase": s.human_phase,
    }


def trial_outcome(s: Snapshot) -> dict:
    """The scripted participant's trial (sim/monitor.py): state none, running,
    succeeded, failed or abandoned; the figures of the experiment's table (N, m, s)."""
    t = s.trial
    return {
        "header": header(s, ""),
        "state": t.state,
        "participant": t.participant,
        "duration": t.duration,
        "f_n_min": t.f_n_min,
        "f_n_max": t.f_n_max,
        "max_friction_ratio": t.max_friction_ratio,
        "slip": t.slip,
        "reason": t.reason,
    }


class Base64Text(str):
    """A byte array's base64 text, as rosbridge's JSON carries uint8[]: only the base64 alphabet, so
    no character of it needs a JSON escape (a frame's encoder may put it in as it is:
    app/rosbridge/internal/shared.py)."""

    __slots__ = ()


def image(time: float, bgr: np.ndarray) -> dict:
    """sensor_msgs/Image of a BGR uint8 image (height x width x 3) at `time` (s), in the camera's
    optical frame; `data` as rosbridge's JSON carries uint8[]: base64 text."""
    height, width = bgr.shape[:2]
    return {
        "header": header_at(time, camera.OPTICAL_FRAME),
        "height": height,
        "width": width,
        "encoding": "bgr8",
        "is_bigendian": 0,
        "step": width * 3,
        "data": Base64Text(pybase64.b64encode(np.ascontiguousarray(bgr, np.uint8).tobytes()).decode("ascii")),
    }


def camera_info_at(time: float) -> dict:
    """sensor_msgs/CameraInfo of the lab's camera (sim/camera.py): K, no distortion, P = [K | 0]."""
    width, height = camera.CAMERA_SIZE
    k = camera.intrinsics()
    return {
        "header": header_at(time, camera.OPTICAL_FRAME),
        "height": height,
        "width": width,
        "distortion_model": "plumb_bob",
        "d": [0.0] * 5,
        "k": k.flatten().tolist(),
        "r": np.eye(3).flatten().tolist(),
        "p": np.hstack((k, np.zeros((3, 1)))).flatten().tolist(),
        "binning_x": 0,
        "binning_y": 0,
        "roi": {"x_offset": 0, "y_offset": 0, "height": 0, "width": 0, "do_rectify": False},
    }


def camera_info(s: Snapshot) -> dict:
    return camera_info_at(s.time)


@dataclass(frozen=True)
class Topic:
    name: str
    type: str
    build: Callable[[Any], dict]  # a world's snapshot -> the message (the mobile world's: sim/mobile/messages.py)


TOPICS = [
    Topic(F_EXT, "geometry_msgs/WrenchStamped", wrench_stamped),
    Topic("/joint_states", "sensor_msgs/JointState", joint_state),
    Topic("/cartesian_velocity_controller/command", "geometry_msgs/Twist", twist),
    Topic("/object_pose", "geometry_msgs/PoseStamped", object_pose),
    Topic("/human_hand_pose", "geometry_msgs/PoseStamped", hand_pose),
    Topic("/contact_state", "hri_lab/ContactState", contact_state),
    Topic("/lifting_state", "hri_lab/LiftingState", lifting_state),
    Topic("/trial", "hri_lab/TrialOutcome", trial_outcome),
]
