"""Signal pieces shared by the sensor, the person, the robot's motions and the controllers (SI units)."""

from __future__ import annotations

import math

import numpy as np


def cutoff_time_constant(cutoff_hz: float) -> float | None:
    """tau = 1 / (2 pi f_c) (s) of a first-order low-pass with cut-off f_c (Hz); None for f_c <= 0 (no filter)."""
    return 1.0 / (2.0 * math.pi * cutoff_hz) if cutoff_hz > 0.0 else None


class LowPass:
    """First-order low-pass, y <- y + a (x - y), a = dt / (tau + dt).

    Without a time constant (tau None: filter off) or before the first sample, y = x."""

    def __init__(self, value: float | np.ndarray | None = None) -> None:
        self.value = value

    def reset(self, value: float | np.ndarray | None = None) -> None:
        self.value = value

    def update(self, x, dt: float, time_constant: float | None):
        """The filtered value after sample x (s: dt, time_constant)."""
        if time_constant is None or self.value is None:
            self.value = x.copy() if isinstance(x, np.ndarray) else float(x)
        else:
            self.value = self.value + dt / (time_constant + dt) * (x - self.value)
        return self.value

    def update_hz(self, x, dt: float, cutoff_hz: float):
        """update() with the cut-off frequency (Hz; <= 0: no filter)."""
        return self.update(x, dt, cutoff_time_constant(cutoff_hz))


def low_pass_gain(dt: float, cutoff_hz: float) -> float:
    """a of LowPass for a cut-off f_c > 0 (Hz): dt / (tau + dt), tau = 1 / (2 pi f_c) (plain Python that
    the compiled kernels compile too: sim/physics/sensor.py)."""
    tau = 1.0 / (2.0 * math.pi * cutoff_hz)
    return dt / (tau + dt)


def saturate(x: np.ndarray, limit: float) -> np.ndarray:
    """A 3-vector scaled down to |x| = limit if longer (direction kept)."""
    a, b, c = x.tolist()
    norm = math.sqrt(a * a + b * b + c * c)
    return x * (limit / norm) if norm > limit else x


def minimum_jerk(tau: float) -> float:
    """s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 on [0, 1] (peak speed 1.875 / T; compiled too, by
    sim/person/human.py)."""
    tau = min(max(tau, 0.0), 1.0)
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)


MINIMUM_JERK_PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)  # max |d2s/dtau2|, at tau = 1/2 -+ sqrt(3)/6


def minimum_jerk_rate(tau: float) -> float:
    """ds/dtau = 30 tau^2 (1 - tau)^2 on [0, 1]."""
    tau = min(max(tau, 0.0), 1.0)
    return 30.0 * tau * tau * (1.0 - tau) ** 2
