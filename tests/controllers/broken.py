"""Controllers with one bug each, for the grader's tests (load as broken.py:ClassName)."""

import time

import numpy as np

from sim.controllers.interface import LiftingParams
from sim.controllers.sp import SPController


class FlippedNormal(SPController):
    """Presses when it should release and releases when it should press (sign of n flipped)."""

    def twist_ee(self, wrench_ee, params):
        twist = super().twist_ee(wrench_ee, params)
        twist[2] = -twist[2]
        return twist


class EEFrameTwist(SPController):
    """Returns the twist in the EE frame (forgets R)."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return super().step(wrench_ee, np.eye(4), params, dt)


class NoTangential(SPController):
    """Never follows tangentially (the cone margin is infinite)."""

    def twist_ee(self, wrench_ee, params: LiftingParams):
        lazy = LiftingParams(**{**vars(params), "alpha": 1e6})
        return super().twist_ee(wrench_ee, lazy)


class Raising:
    """A bug in step (no start/stop of its own: the lab's semantics start it)."""

    def reset(self):
        pass

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        raise ZeroDivisionError("oops, a bug in step")


class ReturnsNaN(SPController):
    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return np.full(6, np.nan)


class TooSlow(SPController):
    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        end = time.thread_time() + 0.006  # 6 ms of CPU per step: beyond the 5 ms budget
        while time.thread_time() < end:
            pass
        return super().step(wrench_ee, transform_ee_to_base, params, dt)
