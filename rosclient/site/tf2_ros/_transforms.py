"""Rigid transforms as 4x4 matrices and unit quaternions (x, y, z, w), the one place the tf layers
(tf2_ros, tf) compute them."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def quaternion_matrix(quaternion: Sequence[float]) -> np.ndarray:
    """The 4x4 rotation of a quaternion (x, y, z, w), normalised (a zero one is the identity)."""
    x, y, z, w = (float(v) for v in quaternion)
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm < 1e-12:
        return np.eye(4)
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    matrix = np.eye(4)
    matrix[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    return matrix


def quaternion_from_matrix(matrix: np.ndarray) -> np.ndarray:
    """The unit quaternion (x, y, z, w) of a rotation (the upper 3x3 of `matrix`), w >= 0."""
    m = np.asarray(matrix, dtype=float)[:3, :3]
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s]
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s, (m[1, 0] - m[0, 1]) / s]
    quaternion = np.array(q) / np.linalg.norm(q)
    return -quaternion if quaternion[3] < 0 else quaternion


def compose(translation: Sequence[float], quaternion: Sequence[float]) -> np.ndarray:
    """The 4x4 of a translation and a rotation."""
    matrix = quaternion_matrix(quaternion)
    matrix[:3, 3] = [float(v) for v in translation]
    return matrix


def decompose(matrix: np.ndarray) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    """(translation, quaternion) of a 4x4 transform."""
    t = np.asarray(matrix, dtype=float)[:3, 3]
    q = quaternion_from_matrix(matrix)
    return (float(t[0]), float(t[1]), float(t[2])), (float(q[0]), float(q[1]), float(q[2]), float(q[3]))
