"""The Single Point (SP) controller: the lab's Algorithm 1 (Marullo et al., IEEE RA-L 2020) as
hri-lab reconstructs it. The paper's text was not at hand: every step, gain and sign below is our
reconstruction, configurable through LiftingParams. The steps' prose, with their reasons, is
docs/method.md ("The SP controller as hri-lab reconstructs it"); the numbered comments below mark
the lines that do each step.

Model: the plate touches the box at a single point (the plate centre p_c) with Coulomb friction
mu. A point contact holds no moment, and its friction holds only inside the cone |f_t| <= mu f_n.

Sign convention: F_ext (wrench_ee) is the wrench the ROBOT applies to the box (franka's
K_F_ext_hat_K). Pressing gives f_n > 0. When the person lifts the box, the plate's friction
holds the box back, so f_t points DOWN and the robot must move UP: against f_t.
"""

from __future__ import annotations

import math

import numpy as np

from sim.controllers.interface import LiftingParams
from sim.controllers.lifting_law import SP, LiftingLawController, band_speed, grip_raise, saturate_twist


class SPController(LiftingLawController):
    """Single Point method: normal-force band, friction-cone tangential following, moment compliance.

    Step 0 (low-pass of F_ext), 5b (to the base frame) and 6 (rate limit) are the shared
    LiftingLawController's (sim/controllers/lifting_law.py); steps 1-5a are here (and, compiled,
    in sim/controllers/compiled_law.py, tested equal)."""

    compiled_law = SP

    def __init__(self) -> None:
        self.reset()

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        """Steps 1-5a: the EE twist in the EE frame (m/s, rad/s), before the rate limit."""
        # Step 1: decompose. n = EE z (plate normal); f_n = n.f; f_t = f - f_n n;
        # m_c = m - p_c x f (moment about the plate centre p_c = [0, 0, d]; p_c x f = [-d fy, d fx, 0]).
        fx, fy, fz, mx, my, mz = np.asarray(wrench_ee, dtype=float).tolist()
        d = params.plate_offset
        f_n = fz
        mcx, mcy, mcz = mx + d * fy, my - d * fx, mz
        in_contact = f_n >= params.f_contact

        # Step 2: normal band [f_n_min, f_n_max] (lifting_law.band_speed):
        #   f_n < f_n_min -> v_n = +k_n (f_n_min - f_n)   (press, along +n)
        #   f_n > f_n_max -> v_n = -k_n (f_n - f_n_max)   (release, along -n)
        #   otherwise     -> v_n = 0
        v_n = band_speed(f_n, params)

        # Step 3: tangential following, only while in contact (without contact there is no cone,
        # and sensor noise alone must not move the robot sideways).
        #   limit = alpha mu f_n; |f_t| <= limit -> the contact holds: v_t = 0
        #   beyond: e_t = f_t - limit f_t/|f_t|, v_t = -k_t e_t (move against f_t, with the person)
        #   and raise the grip toward f_n_max: v_n = max(v_n, k_n (f_n_max - f_n)).
        vx = vy = 0.0
        ft_norm = math.hypot(fx, fy)
        limit = params.alpha * params.mu * max(f_n, 0.0)
        self.slipping = in_contact and ft_norm > limit
        if self.slipping:
            excess = 1.0 - limit / ft_norm  # e_t = excess * f_t
            vx, vy = -params.k_t * excess * fx, -params.k_t * excess * fy
            v_n = grip_raise(v_n, f_n, params)

        # Step 4: rotation. A single point holds no moment: comply with it,
        #   w = -k_w (|m_c| - db)+ m_c/|m_c|   (deadband db against noise).
        wx = wy = wz = 0.0
        mc_norm = math.sqrt(mcx * mcx + mcy * mcy + mcz * mcz)
        if in_contact and mc_norm > params.moment_deadband:
            gain = -params.k_w * (1.0 - params.moment_deadband / mc_norm)
            wx, wy, wz = gain * mcx, gain * mcy, gain * mcz

        # Step 5a: twist_ee = [v_t + v_n n, w], saturated at v_max, w_max (direction kept).
        return saturate_twist(np.array([vx, vy, v_n]), np.array([wx, wy, wz]), params)
