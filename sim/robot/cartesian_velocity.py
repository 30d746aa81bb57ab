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
from sim.robot.panda_kinematics import chain_kinematics
from sim.state import Field, Flag, allocate


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


# the robot's state array (sim/state.py): what arm_command_twist reads and writes
Q, QDOT, TWIST_BASE, TWIST_COMMAND, POSTURE, Q_REST, ERROR, TRANSFORM, JACOBIAN, STATE_SIZE = (
    0,
    7,
    14,
    20,
    26,
    33,
    40,
    41,
    57,
    99,
)
# the interface's constants array: the scalars, then qdot_max, qdd_max, q_min, q_max (7 each)
V_MAX, W_MAX, A_MAX, DW_MAX, NULL_GAIN, NULL_RAMP, DAMPING2 = range(7)
QDOT_MAX, QDD_MAX, Q_MIN, Q_MAX = 7, 14, 21, 28


class CartesianVelocityInterface:
    """The robot's joint state driven by Cartesian velocity (or joint velocity) commands.

    The state lives in `self.state` (q, qdot, the executed and commanded twists, the posture
    term, the flange pose and Jacobian, the error flag); the attributes are views of it, and the
    compiled step advances it with `arm_command_twist`, the same kernel `command_twist` runs."""

    damping = 0.02  # lambda of damped least squares (m)
    null_space_gain = 1.0  # 1/s, pull of the posture toward q_rest
    null_space_ramp = 0.5  # the posture term's rate of change, as a fraction of the joint acceleration limits

    q = Field(Q, 7)  # rad
    qdot = Field(QDOT, 7)  # rad/s
    twist_base = Field(TWIST_BASE, 6)  # last executed EE twist (base frame)
    twist_command = Field(TWIST_COMMAND, 6)  # last accepted command (for the acceleration check)
    posture = Field(POSTURE, 7)  # rad/s, last null-space posture term (ramped)
    q_rest = Field(Q_REST, 7)  # rad, the posture the null space pulls toward
    has_error = Flag(ERROR)  # the error flag the compiled step sees (the reason is `error`)
    transform_ee_to_base = Field(TRANSFORM, 4, 4)
    jacobian = Field(JACOBIAN, 6, 7)  # flange Jacobian, base frame (LOCAL_WORLD_ALIGNED)

    def __init__(self, model: PandaModel, q: np.ndarray, limits: VelocityLimits | None = None) -> None:
        self.model = model
        self.chain = model.chain
        self.limits = limits or VelocityLimits()
        self.qdd_max = (
            self.limits.joint_acceleration
            if self.limits.joint_acceleration is not None
            else panda.JOINT_ACCELERATION_LIMITS
        )
        self.state = allocate(CartesianVelocityInterface)
        self._error: str | None = None
        self.reset(q)

    def constants(self) -> np.ndarray:
        """The limits and gains as the kernels read them (layout: V_MAX ... Q_MAX above)."""
        lim, model = self.limits, self.model
        return np.concatenate(
            (
                [
                    lim.cartesian_velocity,
                    lim.cartesian_angular_velocity,
                    lim.cartesian_acceleration,
                    lim.cartesian_angular_acceleration,
                    self.null_space_gain,
                    self.null_space_ramp,
                    self.damping**2,
                ],
                model.qdot_max,
                self.qdd_max,
                model.q_min,
                model.q_max,
            )
        )

    @property
    def error(self) -> str | None:
        """The reflex's reason; None without error."""
        return self._error

    @error.setter
    def error(self, reason: str | None) -> None:
        self._error = reason
        self.has_error = reason is not None

    def reset(self, q: np.ndarray) -> None:
        """Put the robot at rest at q (rad) with no error."""
        self.q = np.array(q, dtype=float)
        self.q_rest = self.q
        self.qdot = 0.0
        self.twist_base = 0.0
        self.twist_command = 0.0
        self.posture = 0.0
        self.error = None
        self.update_kinematics()

    def update_kinematics(self) -> None:
        c = self.chain
        chain_kinematics(
            self.q,
            c.rotations,
            c.translations,
            c.axes,
            c.flange_rotation,
            c.flange_translation,
            self.transform_ee_to_base,
            self.jacobian,
        )

    # --- commands ---------------------------------------------------------------------------
    def command_twist(self, twist_base: np.ndarray, dt: float) -> None:
        """Execute one control period of an EE twist in the base frame (m/s, rad/s)."""
        if self.error is not None:
            self._halt()
            return
        twist = np.asarray(twist_base, dtype=float)
        if twist.shape != (6,):
            self.stop_with_error(self.reflex_reason(INVALID, -1, 0.0))
            return
        c = self.chain
        kind, j, value = arm_command_twist(
            self.state,
            twist,
            dt,
            self.constants(),
            c.rotations,
            c.translations,
            c.axes,
            c.flange_rotation,
            c.flange_translation,
        )
        if kind != OK:
            self.stop_with_error(self.reflex_reason(kind, j, value))

    def command_joint_velocity(self, qdot: np.ndarray, dt: float) -> None:
        """Execute one control period of joint velocities (rad/s), e.g. a joint-space motion."""
        if self.error is not None:
            self._halt()
            return
        try:
            qdot = np.asarray(qdot, dtype=float)
            if qdot.shape != (self.model.nq,) or not np.isfinite(qdot).all():
                raise Reflex("invalid command: joint velocity must be 7 finite numbers")
            kind, j, value = check_joint_limits(
                qdot, self.qdot, self.q, dt, self.model.qdot_max, self.qdd_max, self.model.q_min, self.model.q_max
            )
            if kind != OK:
                raise Reflex(self.reflex_reason(kind, j, value))
            self._integrate(qdot, dt)
            self.twist_command = self.twist_base
            self.posture = 0.0  # a twist command after this motion ramps the posture term from zero
        except Reflex as reflex:
            self.stop_with_error(str(reflex))

    def recover(self) -> None:
        """Clear the reflex error (franka's automatic error recovery); the robot stays at rest."""
        self.error = None
        self._halt()

    # --- internals --------------------------------------------------------------------------
    def reflex_reason(self, kind: int, j: int, value: float) -> str:
        """The reflex's message for a limit the kernels found broken (kind, joint or axis, value)."""
        model, lim = self.model, self.limits
        return {
            INVALID: lambda: "invalid command: twist must be 6 finite numbers",
            CARTESIAN_VELOCITY: lambda: (
                f"cartesian velocity limit: |v| = {value:.3f} m/s > {lim.cartesian_velocity} m/s"
            ),
            CARTESIAN_ANGULAR_VELOCITY: lambda: (
                f"cartesian velocity limit: |w| = {value:.3f} rad/s > {lim.cartesian_angular_velocity} rad/s"
            ),
            CARTESIAN_ACCELERATION: lambda: (
                f"cartesian acceleration limit: {value:.1f} m/s^2 > {lim.cartesian_acceleration} m/s^2"
            ),
            CARTESIAN_ANGULAR_ACCELERATION: lambda: (
                f"cartesian acceleration limit: {value:.1f} rad/s^2 > {lim.cartesian_angular_acceleration} rad/s^2"
            ),
            VELOCITY: lambda: (
                f"joint velocity limit: joint {j + 1} at {value:.3f} rad/s (limit {model.qdot_max[j]:.3f})"
            ),
            ACCELERATION: lambda: (
                f"joint acceleration limit: joint {j + 1} at {value:.1f} rad/s^2 (limit {self.qdd_max[j]:.1f})"
            ),
            POSITION: lambda: (
                f"joint position limit: joint {j + 1} would reach {value:.3f} rad "
                f"(range {model.q_min[j]:.3f}..{model.q_max[j]:.3f})"
            ),
        }[kind]()

    def _integrate(self, qdot: np.ndarray, dt: float) -> None:
        """q <- q + qdot dt, then the flange pose, the Jacobian and the executed twist J qdot."""
        self.q = self.q + qdot * dt
        self.qdot = qdot
        self.update_kinematics()
        self.twist_base = self.jacobian @ qdot

    def _halt(self) -> None:
        self.state[POSTURE : POSTURE + 7] = 0.0
        self.state[QDOT : QDOT + 7] = 0.0
        self.state[TWIST_BASE : TWIST_BASE + 6] = 0.0
        self.state[TWIST_COMMAND : TWIST_COMMAND + 6] = 0.0

    def stop_with_error(self, reason: str) -> None:
        """Halt (zero velocity) with `reason` as the error, as a reflex does."""
        self.error = reason
        self._halt()


OK, VELOCITY, ACCELERATION, POSITION = 0, 1, 2, 3
CARTESIAN_VELOCITY, CARTESIAN_ANGULAR_VELOCITY, CARTESIAN_ACCELERATION, CARTESIAN_ANGULAR_ACCELERATION = 4, 5, 6, 7
INVALID = 8  # not 6 finite numbers


@njit(cache=True)
def twist_to_joint_velocity(
    jac,
    twist,
    twist_prev,
    q,
    qdot_prev,
    posture,
    q_rest,
    dt,
    v_max,
    w_max,
    a_max,
    dw_max,
    null_space_gain,
    null_space_ramp,
    damping2,
    qdot_max,
    qdd_max,
    q_min,
    q_max,
):
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
    The null-space projector is undamped so that the posture term never moves the EE.
    (J J^T + lambda^2 I and J J^T + 1e-10 I are symmetric positive definite: Cholesky solves.)"""
    rows, cols = jac.shape
    gram = np.zeros((rows, rows))
    for i in range(rows):
        for j in range(i + 1):
            acc = 0.0
            for k in range(cols):
                acc += jac[i, k] * jac[j, k]
            gram[i, j] = gram[j, i] = acc
    damped = gram.copy()
    for i in range(rows):
        damped[i, i] += damping2
        gram[i, i] += 1e-10
    jp = np.zeros(rows)
    for i in range(rows):
        for k in range(cols):
            jp[i] += jac[i, k] * posture[k]
    y = _cholesky_solve(damped, twist)
    z = _cholesky_solve(gram, jp)
    qdot = np.empty(cols)
    for k in range(cols):
        acc = posture[k]
        for i in range(rows):
            acc += jac[i, k] * (y[i] - z[i])
        qdot[k] = acc
    return qdot


@njit(cache=True)
def _cholesky_solve(a, b):
    """x with a x = b, a symmetric positive definite (a = L L^T, then two triangular solves)."""
    n = a.shape[0]
    low = np.zeros((n, n))
    for i in range(n):
        for j in range(i + 1):
            acc = a[i, j]
            for k in range(j):
                acc -= low[i, k] * low[j, k]
            if i == j:
                low[i, i] = math.sqrt(acc) if acc > 0.0 else 1e-300
            else:
                low[i, j] = acc / low[j, j]
    y = np.empty(n)
    for i in range(n):
        acc = b[i]
        for k in range(i):
            acc -= low[i, k] * y[k]
        y[i] = acc / low[i, i]
    x = np.empty(n)
    for i in range(n - 1, -1, -1):
        acc = y[i]
        for k in range(i + 1, n):
            acc -= low[k, i] * x[k]
        x[i] = acc / low[i, i]
    return x


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


@njit(cache=True)
def arm_command_twist(state, twist, dt, constants, rotations, translations, axes, flange_rotation, flange_translation):
    """One control period of a twist command on the state array (CartesianVelocityInterface's
    layout): with the error flag set, the robot stays halted; a command breaking a limit halts it
    and sets the flag; otherwise q <- q + qdot dt with the flange pose, Jacobian and executed
    twist J qdot. Returns (kind, joint or axis, value) of the broken limit, kind OK if none."""
    q, qdot_prev = state[Q : Q + 7], state[QDOT : QDOT + 7]
    twist_base, twist_command = state[TWIST_BASE : TWIST_BASE + 6], state[TWIST_COMMAND : TWIST_COMMAND + 6]
    posture = state[POSTURE : POSTURE + 7]
    if state[ERROR] != 0.0:
        posture[:] = 0.0
        qdot_prev[:] = 0.0
        twist_base[:] = 0.0
        twist_command[:] = 0.0
        return OK, -1, 0.0
    c = constants
    transform = state[TRANSFORM : TRANSFORM + 16].reshape((4, 4))
    jacobian = state[JACOBIAN : JACOBIAN + 42].reshape((6, 7))
    kind, j, value, qdot, posture_new = twist_to_joint_velocity(
        jacobian,
        twist,
        twist_command,
        q,
        qdot_prev,
        posture,
        state[Q_REST : Q_REST + 7],
        dt,
        c[V_MAX],
        c[W_MAX],
        c[A_MAX],
        c[DW_MAX],
        c[NULL_GAIN],
        c[NULL_RAMP],
        c[DAMPING2],
        c[QDOT_MAX : QDOT_MAX + 7],
        c[QDD_MAX : QDD_MAX + 7],
        c[Q_MIN : Q_MIN + 7],
        c[Q_MAX : Q_MAX + 7],
    )
    if kind != OK:
        state[ERROR] = 1.0
        posture[:] = 0.0
        qdot_prev[:] = 0.0
        twist_base[:] = 0.0
        twist_command[:] = 0.0
        return kind, j, value
    posture[:] = posture_new
    for i in range(7):
        q[i] += qdot[i] * dt
        qdot_prev[i] = qdot[i]
    chain_kinematics(q, rotations, translations, axes, flange_rotation, flange_translation, transform, jacobian)
    for i in range(6):
        acc = 0.0
        for k in range(7):
            acc += jacobian[i, k] * qdot[k]
        twist_base[i] = acc
    twist_command[:] = twist
    return OK, -1, 0.0
