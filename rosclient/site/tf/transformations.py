"""tf.transformations' common functions (ROS 1): 4x4 homogeneous matrices and quaternions (x, y, z, w),
Euler angles in the static x-y-z convention `sxyz` (tf's default: R = Rz(yaw) Ry(pitch) Rx(roll)) and
its mirror `rzyx`. Another axes convention raises ValueError naming the two supported."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from tf2_ros._transforms import quaternion_from_matrix as _quaternion_from_matrix
from tf2_ros._transforms import quaternion_matrix as _quaternion_matrix

AXES = ("sxyz", "rzyx")


def _angles(ai: float, aj: float, ak: float, axes: str) -> tuple[float, float, float]:
    """(roll about x, pitch about y, yaw about z) of Euler angles given in `axes`."""
    if axes == "sxyz":
        return ai, aj, ak
    if axes == "rzyx":
        return ak, aj, ai
    raise ValueError(f"axes {axes!r}: only {', '.join(AXES)} are supported here")


def identity_matrix() -> np.ndarray:
    return np.identity(4)


def translation_matrix(direction: Sequence[float]) -> np.ndarray:
    matrix = np.identity(4)
    matrix[:3, 3] = np.asarray(direction, dtype=float)[:3]
    return matrix


def translation_from_matrix(matrix: np.ndarray) -> np.ndarray:
    return np.array(matrix, dtype=float, copy=True)[:3, 3]


def quaternion_matrix(quaternion: Sequence[float]) -> np.ndarray:
    return _quaternion_matrix(quaternion)


def quaternion_from_matrix(matrix: np.ndarray) -> np.ndarray:
    return _quaternion_from_matrix(matrix)


def euler_matrix(ai: float, aj: float, ak: float, axes: str = "sxyz") -> np.ndarray:
    roll, pitch, yaw = _angles(ai, aj, ak, axes)
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    matrix = np.identity(4)
    matrix[:3, :3] = [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
    return matrix


def euler_from_matrix(matrix: np.ndarray, axes: str = "sxyz") -> tuple[float, float, float]:
    m = np.asarray(matrix, dtype=float)[:3, :3]
    cy = math.hypot(m[0, 0], m[1, 0])
    if cy > 1e-9:
        roll, pitch, yaw = math.atan2(m[2, 1], m[2, 2]), math.atan2(-m[2, 0], cy), math.atan2(m[1, 0], m[0, 0])
    else:  # gimbal lock: yaw folded into roll
        roll, pitch, yaw = math.atan2(-m[1, 2], m[1, 1]), math.atan2(-m[2, 0], cy), 0.0
    if axes == "sxyz":
        return roll, pitch, yaw
    _angles(0.0, 0.0, 0.0, axes)  # refuses an unsupported convention
    return yaw, pitch, roll


def quaternion_from_euler(ai: float, aj: float, ak: float, axes: str = "sxyz") -> np.ndarray:
    return quaternion_from_matrix(euler_matrix(ai, aj, ak, axes))


def euler_from_quaternion(quaternion: Sequence[float], axes: str = "sxyz") -> tuple[float, float, float]:
    return euler_from_matrix(quaternion_matrix(quaternion), axes)


def quaternion_multiply(quaternion1: Sequence[float], quaternion0: Sequence[float]) -> np.ndarray:
    """quaternion1 * quaternion0 (apply quaternion0 first)."""
    x1, y1, z1, w1 = (float(v) for v in quaternion1)
    x0, y0, z0, w0 = (float(v) for v in quaternion0)
    return np.array(
        [
            x1 * w0 + y1 * z0 - z1 * y0 + w1 * x0,
            -x1 * z0 + y1 * w0 + z1 * x0 + w1 * y0,
            x1 * y0 - y1 * x0 + z1 * w0 + w1 * z0,
            -x1 * x0 - y1 * y0 - z1 * z0 + w1 * w0,
        ]
    )


def quaternion_conjugate(quaternion: Sequence[float] | np.ndarray) -> np.ndarray:
    x, y, z, w = (float(v) for v in quaternion)
    return np.array([-x, -y, -z, w])


def quaternion_inverse(quaternion: Sequence[float]) -> np.ndarray:
    q = np.asarray(quaternion, dtype=float)
    return quaternion_conjugate(q) / float(np.dot(q, q))


def quaternion_about_axis(angle: float, axis: Sequence[float]) -> np.ndarray:
    a = np.asarray(axis, dtype=float)[:3]
    a = a / np.linalg.norm(a)
    return np.array([*(a * math.sin(angle / 2.0)), math.cos(angle / 2.0)])


def inverse_matrix(matrix: np.ndarray) -> np.ndarray:
    return np.linalg.inv(matrix)


def concatenate_matrices(*matrices: np.ndarray) -> np.ndarray:
    result = np.identity(4)
    for matrix in matrices:
        result = result @ np.asarray(matrix, dtype=float)
    return result


def vector_norm(data: Sequence[float]) -> float:
    return float(np.linalg.norm(np.asarray(data, dtype=float)))


def unit_vector(data: Sequence[float]) -> np.ndarray:
    vector = np.asarray(data, dtype=float)
    return vector / np.linalg.norm(vector)
