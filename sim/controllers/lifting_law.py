"""The pieces of the lifting law that the SP and patch controllers share (each step numbered as
in sim/controllers/sp.py). Forces in N, speeds in m/s and rad/s, gains in (m/s)/N."""
from __future__ import annotations

import numpy as np

from sim.controllers.interface import LiftingController, LiftingParams
from sim.signals import LowPass, saturate
from sim.spatial import rotate_twist


def band_speed(f_n: float, params: LiftingParams) -> float:
    """Step 2, the normal band [f_n_min, f_n_max]:
    f_n < f_n_min -> +k_n (f_n_min - f_n) (press, along +n); f_n > f_n_max -> -k_n (f_n - f_n_max)
    (release, along -n); inside -> 0."""
    if f_n < params.f_n_min:
        return params.k_n * (params.f_n_min - f_n)
    if f_n > params.f_n_max:
        return -params.k_n * (f_n - params.f_n_max)
    return 0.0


def grip_raise(v_n: float, f_n: float, params: LiftingParams) -> float:
    """Step 3's grip raise while the friction is beyond its margin: v_n = max(v_n, k_n (f_n_max - f_n))
    below f_n_max (press toward the top of the band, never above it)."""
    return max(v_n, params.k_n * (params.f_n_max - f_n)) if f_n < params.f_n_max else v_n


def saturate_twist(v: np.ndarray, w: np.ndarray, params: LiftingParams) -> np.ndarray:
    """Step 5a: twist = [v, w] with |v| <= v_max and |w| <= w_max (directions kept)."""
    return np.concatenate((saturate(v, params.v_max), saturate(w, params.w_max)))


def rate_limit(twist_previous: np.ndarray, twist_target: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
    """Step 6: |dv| <= a_max dt and |dw| <= dw_max dt per control period (franka's limitRate idea)."""
    delta = twist_target - twist_previous
    return twist_previous + np.concatenate((saturate(delta[:3], params.a_max * dt), saturate(delta[3:], params.dw_max * dt)))


class LiftingLawController(LiftingController):
    """Steps 0, 5b and 6 around a controller's own steps 1-5a (`twist_ee`):

    0. low-pass F_ext (first order, cut-off filter_hz) against the sensor noise;
    5b. twist_base = blockdiag(R, R) twist_ee, R = rotation EE -> base;
    6. rate limit, so noise never trips the robot's acceleration reflex."""

    def reset(self) -> None:
        self.twist_base = np.zeros(6)  # last command (for the rate limiter)
        self.wrench_filter = LowPass()
        self.slipping = False  # the friction was beyond its margin in the last step

    def continue_from(self, twist_base: np.ndarray) -> None:
        """Bumpless take-over: step 6 starts from the running command twist_base (m/s, rad/s, base
        frame) instead of rest, so the first command differs from it by at most a_max dt, dw_max dt."""
        self.twist_base = np.array(twist_base, dtype=float)

    def step(self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
        wrench_filtered = self.wrench_filter.update_hz(np.asarray(wrench_ee, dtype=float), dt, params.filter_hz)  # step 0
        twist_ee = self.twist_ee(wrench_filtered, params) if params.running else np.zeros(6)
        twist_target = rotate_twist(transform_ee_to_base[:3, :3], twist_ee)  # step 5b
        self.twist_base = rate_limit(self.twist_base, twist_target, params, dt)  # step 6
        return self.twist_base.copy()

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        """Steps 1-5a: the EE twist in the EE frame (m/s, rad/s) from the filtered F_ext."""
        raise NotImplementedError
