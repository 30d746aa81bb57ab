"""Small spatial-algebra helpers (twists/wrenches are [linear, angular])."""
from __future__ import annotations

import math

import numpy as np
from numba import njit


def rotation_exp(omega_dt: np.ndarray) -> np.ndarray:
    """Rotation matrix exp([omega_dt]x) (Rodrigues; pinocchio's exp3, compiled: tests/test_spatial.py)."""
    return exp3(np.asarray(omega_dt, dtype=float))


def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector log(R) (rad) (pinocchio's log3, compiled: tests/test_spatial.py)."""
    return log3(np.asarray(rotation, dtype=float))


@njit(cache=True)
def exp3(w):
    """exp([w]x) = I + sin(t)/t [w]x + (1 - cos t)/t^2 [w]x^2, t = |w| (Taylor terms near t = 0)."""
    t2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    t = math.sqrt(t2)
    if t < 1e-4:
        a, b = 1.0 - t2 / 6.0, 0.5 - t2 / 24.0
    else:
        a, b = math.sin(t) / t, (1.0 - math.cos(t)) / t2
    x, y, z = w[0], w[1], w[2]
    r = np.empty((3, 3))
    r[0, 0], r[0, 1], r[0, 2] = 1.0 - b * (y * y + z * z), b * x * y - a * z, b * x * z + a * y
    r[1, 0], r[1, 1], r[1, 2] = b * x * y + a * z, 1.0 - b * (x * x + z * z), b * y * z - a * x
    r[2, 0], r[2, 1], r[2, 2] = b * x * z - a * y, b * y * z + a * x, 1.0 - b * (x * x + y * y)
    return r


@njit(cache=True)
def log3(r):
    """The rotation vector w with exp([w]x) = r, |w| in [0, pi] (pinocchio's log3: the axis from
    the skew part, and from the diagonal near pi where the skew part vanishes)."""
    tr = r[0, 0] + r[1, 1] + r[2, 2]
    c = min(max((tr - 1.0) / 2.0, -1.0), 1.0)
    t = math.acos(c)
    w = np.empty(3)
    if t >= math.pi - 1e-2:
        beta = t * t / (1.0 - c)  # r_ii = c + (1 - c) k_i^2  ->  (r_ii - c) beta = t^2 k_i^2
        d0, d1, d2 = (r[0, 0] - c) * beta, (r[1, 1] - c) * beta, (r[2, 2] - c) * beta
        w[0] = (1.0 if r[2, 1] > r[1, 2] else -1.0) * (math.sqrt(d0) if d0 > 0.0 else 0.0)
        w[1] = (1.0 if r[0, 2] > r[2, 0] else -1.0) * (math.sqrt(d1) if d1 > 0.0 else 0.0)
        w[2] = (1.0 if r[1, 0] > r[0, 1] else -1.0) * (math.sqrt(d2) if d2 > 0.0 else 0.0)
        return w
    k = 0.5 * (1.0 + t * t / 6.0) if t < 1e-4 else 0.5 * t / math.sin(t)  # t / (2 sin t)
    w[0], w[1], w[2] = k * (r[2, 1] - r[1, 2]), k * (r[0, 2] - r[2, 0]), k * (r[1, 0] - r[0, 1])
    return w


@njit(cache=True)
def orthonormalize(rotation):
    """Nearest rotation matrix (removes integration drift)."""
    u, _, vt = np.linalg.svd(rotation)
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1
        r = u @ vt
    return r


def norm3(v: np.ndarray) -> float:
    """|v| of a 3-vector (np.linalg.norm costs microseconds on tiny arrays)."""
    a, b, c = v.tolist()
    return math.sqrt(a * a + b * b + c * c)


