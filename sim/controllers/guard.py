"""A controller under guard: what a plug-in (a student's file) may not do to the robot.

Each step is checked: an exception, a twist that is not 6 finite numbers, steps slower than
`max_step` (`max_slow_steps` times within `window` steps: a one-off pause is forgiven) or an
average over `window` steps slower than `mean_step` raises ControllerFault, which the world turns
into an error state (zero twist, the robot stops) that says why, with the traceback. The
simulation and the server go on. Time is the thread's CPU time, so a busy machine (other
processes) does not count against the controller.
"""
from __future__ import annotations

import time
import traceback
from collections import deque
from dataclasses import dataclass

import numpy as np

from sim.controllers.interface import Controller, LiftingParams, start_lifting, stop_lifting


class ControllerFault(Exception):
    """Why a guarded controller was stopped (the message is for the student)."""


@dataclass(frozen=True)
class Budget:
    mean_step: float = 0.5e-3  # s, average over `window` steps
    max_step: float = 5e-3  # s, a single step
    max_slow_steps: int = 3  # steps beyond max_step tolerated within `window` minus one
    window: int = 1000


class GuardedController:
    def __init__(self, inner: Controller, budget: Budget = Budget()) -> None:
        self.inner = inner
        self.budget = budget
        self.name = type(inner).__name__
        self.durations: deque[float] = deque(maxlen=budget.window)

    def reset(self) -> None:
        self.durations.clear()
        self._call("reset")

    def step(self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
        started = time.thread_time()
        raw = self._call("step", wrench_ee, transform_ee_to_base, params, dt)
        elapsed = time.thread_time() - started
        self._check_time(elapsed)
        try:
            twist = np.asarray(raw, dtype=float)
        except (TypeError, ValueError):
            raise ControllerFault(f"{self.name}.step returned {type(raw).__name__}, not 6 numbers") from None
        if twist.shape != (6,):
            raise ControllerFault(f"{self.name}.step returned shape {twist.shape}, expected (6,) = [vx, vy, vz, wx, wy, wz]")
        if not np.all(np.isfinite(twist)):
            raise ControllerFault(f"{self.name}.step returned a non-finite twist {twist.tolist()}")
        return twist

    def _call(self, method: str, *args):
        try:
            return getattr(self.inner, method)(*args)
        except ControllerFault:
            raise
        except (Exception, SystemExit) as exc:  # noqa: BLE001 - any failure of the plug-in (even exit()) stops the robot
            trace = "".join(traceback.format_exception(exc))
            raise ControllerFault(f"{self.name}.{method} raised {type(exc).__name__}: {exc}\n{trace}") from None

    def _check_time(self, elapsed: float) -> None:
        budget = self.budget
        self.durations.append(elapsed)
        if elapsed > budget.max_step:
            slow = sum(1 for d in self.durations if d > budget.max_step)
            if slow >= budget.max_slow_steps:
                raise ControllerFault(
                    f"{self.name}.step took {elapsed * 1e3:.1f} ms in one step, {slow} steps over "
                    f"{budget.max_step * 1e3:g} ms within {len(self.durations)} (budget {budget.max_step * 1e3:g} ms)"
                )
        if len(self.durations) == budget.window:
            mean = sum(self.durations) / budget.window
            if mean > budget.mean_step:
                raise ControllerFault(
                    f"{self.name}.step took {mean * 1e3:.2f} ms on average over {budget.window} steps "
                    f"(budget {budget.mean_step * 1e3:g} ms)"
                )

    # the start/stop service handlers: the plug-in's own when it has them, else the lab's
    def start(self, params: LiftingParams, force: float) -> str:
        if callable(getattr(self.inner, "start", None)):
            return str(self._call("start", params, force))
        return start_lifting(params, force)

    def stop(self, params: LiftingParams) -> str:
        if callable(getattr(self.inner, "stop", None)):
            return str(self._call("stop", params))
        return stop_lifting(params)
