"""The Franka Panda kinematic model (pinocchio, from example-robot-data) and its flange frame.

Frames: `base` = panda_link0 (z up); `ee` = the flange panda_link8 (the lab's end effector is
"None", so EE = flange = franka's stiffness frame K). The contact plate (sim/robot/plate.py) is
rigidly mounted on the flange: outward normal = flange +z, centre at `offset` along flange +z.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from sim.robot.assets import panda_urdf
from sim.robot.panda_kinematics import chain_arrays

# franka's "ready" pose (rad).
READY_Q = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])

# The lab's "side" start pose (rad): the plate faces base +y horizontally (toward the person, who
# stands at the robot's side), flange at about (0.60, 0.15, 0.35) m in the base frame with its x
# axis pointing down. Solved once with damped least-squares IK seeded at READY_Q (a Panda cannot
# point its flange forward, +x, at this height: joint 6 runs out of range) and kept here like
# franka's ready pose.
SIDE_Q = np.array([-0.1566, 0.3832, 0.2697, -1.915, 1.5575, 1.7074, 0.8523])

# Panda limits that the URDF does not carry (franka datasheet / libfranka constants).
JOINT_ACCELERATION_LIMITS = np.array([15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0])  # rad/s^2
CARTESIAN_VELOCITY_LIMIT = 1.7  # m/s
CARTESIAN_ANGULAR_VELOCITY_LIMIT = 2.5  # rad/s
CARTESIAN_ACCELERATION_LIMIT = 13.0  # m/s^2
CARTESIAN_ANGULAR_ACCELERATION_LIMIT = 25.0  # rad/s^2

ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")


class PandaModel:
    """Pinocchio model of the 7 arm joints (fingers locked) with FK and the flange Jacobian."""

    flange_name = "panda_link8"

    def __init__(self) -> None:
        full = pin.buildModelFromUrdf(str(panda_urdf()))
        lock = [full.getJointId(name) for name in FINGER_JOINTS]
        self.model = pin.buildReducedModel(full, lock, pin.neutral(full))
        self.data = self.model.createData()
        self.flange_id = self.model.getFrameId(self.flange_name)
        self.q_min = self.model.lowerPositionLimit.copy()
        self.q_max = self.model.upperPositionLimit.copy()
        self.qdot_max = self.model.velocityLimit.copy()
        self.tau_max = self.model.effortLimit.copy()
        self.nq = self.model.nq
        self.chain = chain_arrays(self.model, self.flange_id)  # what the compiled step evaluates (panda_kinematics)

    def transform_ee_to_base(self, q: np.ndarray) -> np.ndarray:
        """Homogeneous transform (4x4) of the flange in the base frame."""
        pin.framesForwardKinematics(self.model, self.data, q)
        return self.data.oMf[self.flange_id].homogeneous

    def jacobian_base(self, q: np.ndarray) -> np.ndarray:
        """Flange Jacobian (6x7): joint velocities -> twist of the flange origin in the base frame
        (pinocchio LOCAL_WORLD_ALIGNED)."""
        return pin.computeFrameJacobian(self.model, self.data, q, self.flange_id, pin.LOCAL_WORLD_ALIGNED)

    def kinematics(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(transform_ee_to_base 4x4, jacobian_base 6x7) in one pass."""
        jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.flange_id, pin.LOCAL_WORLD_ALIGNED)
        pin.updateFramePlacement(self.model, self.data, self.flange_id)
        return self.data.oMf[self.flange_id].homogeneous, jacobian

    def torques_from_wrench(self, q: np.ndarray, wrench_base: np.ndarray) -> np.ndarray:
        """Exercise 8: tau = J(q)^T F (Nm), F = [f, m] at the flange origin in the base frame (N, Nm)."""
        return self.jacobian_base(np.asarray(q, float)).T @ np.asarray(wrench_base, float)

    def wrench_from_torques(self, q: np.ndarray, torques: np.ndarray) -> tuple[np.ndarray, float]:
        """Exercise 2: least-squares F with J^T F = tau (J^T is 7x6, overdetermined).

        Returns (F (6,), residual norm ||J^T F - tau|| in Nm): a residual > 0 means the torques
        contain a part no flange wrench can produce."""
        jt = self.jacobian_base(np.asarray(q, float)).T
        tau = np.asarray(torques, float)
        with np.errstate(over="ignore", invalid="ignore"):  # huge inputs: inf/nan, refused by the caller
            wrench, *_ = np.linalg.lstsq(jt, tau, rcond=None)
            return wrench, float(np.linalg.norm(jt @ wrench - tau))
