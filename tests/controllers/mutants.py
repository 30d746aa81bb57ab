"""Controllers with one mistake each (load as mutants.py:ClassName), and the two that do nothing;
each must lose exactly the grader's items that test its mistake, or fall below the pass mark."""

import numpy as np

from sim.controllers.interface import LiftingParams
from sim.controllers.sp import SPController


class ZeroTwist:
    def reset(self):
        pass

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return np.zeros(6)


class Admittance(SPController):
    """A plain admittance follower: v = k (f_ref - f) along n, v_t = -0.05 f_t; no cone, no band
    logic, no moment compliance (filtered and rate-limited like SP, so it carries the box)."""

    def twist_ee(self, wrench_ee, params: LiftingParams):
        fx, fy, fz = wrench_ee[:3]
        v = np.array([-0.05 * fx, -0.05 * fy, params.k_n * (params.f_n_min + 2.5 - fz)])
        norm = np.linalg.norm(v)
        return np.concatenate((v * min(1.0, params.v_max / norm) if norm > 0 else v, np.zeros(3)))


class EEFrame(SPController):
    """Returns the twist in the EE frame (forgets R)."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return super().step(wrench_ee, np.eye(4), params, dt)


class TangentialFlipped(SPController):
    """Moves WITH f_t instead of against it."""

    def twist_ee(self, wrench_ee, params):
        twist = super().twist_ee(wrench_ee, params)
        twist[:2] = -twist[:2]
        return twist


class NoGripRaise(SPController):
    """Beyond the cone it follows but does not press toward f_n_max."""

    def twist_ee(self, wrench_ee, params):
        twist = super().twist_ee(wrench_ee, params)
        f_n = wrench_ee[2]
        if self.slipping and params.f_n_min <= f_n <= params.f_n_max:
            twist[2] = 0.0
        return twist


class BandTooWide(SPController):
    """start sets f_n_max = force + 10 N."""

    def start(self, params, force):
        params.f_n_min, params.f_n_band, params.running = force, 10.0, True
        return "started"

    def twist_ee(self, wrench_ee, params):
        wide = LiftingParams(**{**vars(params), "f_n_band": 10.0})
        return super().twist_ee(wrench_ee, wide)


class StartStopNoBand(SPController):
    """start/stop switch `running` but never set the band."""

    def start(self, params, force):
        params.running = True
        return "started"

    def stop(self, params):
        params.running = False
        return "stopped"


class MomentsHeld(SPController):
    """Holds every moment (no rotation)."""

    def twist_ee(self, wrench_ee, params):
        twist = super().twist_ee(wrench_ee, params)
        twist[3:] = 0.0
        return twist
