"""The box: a rigid body with gravity, moved only by the forces applied to it.

Semi-implicit (symplectic) Euler, world frame:
    v <- v + (F/m + g) dt,   x <- x + v dt
    w <- w + I_w^-1 (tau - w x I_w w) dt,   R <- exp([w dt]x) R,   I_w = R I_body R^T
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from sim import spatial
from sim.physics.contact import BoxPose

GRAVITY = np.array([0.0, 0.0, -9.81])  # m/s^2
orthonormalize = njit(cache=True)(spatial.orthonormalize)  # sim/spatial.py's, compiled for box_step


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
        self._inertia = self.params.inertia_body
        self._inertia_inv = np.linalg.inv(self._inertia)
        self._half_size = np.asarray(self.params.size, dtype=float) / 2.0
        self._steps = 0

    def set_params(self, params: BoxParams) -> None:
        self.params = params
        self._inertia = params.inertia_body
        self._inertia_inv = np.linalg.inv(self._inertia)
        self._half_size = np.asarray(params.size, dtype=float) / 2.0

    @property
    def half_size(self) -> np.ndarray:
        """Half extents along the box axes (m)."""
        return self._half_size

    def pose(self) -> BoxPose:
        return BoxPose(self.position, self.rotation, self.velocity, self.angular_velocity, self.half_size)

    def step(self, force: np.ndarray, torque: np.ndarray, dt: float) -> None:
        """Advance dt (s) under the total external force (N) and moment about the centre (Nm), world."""
        self._steps = box_step(
            self.position,
            self.rotation,
            self.velocity,
            self.angular_velocity,
            np.asarray(force, float),
            np.asarray(torque, float),
            self.params.mass,
            self._inertia,
            self._inertia_inv,
            GRAVITY,
            dt,
            self._steps,
        )


@njit(cache=True)
def box_step(position, rotation, velocity, omega, force, torque, mass, inertia, inertia_inv, gravity, dt, steps):
    """One step of `_integrate`, and every 1000th the rotation orthonormalized; returns steps + 1."""
    _integrate(position, rotation, velocity, omega, force, torque, mass, inertia, inertia_inv, gravity, dt)
    steps += 1
    if steps % 1000 == 0:
        rotation[:, :] = orthonormalize(rotation)
    return steps


@njit(cache=True)
def _integrate(position, rotation, velocity, omega, force, torque, mass, inertia, inertia_inv, gravity, dt):
    """One semi-implicit Euler step of the module docstring, in place."""
    for i in range(3):
        velocity[i] += (force[i] / mass + gravity[i]) * dt
    # body-frame angular velocity and moment: w_b = R^T w, tau_b = R^T tau - w_b x I w_b
    w_b = rotation.T @ omega
    iw = inertia @ w_b
    tau_b = rotation.T @ torque
    tau_b[0] -= w_b[1] * iw[2] - w_b[2] * iw[1]
    tau_b[1] -= w_b[2] * iw[0] - w_b[0] * iw[2]
    tau_b[2] -= w_b[0] * iw[1] - w_b[1] * iw[0]
    w_b += (inertia_inv @ tau_b) * dt
    omega[:] = rotation @ w_b
    for i in range(3):
        position[i] += velocity[i] * dt
    # R <- exp([w dt]x) R (Rodrigues)
    wx, wy, wz = omega[0] * dt, omega[1] * dt, omega[2] * dt
    theta = (wx * wx + wy * wy + wz * wz) ** 0.5
    if theta > 1e-12:
        kx, ky, kz = wx / theta, wy / theta, wz / theta
        c, s = np.cos(theta), np.sin(theta)
        v = 1.0 - c
        step = np.array(
            [
                [c + kx * kx * v, kx * ky * v - kz * s, kx * kz * v + ky * s],
                [ky * kx * v + kz * s, c + ky * ky * v, ky * kz * v - kx * s],
                [kz * kx * v - ky * s, kz * ky * v + kx * s, c + kz * kz * v],
            ]
        )
        rotation[:, :] = step @ rotation
