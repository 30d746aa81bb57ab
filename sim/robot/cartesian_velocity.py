"""franka-like Cartesian velocity interface with libfranka-style reflexes.

A command is the twist of the flange (EE) origin expressed in the base frame,
twist_base = [vx, vy, vz, wx, wy, wz] (m/s, rad/s), one per 1 ms control period.
It is turned into joint velocities with damped least squares and integrated:

    qdot = J^T (J J^T + lambda^2 I)^-1 twist_base + (I - J^+ J) k_null (q_rest - q)
    q    <- q + qdot dt

The null-space term keeps the redundant 7th DoF near the start posture; it does not move the EE.
A command that would break a limit is not followed: the robot stops (qdot = 0) and an error
state with the reason is raised, like libfranka's reflexes, until `recover()`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from sim.robot import panda
from sim.robot.panda import PandaModel


@dataclass
class VelocityLimits:
    """Panda limits checked on every command (SI units)."""

    cartesian_velocity: float = panda.CARTESIAN_VELOCITY_LIMIT  # m/s
    cartesian_angular_velocity: float = panda.CARTESIAN_ANGULAR_VELOCITY_LIMIT  # rad/s
    cartesian_acceleration: float = panda.CARTESIAN_ACCELERATION_LIMIT  # m/s^2
    cartesian_angular_acceleration: float = panda.CARTESIAN_ANGULAR_ACCELERATION_LIMIT  # rad/s^2
    joint_acceleration: np.ndarray | None = None  # rad/s^2, default Panda datasheet


class Reflex(Exception):
    """A limit violation (the message is the error reason)."""


class CartesianVelocityInterface:
    """The robot's joint state driven by Cartesian velocity (or joint velocity) commands."""

    damping = 0.02  # lambda of damped least squares (m)
    null_space_gain = 1.0  # 1/s, pull of the posture toward q_rest
    null_space_ramp = 0.5  # the posture term's rate of change, as a fraction of the joint acceleration limits

    def __init__(self, model: PandaModel, q: np.ndarray, limits: VelocityLimits | None = None) -> None:
        self.model = model
        self.limits = limits or VelocityLimits()
        self.qdd_max = (
            self.limits.joint_acceleration
            if self.limits.joint_acceleration is not None
            else panda.JOINT_ACCELERATION_LIMITS
        )
        self.reset(q)

    def reset(self, q: np.ndarray) -> None:
        """Put the robot at rest at q (rad) with no error."""
        self.q = np.array(q, dtype=float)
        self.q_rest = self.q.copy()
        self.qdot = np.zeros(self.model.nq)
        self.twist_base = np.zeros(6)  # last executed EE twist (base frame)
        self.twist_command = np.zeros(6)  # last accepted command (for the acceleration check)
        self.posture = np.zeros(self.model.nq)  # rad/s, last null-space posture term (ramped)
        self.error: str | None = None
        self.update_kinematics()

    def update_kinematics(self) -> None:
        self.transform_ee_to_base, self.jacobian = self.model.kinematics(self.q)

    # --- commands ---------------------------------------------------------------------------
    def command_twist(self, twist_base: np.ndarray, dt: float) -> None:
        """Execute one control period of an EE twist in the base frame (m/s, rad/s)."""
        if self.error is not None:
            self._halt()
            return
        twist = np.asarray(twist_base, dtype=float)
        if twist.shape != (6,):
            self.stop_with_error(self._reason(INVALID, -1, 0.0))
            return
        model, lim = self.model, self.limits
        # one kernel: finite numbers, the Cartesian limits, the posture ramp, damped least squares, the joint limits
        kind, j, value, qdot, posture = twist_to_joint_velocity(
            self.jacobian, twist, self.twist_command, self.q, self.qdot, self.posture, self.q_rest, dt,
            lim.cartesian_velocity, lim.cartesian_angular_velocity, lim.cartesian_acceleration,
            lim.cartesian_angular_acceleration, self.null_space_gain, self.null_space_ramp, self.damping**2,
            model.qdot_max, self.qdd_max, model.q_min, model.q_max,
        )
        if kind != OK:
            self.stop_with_error(self._reason(kind, j, value))
            return
        self.posture = posture
        self._integrate(qdot, dt)
        self.twist_command = twist.copy()

    def command_joint_velocity(self, qdot: np.ndarray, dt: float) -> None:
        """Execute one control period of joint velocities (rad/s), e.g. a joint-space motion."""
        if self.error is not None:
            self._halt()
            return
        try:
            qdot = np.asarray(qdot, dtype=float)
            if qdot.shape != (self.model.nq,) or not np.isfinite(qdot).all():
                raise Reflex("invalid command: joint velocity must be 7 finite numbers")
            kind, j, value = check_joint_limits(qdot, self.qdot, self.q, dt, self.model.qdot_max, self.qdd_max,
                                                self.model.q_min, self.model.q_max)
            if kind != OK:
                raise Reflex(self._reason(kind, j, value))
            self._integrate(qdot, dt)
            self.twist_command = self.twist_base.copy()
            self.posture[:] = 0.0  # a twist command after this motion ramps the posture term from zero
        except Reflex as reflex:
            self.stop_with_error(str(reflex))

    def recover(self) -> None:
        """Clear the reflex error (franka's automatic error recovery); the robot stays at rest."""
        self.error = None
        self._halt()

    # --- internals --------------------------------------------------------------------------
    def _reason(self, kind: int, j: int, value: float) -> str:
        """The reflex's message for a limit the kernels found broken (kind, joint or axis, value)."""
        model, lim = self.model, self.limits
        return {
            INVALID: lambda: "invalid command: twist must be 6 finite numbers",
            CARTESIAN_VELOCITY: lambda: f"cartesian velocity limit: |v| = {value:.3f} m/s > {lim.cartesian_velocity} m/s",
            CARTESIAN_ANGULAR_VELOCITY: lambda: (f"cartesian velocity limit: |w| = {value:.3f} rad/s > "
                                                 f"{lim.cartesian_angular_velocity} rad/s"),
            CARTESIAN_ACCELERATION: lambda: (f"cartesian acceleration limit: {value:.1f} m/s^2 > "
                                             f"{lim.cartesian_acceleration} m/s^2"),
            CARTESIAN_ANGULAR_ACCELERATION: lambda: (f"cartesian acceleration limit: {value:.1f} rad/s^2 > "
                                                     f"{lim.cartesian_angular_acceleration} rad/s^2"),
            VELOCITY: lambda: f"joint velocity limit: joint {j + 1} at {value:.3f} rad/s (limit {model.qdot_max[j]:.3f})",
            ACCELERATION: lambda: f"joint acceleration limit: joint {j + 1} at {value:.1f} rad/s^2 (limit {self.qdd_max[j]:.1f})",
            POSITION: lambda: (f"joint position limit: joint {j + 1} would reach {value:.3f} rad "
                               f"(range {model.q_min[j]:.3f}..{model.q_max[j]:.3f})"),
        }[kind]()

    def _integrate(self, qdot: np.ndarray, dt: float) -> None:
        """q <- q + qdot dt, then the flange pose, the Jacobian and the executed twist J qdot."""
        self.q = self.q + qdot * dt
        self.qdot = qdot
        self.update_kinematics()
        self.twist_base = self.jacobian @ qdot

    def _halt(self) -> None:
        self.posture[:] = 0.0
        self.qdot[:] = 0.0
        self.twist_base[:] = 0.0
        self.twist_command[:] = 0.0

    def stop_with_error(self, reason: str) -> None:
        """Halt (zero velocity) with `reason` as the error, as a reflex does."""
        self.error = reason
        self._halt()


OK, VELOCITY, ACCELERATION, POSITION = 0, 1, 2, 3
CARTESIAN_VELOCITY, CARTESIAN_ANGULAR_VELOCITY, CARTESIAN_ACCELERATION, CARTESIAN_ANGULAR_ACCELERATION = 4, 5, 6, 7
INVALID = 8  # not 6 finite numbers


@njit(cache=True)
def twist_to_joint_velocity(jac, twist, twist_prev, q, qdot_prev, posture, q_rest, dt, v_max, w_max, a_max, dw_max,
                            null_space_gain, null_space_ramp, damping2, qdot_max, qdd_max, q_min, q_max):
    """One Cartesian velocity command -> (kind, index, value, qdot, posture); kind OK or the first
    check failed, in libfranka's order: 6 finite numbers, |v|, |w|, the Cartesian accelerations,
    then (after DLS) the joint velocity, acceleration and position limits.
        posture <- posture + clip(k (q_rest - q) - posture, +-ramp qdd_max dt)  (a ramp: from rest
                   far from q_rest the term alone would exceed the joint acceleration limit)
        qdot = damped_least_squares(J, twist, posture)"""
    for i in range(6):
        if not math.isfinite(twist[i]):
            return INVALID, -1, 0.0, qdot_prev, posture
    v = math.sqrt(twist[0] * twist[0] + twist[1] * twist[1] + twist[2] * twist[2])
    w = math.sqrt(twist[3] * twist[3] + twist[4] * twist[4] + twist[5] * twist[5])
    if v > v_max:
        return CARTESIAN_VELOCITY, -1, v, qdot_prev, posture
    if w > w_max:
        return CARTESIAN_ANGULAR_VELOCITY, -1, w, qdot_prev, posture
    d = twist - twist_prev
    a = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / dt
    alpha = math.sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]) / dt
    if a > a_max:
        return CARTESIAN_ACCELERATION, -1, a, qdot_prev, posture
    if alpha > dw_max:
        return CARTESIAN_ANGULAR_ACCELERATION, -1, alpha, qdot_prev, posture
    step = null_space_ramp * qdd_max * dt
    posture_new = posture + np.minimum(np.maximum(null_space_gain * (q_rest - q) - posture, -step), step)
    qdot = damped_least_squares(jac, twist, posture_new, damping2)
    kind, j, value = check_joint_limits(qdot, qdot_prev, q, dt, qdot_max, qdd_max, q_min, q_max)
    return kind, j, value, qdot, posture_new


@njit(cache=True)
def damped_least_squares(jac, twist, posture, damping2):
    """qdot = J^T (J J^T + lambda^2 I)^-1 twist + (I - J^T (J J^T)^-1 J) posture.
    The null-space projector is undamped so that the posture term never moves the EE."""
    gram = jac @ jac.T
    damped = gram.copy()
    for i in range(6):
        damped[i, i] += damping2
        gram[i, i] += 1e-10
    qdot = jac.T @ np.linalg.solve(damped, twist)
    return qdot + posture - jac.T @ np.linalg.solve(gram, jac @ posture)


@njit(cache=True)
def check_joint_limits(qdot, qdot_prev, q, dt, qdot_max, qdd_max, q_min, q_max):
    """(kind, joint, value) of the first limit the step q + qdot dt would break; kind OK if none."""
    for j in range(q.shape[0]):
        if abs(qdot[j]) > qdot_max[j]:
            return VELOCITY, j, qdot[j]
    for j in range(q.shape[0]):
        qdd = abs(qdot[j] - qdot_prev[j]) / dt
        if qdd > qdd_max[j]:
            return ACCELERATION, j, qdd
    for j in range(q.shape[0]):
        q_next = q[j] + qdot[j] * dt
        if q_next < q_min[j] or q_next > q_max[j]:
            return POSITION, j, q_next
    return OK, -1, 0.0
