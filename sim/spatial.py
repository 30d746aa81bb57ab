"""Small spatial-algebra helpers (twists/wrenches are [linear, angular]). exp3, log3 and
orthonormalize are plain code that numba compiles too (the kernels compile them where they use
them), so this module never imports numba.

pinocchio is imported where it is used, not here: the controllers' side (sim/controllers/, which a
sandboxed child imports for every graded item) uses rotate_twist and must not pay pinocchio's start-up."""

from __future__ import annotations

import math

import numpy as np


def rotate_twist(rotation_a_to_b: np.ndarray, twist_a: np.ndarray) -> np.ndarray:
    """Express a twist (or wrench) given in frame a in frame b, same reference point:
    x_b = blockdiag(R, R) @ x_a with R = rotation a -> b."""
    return np.concatenate((rotation_a_to_b @ twist_a[:3], rotation_a_to_b @ twist_a[3:]))


def rotation_exp(omega_dt: np.ndarray) -> np.ndarray:
    """Rotation matrix exp([omega_dt]x) (Rodrigues, via pinocchio)."""
    import pinocchio as pin

    return pin.exp3(omega_dt)


def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector log(R) (rad), via pinocchio."""
    import pinocchio as pin

    return pin.log3(rotation)


def exp3(w):
    """exp([w]x) (pinocchio's exp3 as plain code that the kernels compile: sim/person/human.py;
    tests/sim/test_spatial.py) = I + sin(t)/t [w]x + (1 - cos t)/t^2 [w]x^2, t = |w| (Taylor terms near t = 0)."""
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


def orthonormalize(rotation: np.ndarray) -> np.ndarray:
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


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for two 3-vectors (np.cross is slow on tiny arrays; so is arithmetic on numpy scalars)."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
