"""External command: the robot follows twists that a node publishes (franka_ros's Cartesian
velocity controller on `/cartesian_velocity_controller/command`), with franka's rules:

- the command is held until the next one; a command not renewed within `period` (100 ms of
  simulation time) is a communication constraints violation: the robot stops (reflex error,
  cleared by error recovery), as libfranka does when the control loop misses its deadline;
- the command is rate limited like libfranka's `limit_rate` (|dv| <= a_max dt, |dw| <= dw_max dt,
  LiftingParams), so a step in the command is followed smoothly; a command beyond the Panda's
  velocity limits still trips the robot's reflex (the interface checks it);
- the limit starts from the running command (`continue_from`, as `limit_rate` starts from the last
  command sent): a node that takes over while the lab's controller moves the robot (its start
  service started the lab's lifting, its first twist comes later) does not jump the command.
The lab's `running` flag does not gate it: a node drives the robot while its commands are fresh.
"""

from __future__ import annotations

import numpy as np

from sim.controllers.interface import LiftingController, LiftingParams
from sim.controllers.lifting_law import rate_limit
from sim.robot.cartesian_velocity import Reflex

COMMAND_PERIOD = 0.1  # s of simulation time a command stays valid


class ExternalCommand(LiftingController):
    def __init__(self, period: float = COMMAND_PERIOD) -> None:
        self.period = period
        self.reset()

    def reset(self) -> None:
        """From rest, waiting for a first command (the watchdog is armed by it)."""
        self.twist_target = np.zeros(6)  # base frame, m/s and rad/s
        self.twist_base = np.zeros(6)  # last output (rate limited)
        self.age: float | None = None  # s since the last command; None: no command yet

    def continue_from(self, twist_base: np.ndarray) -> None:
        """Take over bumpless: the rate limit starts from the running command (base frame, m/s and rad/s)."""
        self.twist_base = np.asarray(twist_base, dtype=float).copy()

    def command(self, twist_base: np.ndarray) -> None:
        """A new command (6 finite numbers, base frame); renews the watchdog."""
        twist = np.asarray(twist_base, dtype=float)
        if twist.shape != (6,) or not np.all(np.isfinite(twist)):
            raise ValueError("a twist command is 6 finite numbers [vx, vy, vz, wx, wy, wz]")
        self.twist_target = twist.copy()
        self.age = 0.0

    def step(
        self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float
    ) -> np.ndarray:
        if self.age is not None:
            self.age += dt
            if self.age > self.period + 1e-9:
                age = self.age
                self.reset()
                raise Reflex(
                    f"communication constraints violation: no command on /cartesian_velocity_controller/command "
                    f"for {age * 1e3:.0f} ms (period {self.period * 1e3:.0f} ms)"
                )
        # limit_rate: twist <- twist + sat(target - twist), |dv| <= a_max dt, |dw| <= dw_max dt
        self.twist_base = rate_limit(self.twist_base, self.twist_target, params, dt)
        return self.twist_base.copy()
