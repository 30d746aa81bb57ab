"""The 3-DoF planar arm of Exercise 1: three revolute joints about z, links of 1 m.

Hand position p = sum_i L_i [cos(theta_i), sin(theta_i)] with theta_i = q_1 + ... + q_i.
"""

from __future__ import annotations

import numpy as np

LINK_LENGTHS = (1.0, 1.0, 1.0)  # m


def forward_kinematics(q: np.ndarray, lengths=LINK_LENGTHS) -> np.ndarray:
    """Hand position [x, y] (m) and orientation phi = q1+q2+q3 (rad) as [x, y, phi]."""
    theta = np.cumsum(np.asarray(q, float))
    x = float(np.dot(lengths, np.cos(theta)))
    y = float(np.dot(lengths, np.sin(theta)))
    return np.array([x, y, theta[-1]])


def jacobian(q: np.ndarray, lengths=LINK_LENGTHS) -> np.ndarray:
    """Jacobian (3x3) of [x, y, phi] w.r.t. q:
    dx/dq_j = -sum_{i>=j} L_i sin(theta_i), dy/dq_j = sum_{i>=j} L_i cos(theta_i), dphi/dq_j = 1."""
    theta = np.cumsum(np.asarray(q, float))
    ls = np.asarray(lengths, float)
    # reversed cumulative sums give the sum over links i >= j
    sx = np.cumsum((ls * np.sin(theta))[::-1])[::-1]
    cy = np.cumsum((ls * np.cos(theta))[::-1])[::-1]
    return np.vstack((-sx, cy, np.ones(3)))


def torques(q: np.ndarray, force: np.ndarray, lengths=LINK_LENGTHS) -> np.ndarray:
    """tau = J(q)^T F with F = [fx, fy] (N) or [fx, fy, mz] (N, Nm) at the hand; returns 3 torques (Nm)."""
    f = np.asarray(force, float)
    if f.shape == (2,):
        f = np.append(f, 0.0)
    if f.shape != (3,):
        raise ValueError("force must have 2 ([fx, fy]) or 3 ([fx, fy, mz]) components")
    return jacobian(q, lengths).T @ f
