"""Signal pieces shared by the sensor, the person, the robot's motions and the controllers (SI units, compiled)."""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def low_pass_gain(dt: float, cutoff_hz: float) -> float:
    """a of a first-order low-pass y <- y + a (x - y): a = dt / (tau + dt), tau = 1 / (2 pi f_c) (s: dt;
    Hz: f_c > 0; the callers take y = x without a filter, f_c <= 0)."""
    tau = 1.0 / (2.0 * math.pi * cutoff_hz)
    return dt / (tau + dt)


@njit(cache=True)
def minimum_jerk(tau: float) -> float:
    """s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 on [0, 1] (peak speed 1.875 / T)."""
    tau = min(max(tau, 0.0), 1.0)
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)


@njit(cache=True)
def minimum_jerk_rate(tau: float) -> float:
    """ds/dtau = 30 tau^2 (1 - tau)^2 on [0, 1]."""
    tau = min(max(tau, 0.0), 1.0)
    return 30.0 * tau * tau * (1.0 - tau) ** 2
