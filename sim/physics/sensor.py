"""F_ext estimate, like franka_ros's /franka_state_controller/F_ext (K_F_ext_hat_K).

The wrench the robot applies to the environment, at the flange (EE = K) origin, expressed in
the flange frame:
    f_ee = R^T f,   m_ee = R^T (m_c + (p_c - p_ee) x f)
with f, m_c the plate's contact force and moment on the box about the plate centre p_c (world),
R = rotation EE -> base. Pressing the plate on the box gives f_n = f_ee . z > 0.
Then Gaussian noise (N, Nm) and an optional first-order low-pass (sim.signals.low_pass_gain):
    y <- y + a (x - y),  a = dt / (tau + dt),  tau = 1 / (2 pi f_c).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from sim import signals

low_pass_gain = njit(cache=True)(signals.low_pass_gain)  # sim/signals.py's, compiled for the kernels
NOISE_BLOCK = 1024  # samples of noise drawn from the world's rng at once (the same stream as one at a time)


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
    out = np.empty(6)
    wrench_at_ee_into(
        np.asarray(force_world, float),
        np.asarray(moment_plate_world, float),
        np.asarray(position_plate, float),
        np.asarray(transform_ee_to_base, float),
        out,
    )
    return out


@njit(cache=True)
def wrench_at_ee_into(force_world, moment_plate_world, position_plate, transform, out):
    """wrench_at_ee into `out`: f_ee = R^T f, m_ee = R^T (m_c + (p_c - p_ee) x f)."""
    r0, r1, r2 = (
        position_plate[0] - transform[0, 3],
        position_plate[1] - transform[1, 3],
        position_plate[2] - transform[2, 3],
    )
    f0, f1, f2 = force_world[0], force_world[1], force_world[2]
    m0 = moment_plate_world[0] + (r1 * f2 - r2 * f1)
    m1 = moment_plate_world[1] + (r2 * f0 - r0 * f2)
    m2 = moment_plate_world[2] + (r0 * f1 - r1 * f0)
    for i in range(3):
        out[i] = transform[0, i] * f0 + transform[1, i] * f1 + transform[2, i] * f2
        out[3 + i] = transform[0, i] * m0 + transform[1, i] * m1 + transform[2, i] * m2


class WrenchSensor:
    """Adds noise and filtering to the true wrench. The filter's state is `self.state` (the last
    output, then 1 once there is one), advanced by `measure_into`, which the compiled world step
    runs too; the noise comes from `rng` in blocks (`next_noise`)."""

    def __init__(self, params: SensorParams, rng: np.random.Generator) -> None:
        self.params = params
        self.rng = rng
        self.state = np.zeros(7)
        self.noise = np.zeros((0, 6))
        self.noise_index = 0
        self._scales: tuple[SensorParams | None, np.ndarray] = (None, np.zeros(3))

    def reset(self) -> None:
        self.state[:] = 0.0

    def next_noise(self) -> np.ndarray:
        """The next standard-normal sample (6,), unscaled."""
        if self.noise_index >= len(self.noise):
            self.noise = self.rng.standard_normal((NOISE_BLOCK, 6))
            self.noise_index = 0
        self.noise_index += 1
        return self.noise[self.noise_index - 1]

    def scales(self) -> np.ndarray:
        """(force std, moment std, cut-off Hz) as measure_into reads them."""
        p = self.params
        if self._scales[0] is not p:  # the params are frozen: a change is a new object
            self._scales = (p, np.array([p.force_noise_std, p.moment_noise_std, p.filter_cutoff_hz]))
        return self._scales[1]

    def measure(self, wrench_ee: np.ndarray, dt: float) -> np.ndarray:
        """One sample (6,) of F_ext from the true wrench_ee."""
        out = np.empty(6)
        measure_into(np.asarray(wrench_ee, float), self.next_noise(), self.scales(), dt, self.state, out)
        return out


@njit(cache=True)
def measure_into(wrench_ee, noise, scales, dt, state, out):
    """out = low-pass(wrench_ee + noise): noise[:3] scaled by the force std, noise[3:] by the moment
    std; the filter y <- y + a (x - y), a = dt / (tau + dt), tau = 1 / (2 pi f_c) (sim.signals.low_pass_gain;
    f_c <= 0 or the first sample: y = x). state = (y, has y)."""
    for i in range(6):
        out[i] = wrench_ee[i] + noise[i] * (scales[0] if i < 3 else scales[1])
    if scales[2] > 0.0 and state[6] != 0.0:
        a = low_pass_gain(dt, scales[2])
        for i in range(6):
            out[i] = state[i] + a * (out[i] - state[i])
    for i in range(6):
        state[i] = out[i]
    state[6] = 1.0
