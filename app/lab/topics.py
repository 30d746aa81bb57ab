"""The lab's topics (docs/design.md, "Topics"), one declaration each: name, ROS type, builder."""
import threading

import numpy as np

from app.ros.topics import Topic, header, pose, vector3
from sim.robot.panda import ARM_JOINTS, PandaModel
from sim.world import Snapshot


def wrench_stamped(s: Snapshot) -> dict:
    return {"header": header(s, "panda_K"), "wrench": {"force": vector3(s.wrench_ee[:3]), "torque": vector3(s.wrench_ee[3:])}}


def joint_state(s: Snapshot) -> dict:
    return {"header": header(s, ""), "name": list(ARM_JOINTS), "position": s.q.tolist(), "velocity": s.qdot.tolist(), "effort": []}


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


_MODEL_LOCK = threading.Lock()
_MODEL: list[PandaModel] = []  # one model for the Jacobian, made on first use (pinocchio's data is not thread-safe)


def franka_state(s: Snapshot) -> dict:
    """What franka_state_controller publishes, the lab's subset: q, dq, O_T_EE (4x4, column-major),
    K_F_ext_hat_K (= F_ext) and O_Jac_EE, the flange Jacobian in the base frame (6x7,
    column-major like libfranka's zeroJacobian: twist_base = J qdot)."""
    with _MODEL_LOCK:
        if not _MODEL:
            _MODEL.append(PandaModel())
        jacobian = np.array(_MODEL[0].jacobian_base(s.q))
    return {"header": header(s, "panda_link0"), "q": s.q.tolist(), "dq": s.qdot.tolist(),
            "O_T_EE": s.transform_ee_to_base.flatten(order="F").tolist(),
            "K_F_ext_hat_K": s.wrench_ee.tolist(), "O_Jac_EE": jacobian.flatten(order="F").tolist()}


TOPICS = [
    Topic("/franka_state_controller/F_ext", "geometry_msgs/WrenchStamped", wrench_stamped),
    Topic("/joint_states", "sensor_msgs/JointState", joint_state),
    Topic("/cartesian_velocity_controller/command", "geometry_msgs/Twist", twist),
    Topic("/object_pose", "geometry_msgs/PoseStamped", object_pose),
    Topic("/human_hand_pose", "geometry_msgs/PoseStamped", hand_pose),
    Topic("/contact_state", "hri_lab/ContactState", contact_state),
    Topic("/lifting_state", "hri_lab/LiftingState", lifting_state),
    Topic("/franka_state_controller/franka_states", "hri_lab/FrankaState", franka_state),
]
