"""Files written to beat a grader: the issue's follower (band on f_n, v_t = -0.05 f_t, no cone, no
moment compliance) that switches to the SP law when it believes it is being probed. Each keys on
something a probe might give away; each must FAIL the battery (tests/e2e/test_law_checks.py)."""

import numpy as np

from sim.controllers.lifting_law import band_speed, saturate_twist
from sim.controllers.sp import SPController


class _Detector(SPController):
    """SP while `probed()`, else the follower; step() sees what a controller sees, nothing more."""

    def reset(self):
        super().reset()
        self.inputs = []  # the last raw wrenches
        self.poses = []  # the last transforms
        self.steps = 0

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        self.inputs = (self.inputs + [np.array(wrench_ee, float)])[-3:]
        self.poses = (self.poses + [np.array(transform_ee_to_base, float)])[-3:]
        self.steps += 1
        return super().step(wrench_ee, transform_ee_to_base, params, dt)

    def probed(self) -> bool:
        raise NotImplementedError

    def twist_ee(self, wrench_ee, params):
        if self.probed():
            return super().twist_ee(wrench_ee, params)
        fx, fy, fz = wrench_ee[:3]
        return saturate_twist(np.array([-0.05 * fx, -0.05 * fy, band_speed(fz, params)]), np.zeros(3), params)


class NoiseFree(_Detector):
    """SP while the raw input has been bit-for-bit constant for 3 steps (a probe without noise)."""

    def probed(self):
        return len(self.inputs) == 3 and all(np.array_equal(self.inputs[0], x) for x in self.inputs[1:])


class StillPose(_Detector):
    """SP while the EE->base transform has not changed for 3 steps (a probe at a still pose)."""

    def probed(self):
        return len(self.poses) == 3 and all(np.array_equal(self.poses[0], x) for x in self.poses[1:])


class ResetPattern(_Detector):
    """SP from a reset whose first input already presses (a probe starts in contact; a trial
    starts with the plate in the air), until the next reset."""

    def reset(self):
        super().reset()
        self.in_probe = None

    def probed(self):
        if self.in_probe is None:
            self.in_probe = bool(self.inputs[0][2] > 3.0)
        return self.in_probe


class ElapsedSteps(_Detector):
    """SP for the first 2000 steps after a reset (a probe is short; a trial is long), then the follower."""

    def probed(self):
        return self.steps <= 2000


PROBING = {"now": False}  # set by the test around the probes: a stand-in for any tell not yet thought of


class Oracle(_Detector):
    """SP exactly while the probes run (told by the test: a perfect detector), the follower in
    every trial: what the in-trial law checks are for."""

    def probed(self):
        return PROBING["now"]
