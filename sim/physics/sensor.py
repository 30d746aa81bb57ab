"""F_ext estimate, like franka_ros's /franka_state_controller/F_ext (K_F_ext_hat_K).

The wrench the robot applies to the environment, at the flange (EE = K) origin, expressed in
the flange frame:
    f_ee = R^T f,   m_ee = R^T (m_c + (p_c - p_ee) x f)
with f, m_c the plate's contact force and moment on the box about the plate centre p_c (world),
R = rotation EE -> base. Pressing the plate on the box gives f_n = f_ee . z > 0.
Then Gaussian noise (N, Nm) and an optional first-order low-pass (sim.signals.LowPass):
    y <- y + a (x - y),  a = dt / (tau + dt),  tau = 1 / (2 pi f_c).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.signals import LowPass
from sim.spatial import cross3


@dataclass(frozen=True)
class SensorParams:
    force_noise_std: float = 0.5  # N
    moment_noise_std: float = 0.05  # Nm
    filter_cutoff_hz: float = 0.0  # 0 = no filter


def wrench_at_ee(
    force_world: np.ndarray,
    moment_plate_world: np.ndarray,
    position_plate: np.ndarray,
    transform_ee_to_base: np.ndarray,
) -> np.ndarray:
    """Noise-free wrench (6,) at the EE origin in the EE frame from the plate's force/moment (world)."""
    rotation = transform_ee_to_base[:3, :3]
    moment_ee_world = moment_plate_world + cross3(position_plate - transform_ee_to_base[:3, 3], force_world)
    return np.concatenate((rotation.T @ force_world, rotation.T @ moment_ee_world))


class WrenchSensor:
    """Adds noise and filtering to the true wrench."""

    def __init__(self, params: SensorParams, rng: np.random.Generator) -> None:
        self.params = params
        self.rng = rng
        self.filter = LowPass()

    def reset(self) -> None:
        self.filter.reset()

    def measure(self, wrench_ee: np.ndarray, dt: float) -> np.ndarray:
        """One sample (6,) of F_ext from the true wrench_ee."""
        p = self.params
        noise = self.rng.standard_normal(6)
        noise[:3] *= p.force_noise_std
        noise[3:] *= p.moment_noise_std
        return self.filter.update_hz(wrench_ee + noise, dt, p.filter_cutoff_hz)
