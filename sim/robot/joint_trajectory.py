"""Smooth joint-space motion (the lab's move_to_start): minimum-jerk in q.

q_ref(t) = q0 + (q1 - q0) s(t/T),  s = 10 tau^3 - 15 tau^4 + 6 tau^5
T = max(1.875 max|q1 - q0| / qdot_peak,                       (the fastest joint peaks at qdot_peak)
        max_i sqrt(5.77 |q1_i - q0_i| / (share qdd_max_i)),   (and accelerates at most at share x its limit)
        0.1 s)
qdot_cmd = q_ref'(t) + k (q_ref(t) - q)   (tracking feedback against integration drift)

A short motion at qdot_peak alone would accelerate beyond the joints' limits (its peak acceleration
is 5.77 |dq| / T^2, and T shrinks with |dq|): a move to start 0.026 rad away for joint 4 asked it for
14.8 rad/s^2 (limit 12.5), a reflex; libfranka's example motion generator bounds its motions by both
limits the same way.
"""

from __future__ import annotations

import numpy as np

from sim.robot.panda import JOINT_ACCELERATION_LIMITS
from sim.signals import MINIMUM_JERK_PEAK_ACCELERATION, minimum_jerk, minimum_jerk_rate

ACCELERATION_SHARE = 0.5  # of each joint's acceleration limit the reference uses at most: the feedback adds to it


class JointTrajectory:
    """Minimum-jerk from q_start to q_goal; `command(q, dt)` gives the joint velocity to send."""

    feedback_gain = 10.0  # 1/s

    def __init__(
        self,
        q_start: np.ndarray,
        q_goal: np.ndarray,
        peak_velocity: float = 0.5,
        acceleration_limits: np.ndarray = JOINT_ACCELERATION_LIMITS,
    ) -> None:
        """peak_velocity in rad/s; acceleration_limits per joint in rad/s^2 (the arm's qdd_max)."""
        self.q_start = np.array(q_start, float)
        self.q_goal = np.array(q_goal, float)
        distance = np.abs(self.q_goal - self.q_start)  # rad, per joint
        by_velocity = 1.875 * float(np.max(distance)) / peak_velocity  # s
        by_acceleration = float(
            np.sqrt(np.max(MINIMUM_JERK_PEAK_ACCELERATION * distance / (ACCELERATION_SHARE * acceleration_limits)))
        )  # s
        self.duration = max(by_velocity, by_acceleration, 0.1)  # s
        self.time = 0.0

    @property
    def progress(self) -> float:
        """0..1 share of the motion done."""
        return min(self.time / self.duration, 1.0)

    @property
    def done(self) -> bool:
        return self.time >= self.duration

    def command(self, q: np.ndarray, dt: float) -> np.ndarray:
        """Joint velocity (rad/s) for the next period dt (s)."""
        self.time += dt
        tau = self.progress
        delta = self.q_goal - self.q_start
        q_ref = self.q_start + delta * minimum_jerk(tau)
        qdot_ref = delta * minimum_jerk_rate(tau) / self.duration
        return qdot_ref + self.feedback_gain * (q_ref - q)


class JointBrake:
    """Bring the joints to rest at a constant deceleration (a cancelled motion, like franka's stop)."""

    def __init__(self, qdot: np.ndarray, deceleration: float = 2.0) -> None:
        self.qdot = np.array(qdot, float)
        self.deceleration = deceleration  # rad/s^2, below every Panda joint's limit
        self.progress = 1.0

    @property
    def done(self) -> bool:
        return not np.any(self.qdot)

    def command(self, q: np.ndarray, dt: float) -> np.ndarray:
        step = self.deceleration * dt
        self.qdot = np.sign(self.qdot) * np.maximum(np.abs(self.qdot) - step, 0.0)
        return self.qdot.copy()


class BrakeThenMove:
    """A motion asked for while the joints still move (e.g. a teleop jog): brake them to rest
    (JointBrake), then the minimum-jerk motion from where they stopped. Starting the trajectory at
    once would ask for a velocity jump, which the acceleration limits stop with a reflex."""

    def __init__(
        self,
        qdot: np.ndarray,
        q_now: np.ndarray,
        q_goal: np.ndarray,
        peak_velocity: float = 0.5,
        acceleration_limits: np.ndarray = JOINT_ACCELERATION_LIMITS,
    ) -> None:
        self.brake = JointBrake(qdot)
        self.q_goal = np.array(q_goal, float)
        self.peak_velocity = peak_velocity
        self.acceleration_limits = acceleration_limits
        self.move: JointTrajectory | None = None
        a = self.brake.deceleration
        braking = float(np.max(np.abs(qdot))) / a  # s until every joint is at rest
        q_stop = np.asarray(q_now) + np.sign(qdot) * np.square(qdot) / (2.0 * a)  # v^2 / 2a further on
        self.duration = braking + JointTrajectory(q_stop, q_goal, peak_velocity, acceleration_limits).duration  # s

    @property
    def progress(self) -> float:
        return self.move.progress if self.move is not None else 0.0

    @property
    def done(self) -> bool:
        return self.move is not None and self.move.done

    def command(self, q: np.ndarray, dt: float) -> np.ndarray:
        if not self.brake.done:
            return self.brake.command(q, dt)
        if self.move is None:
            self.move = JointTrajectory(q, self.q_goal, self.peak_velocity, self.acceleration_limits)
        return self.move.command(q, dt)
