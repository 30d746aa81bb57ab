"""The box: a rigid body with gravity, moved only by the forces applied to it.

Semi-implicit (symplectic) Euler, world frame:
    v <- v + (F/m + g) dt,   x <- x + v dt
    w <- w + I_w^-1 (tau - w x I_w w) dt,   R <- exp([w dt]x) R,   I_w = R I_body R^T
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .contact import BoxPose
from .spatial import cross3, orthonormalize, rotation_exp

GRAVITY = np.array([0.0, 0.0, -9.81])  # m/s^2


@dataclass(frozen=True)
class BoxParams:
    mass: float = 1.0  # kg
    size: tuple[float, float, float] = (0.20, 0.20, 0.20)  # m, along the box axes

    @property
    def inertia_body(self) -> np.ndarray:
        """Solid cuboid: I_xx = m (b^2 + c^2) / 12, ... (kg m^2)."""
        a, b, c = self.size
        return self.mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


class Box:
    """Rigid-body state of the box."""

    def __init__(self, params: BoxParams, position: np.ndarray, rotation: np.ndarray | None = None) -> None:
        self.params = params
        self.reset(position, rotation)

    def reset(self, position: np.ndarray, rotation: np.ndarray | None = None) -> None:
        self.position = np.array(position, dtype=float)
        self.rotation = np.eye(3) if rotation is None else np.array(rotation, dtype=float)
        self.velocity = np.zeros(3)
        self.angular_velocity = np.zeros(3)
        self._inertia_inv = np.linalg.inv(self.params.inertia_body)
        self._steps = 0

    def set_params(self, params: BoxParams) -> None:
        self.params = params
        self._inertia_inv = np.linalg.inv(params.inertia_body)

    @property
    def half_size(self) -> np.ndarray:
        return np.asarray(self.params.size) / 2.0

    def pose(self) -> BoxPose:
        return BoxPose(self.position, self.rotation, self.velocity, self.angular_velocity, self.half_size)

    def step(self, force: np.ndarray, torque: np.ndarray, dt: float) -> None:
        """Advance dt (s) under the total external force (N) and moment about the centre (Nm), world."""
        p = self.params
        r = self.rotation
        self.velocity = self.velocity + (force / p.mass + GRAVITY) * dt
        w_body = r.T @ self.angular_velocity
        inertia = p.inertia_body
        tau_body = r.T @ torque - cross3(w_body, inertia @ w_body)
        w_body = w_body + (self._inertia_inv @ tau_body) * dt
        self.angular_velocity = r @ w_body
        self.position = self.position + self.velocity * dt
        self.rotation = rotation_exp(self.angular_velocity * dt) @ r
        self._steps += 1
        if self._steps % 1000 == 0:
            self.rotation = orthonormalize(self.rotation)
