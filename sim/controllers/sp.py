"""The Single Point (SP) controller: the lab's Algorithm 1 (Marullo et al., IEEE RA-L 2020) as
hri-lab reconstructs it. The paper's text was not at hand: every step, gain and sign below is our
reconstruction, documented here and in the README, and configurable through LiftingParams.

Model: the plate touches the box at a single point (the plate centre p_c) with Coulomb friction
mu. A point contact holds no moment, and its friction holds only inside the cone |f_t| <= mu f_n.

Sign convention: F_ext (wrench_ee) is the wrench the ROBOT applies to the box (franka's
K_F_ext_hat_K). Pressing gives f_n > 0. When the person lifts the box, the plate's friction
holds the box back, so f_t points DOWN and the robot must move UP: against f_t.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from sim.controllers.interface import (
    ALPHA, F_CONTACT, K_T, K_W, MOMENT_DEADBAND, MU, PLATE_OFFSET, LiftingParams, lifting_vector,
)
from sim.controllers.lifting_law import SLIPPING, SP, LiftingLawController, band_speed, grip_raise, saturate_twist


class SPController(LiftingLawController):
    """Single Point method: normal-force band, friction-cone tangential following, moment compliance.

    Step 0 (low-pass of F_ext), 5b (to the base frame) and 6 (rate limit) are the shared
    LiftingLawController's (sim/controllers/lifting_law.py); steps 1-5a are `sp_twist_ee` below
    (compiled; the world's compiled step runs it too)."""

    compiled_law = SP

    def __init__(self) -> None:
        self.reset()

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        """Steps 1-5a: the EE twist in the EE frame (m/s, rad/s), before the rate limit."""
        return sp_twist_ee(np.asarray(wrench_ee, dtype=float), lifting_vector(params), self.state)


@njit(cache=True)
def sp_twist_ee(wrench_ee, p, state):
    """Steps 1-5a of the SP method (p = lifting_vector(params); the slipping flag into state)."""
    # Step 1: decompose. n = EE z (plate normal); f_n = n.f; f_t = f - f_n n;
    # m_c = m - p_c x f (moment about the plate centre p_c = [0, 0, d]; p_c x f = [-d fy, d fx, 0]).
    fx, fy, fz, mx, my, mz = wrench_ee[0], wrench_ee[1], wrench_ee[2], wrench_ee[3], wrench_ee[4], wrench_ee[5]
    d = p[PLATE_OFFSET]
    f_n = fz
    mcx, mcy, mcz = mx + d * fy, my - d * fx, mz
    in_contact = f_n >= p[F_CONTACT]

    # Step 2: normal band [f_n_min, f_n_max] (lifting_law.band_speed):
    #   f_n < f_n_min -> v_n = +k_n (f_n_min - f_n)   (press, along +n)
    #   f_n > f_n_max -> v_n = -k_n (f_n - f_n_max)   (release, along -n)
    #   otherwise     -> v_n = 0
    v_n = band_speed(f_n, p)

    # Step 3: tangential following, only while in contact (without contact there is no cone,
    # and sensor noise alone must not move the robot sideways).
    #   limit = alpha mu f_n; |f_t| <= limit -> the contact holds: v_t = 0
    #   beyond: e_t = f_t - limit f_t/|f_t|, v_t = -k_t e_t (move against f_t, with the person)
    #   and raise the grip toward f_n_max: v_n = max(v_n, k_n (f_n_max - f_n)).
    vx = vy = 0.0
    ft_norm = math.hypot(fx, fy)
    limit = p[ALPHA] * p[MU] * max(f_n, 0.0)
    slipping = in_contact and ft_norm > limit
    state[SLIPPING] = 1.0 if slipping else 0.0
    if slipping:
        excess = 1.0 - limit / ft_norm  # e_t = excess * f_t
        vx, vy = -p[K_T] * excess * fx, -p[K_T] * excess * fy
        v_n = grip_raise(v_n, f_n, p)

    # Step 4: rotation. A single point holds no moment: comply with it,
    #   w = -k_w (|m_c| - db)+ m_c/|m_c|   (deadband db against noise).
    wx = wy = wz = 0.0
    mc_norm = math.sqrt(mcx * mcx + mcy * mcy + mcz * mcz)
    if in_contact and mc_norm > p[MOMENT_DEADBAND]:
        gain = -p[K_W] * (1.0 - p[MOMENT_DEADBAND] / mc_norm)
        wx, wy, wz = gain * mcx, gain * mcy, gain * mcz

    # Step 5a: twist_ee = [v_t + v_n n, w], saturated at v_max, w_max (direction kept).
    return saturate_twist(vx, vy, v_n, wx, wy, wz, p)
