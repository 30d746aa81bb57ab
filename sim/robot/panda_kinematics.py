"""The Panda's flange pose and Jacobian as compiled code, from pinocchio's model.

Pinocchio stays the robot model of record (sim/robot/panda.py): at start, the chain's joint
placements (parent joint -> joint, at q = 0), the joints' axes and the flange frame's placement
are read out of `PandaModel.model` into arrays; the hot path (the 1 kHz step) then evaluates

    T_i = T_{i-1} X_i Rot(a_i, q_i),  i = 1..7        (T_0 = I, X_i = model.jointPlacements[i])
    T_ee = T_7 X_flange                                  (X_flange = model.frames[flange].placement)
    J[:3, i] = (R_i a_i) x (p_ee - p_i),  J[3:, i] = R_i a_i  (flange origin, base-aligned axes)

which is pinocchio's `framesForwardKinematics` and `computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)`
for a serial chain of revolute joints. tests/sim/robot/test_kinematics.py checks both against pinocchio at
many random configurations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

AXES = {"JointModelRX": (1.0, 0.0, 0.0), "JointModelRY": (0.0, 1.0, 0.0), "JointModelRZ": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class ChainArrays:
    """The serial chain read out of a pinocchio model (SI units)."""

    rotations: np.ndarray  # (n, 3, 3) joint placement rotations (parent joint -> joint)
    translations: np.ndarray  # (n, 3) joint placement translations (m)
    axes: np.ndarray  # (n, 3) joint axes in the joint frame
    flange_rotation: np.ndarray  # (3, 3) flange frame in its parent joint
    flange_translation: np.ndarray  # (3,) m


def chain_arrays(model, frame_id: int) -> ChainArrays:
    """The chain 1..n of revolute joints of `model` (pinocchio) ending at frame `frame_id`."""
    n = model.njoints - 1
    if list(model.parents) != [0] + list(range(n)):
        raise ValueError("the compiled kinematics needs a serial chain")
    rotations, translations, axes = np.zeros((n, 3, 3)), np.zeros((n, 3)), np.zeros((n, 3))
    for i in range(n):
        joint = model.joints[i + 1]
        name = joint.shortname()
        if name in AXES:
            axes[i] = AXES[name]
        elif name == "JointModelRevoluteUnaligned":
            axes[i] = joint.extract().axis
        else:
            raise ValueError(f"the compiled kinematics needs revolute joints, got {name}")
        placement = model.jointPlacements[i + 1]
        rotations[i], translations[i] = placement.rotation, placement.translation
    frame = model.frames[frame_id]
    if frame.parentJoint != n:
        raise ValueError("the flange frame must hang on the last joint")
    return ChainArrays(
        rotations, translations, axes, frame.placement.rotation.copy(), frame.placement.translation.copy()
    )


@njit(cache=True)
def chain_kinematics(q, rotations, translations, axes, flange_rotation, flange_translation, transform, jacobian):
    """Flange pose (4x4, base frame) into `transform` and its Jacobian (6 x n, LOCAL_WORLD_ALIGNED)
    into `jacobian`, in place (the module docstring's formulas; 3x3 products written out, as
    BLAS calls on 3x3 matrices cost more than the arithmetic)."""
    n = q.shape[0]
    r = np.eye(3)
    tmp = np.empty((3, 3))
    p = np.zeros(3)
    origins = np.empty((n, 3))
    axes_world = np.empty((n, 3))
    for i in range(n):
        # T <- T X_i : p += R t_i, R <- R R_i
        for row in range(3):
            p[row] += r[row, 0] * translations[i, 0] + r[row, 1] * translations[i, 1] + r[row, 2] * translations[i, 2]
        _mul3(r, rotations[i], tmp)
        r[:, :] = tmp
        for row in range(3):
            origins[i, row] = p[row]
            axes_world[i, row] = r[row, 0] * axes[i, 0] + r[row, 1] * axes[i, 1] + r[row, 2] * axes[i, 2]
        # R <- R Rot(a_i, q_i) (Rodrigues, a_i unit, in the joint frame)
        ax, ay, az = axes[i, 0], axes[i, 1], axes[i, 2]
        c, s = math.cos(q[i]), math.sin(q[i])
        v = 1.0 - c
        rot = np.empty((3, 3))
        rot[0, 0], rot[0, 1], rot[0, 2] = c + ax * ax * v, ax * ay * v - az * s, ax * az * v + ay * s
        rot[1, 0], rot[1, 1], rot[1, 2] = ay * ax * v + az * s, c + ay * ay * v, ay * az * v - ax * s
        rot[2, 0], rot[2, 1], rot[2, 2] = az * ax * v - ay * s, az * ay * v + ax * s, c + az * az * v
        _mul3(r, rot, tmp)
        r[:, :] = tmp
    transform[:, :] = 0.0
    for row in range(3):
        transform[row, 3] = p[row] + (
            r[row, 0] * flange_translation[0] + r[row, 1] * flange_translation[1] + r[row, 2] * flange_translation[2]
        )
    _mul3(r, flange_rotation, tmp)
    transform[:3, :3] = tmp
    transform[3, 3] = 1.0
    for i in range(n):
        a0, a1, a2 = axes_world[i, 0], axes_world[i, 1], axes_world[i, 2]
        d0, d1, d2 = transform[0, 3] - origins[i, 0], transform[1, 3] - origins[i, 1], transform[2, 3] - origins[i, 2]
        jacobian[0, i] = a1 * d2 - a2 * d1
        jacobian[1, i] = a2 * d0 - a0 * d2
        jacobian[2, i] = a0 * d1 - a1 * d0
        jacobian[3, i], jacobian[4, i], jacobian[5, i] = a0, a1, a2


@njit(cache=True)
def _mul3(a, b, out):
    """out = a b for 3x3 matrices."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]
