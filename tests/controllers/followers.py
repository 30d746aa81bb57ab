"""Controllers that carry the box without being SP (load as followers.py:ClassName). Each must
FAIL the battery; docs/grading-battery.md says which items each loses (tests/e2e/test_law_checks.py)."""

import numpy as np

from sim.controllers.lifting_law import band_speed, saturate_twist
from sim.controllers.sp import SPController


class AdmittanceBand(SPController):
    """The issue's follower: the band on f_n, v_t = -0.05 f_t; no friction cone, no moment compliance."""

    def twist_ee(self, wrench_ee, params):
        fx, fy, fz = wrench_ee[:3]
        return saturate_twist(np.array([-0.05 * fx, -0.05 * fy, band_speed(fz, params)]), np.zeros(3), params)


class NoCone(SPController):
    """SP without the friction cone: the band and the moments as SP, but it always follows f_t
    (v_t = -k_t f_t, also inside the margin) and never raises the grip."""

    def twist_ee(self, wrench_ee, params):
        fx, fy, fz = wrench_ee[:3]
        twist = super().twist_ee(wrench_ee, params)
        twist[2] = band_speed(fz, params)
        if fz >= params.f_contact:
            twist[:2] = -params.k_t * np.array([fx, fy])
        return saturate_twist(twist[:3], twist[3:], params)
