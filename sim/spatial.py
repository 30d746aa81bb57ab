"""Small spatial-algebra helpers (twists/wrenches are [linear, angular])."""
from __future__ import annotations

import math

import numpy as np
import pinocchio as pin


def skew(v: np.ndarray) -> np.ndarray:
    """[v]x such that skew(v) @ w = v x w."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def rotate_twist(rotation_a_to_b: np.ndarray, twist_a: np.ndarray) -> np.ndarray:
    """Express a twist (or wrench) given in frame a in frame b, same reference point:
    x_b = blockdiag(R, R) @ x_a with R = rotation a -> b."""
    return np.concatenate((rotation_a_to_b @ twist_a[:3], rotation_a_to_b @ twist_a[3:]))


def rotation_exp(omega_dt: np.ndarray) -> np.ndarray:
    """Rotation matrix exp([omega_dt]x) (Rodrigues, via pinocchio)."""
    return pin.exp3(omega_dt)


def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector log(R) (rad), via pinocchio."""
    return pin.log3(rotation)


def orthonormalize(rotation: np.ndarray) -> np.ndarray:
    """Nearest rotation matrix (removes integration drift)."""
    u, _, vt = np.linalg.svd(rotation)
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1
        r = u @ vt
    return r


def rotation_y(angle: float) -> np.ndarray:
    """Rotation about the y axis by `angle` (rad)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def norm3(v: np.ndarray) -> float:
    """|v| of a 3-vector (np.linalg.norm costs microseconds on tiny arrays)."""
    a, b, c = v.tolist()
    return math.sqrt(a * a + b * b + c * c)


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for two 3-vectors (np.cross is slow on tiny arrays)."""
    a0, a1, a2 = a
    b0, b1, b2 = b
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def cross_rows(w: np.ndarray, points: np.ndarray) -> np.ndarray:
    """w x p_i for every row p_i of points (N, 3): points @ [w]x^T."""
    return points @ skew(w).T


def sum_of_moments(arms: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """sum_i r_i x f_i for rows r_i, f_i: with M = sum_i r_i f_i^T, it is the axial vector of M - M^T."""
    m = arms.T @ forces
    return np.array([m[1, 2] - m[2, 1], m[2, 0] - m[0, 2], m[0, 1] - m[1, 0]])
