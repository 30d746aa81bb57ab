"""The pieces of the lifting law that the SP and patch controllers share (each step numbered as
in sim/controllers/sp.py). Forces in N, speeds in m/s and rad/s, gains in (m/s)/N.

The law is compiled (numba): a controller's state is one array (`LiftingLawController.state`),
its parameters the vector `lifting_vector(params)` (sim/controllers/interface.py), and
`lifting_law_step` (sim/controllers/builtin.py) runs steps 0-6 of a built-in controller in one
call, the same function the compiled world step (sim/compiled_step.py) runs. A subclass with its own `twist_ee` (steps 1-5a in
Python) still gets steps 0, 5b and 6 from here."""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from sim.controllers.interface import (
    A_MAX, DW_MAX, F_N_BAND, F_N_MIN, FILTER_HZ, K_N, RUNNING, V_MAX, W_MAX, LiftingController, LiftingParams,
    lifting_vector,
)
from sim.signals import low_pass_gain
from sim.state import Field, Flag, allocate

# the controller's state array (sim/state.py)
TWIST_BASE, FILTERED, HAS_FILTERED, SLIPPING = 0, 6, 12, 13
SP, PATCH = 0, 1  # the built-in laws lifting_law_step runs (twist_ee of sim/controllers/sp.py, patch.py)


@njit(cache=True)
def band_speed(f_n, p):
    """Step 2, the normal band [f_n_min, f_n_max] (p: lifting_vector):
    f_n < f_n_min -> +k_n (f_n_min - f_n) (press, along +n); f_n > f_n_max -> -k_n (f_n - f_n_max)
    (release, along -n); inside -> 0."""
    f_n_max = p[F_N_MIN] + p[F_N_BAND]
    if f_n < p[F_N_MIN]:
        return p[K_N] * (p[F_N_MIN] - f_n)
    if f_n > f_n_max:
        return -p[K_N] * (f_n - f_n_max)
    return 0.0


@njit(cache=True)
def grip_raise(v_n, f_n, p):
    """Step 3's grip raise while the friction is beyond its margin: v_n = max(v_n, k_n (f_n_max - f_n))
    below f_n_max (press toward the top of the band, never above it)."""
    f_n_max = p[F_N_MIN] + p[F_N_BAND]
    return max(v_n, p[K_N] * (f_n_max - f_n)) if f_n < f_n_max else v_n


@njit(cache=True)
def saturate_into(out, start, x, y, z, limit):
    """out[start:start+3] = (x, y, z) scaled down to length `limit` if longer (direction kept)."""
    norm = math.sqrt(x * x + y * y + z * z)
    scale = limit / norm if norm > limit else 1.0
    if norm > limit:
        out[start], out[start + 1], out[start + 2] = x * scale, y * scale, z * scale
    else:
        out[start], out[start + 1], out[start + 2] = x, y, z


@njit(cache=True)
def saturate_twist(vx, vy, vz, wx, wy, wz, p):
    """Step 5a: twist = [v, w] with |v| <= v_max and |w| <= w_max (directions kept)."""
    twist = np.empty(6)
    saturate_into(twist, 0, vx, vy, vz, p[V_MAX])
    saturate_into(twist, 3, wx, wy, wz, p[W_MAX])
    return twist


@njit(cache=True)
def rate_limit_into(previous, target, dv_max, dw_max, out):
    """Step 6: out = previous + (target - previous) with |dv| <= dv_max and |dw| <= dw_max."""
    delta = np.empty(6)
    saturate_into(delta, 0, target[0] - previous[0], target[1] - previous[1], target[2] - previous[2], dv_max)
    saturate_into(delta, 3, target[3] - previous[3], target[4] - previous[4], target[5] - previous[5], dw_max)
    for i in range(6):
        out[i] = previous[i] + delta[i]


def rate_limit(twist_previous: np.ndarray, twist_target: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
    """Step 6: |dv| <= a_max dt and |dw| <= dw_max dt per control period (franka's limitRate idea)."""
    out = np.empty(6)
    rate_limit_into(np.asarray(twist_previous, float), np.asarray(twist_target, float), params.a_max * dt,
                    params.dw_max * dt, out)
    return out


@njit(cache=True)
def low_pass(state, wrench_ee, p, dt):
    """Step 0: the filtered F_ext, y <- y + a (x - y), a = dt / (tau + dt), tau = 1 / (2 pi filter_hz)
    (sim.signals.low_pass_gain; no filter for filter_hz <= 0 and at the first sample)."""
    filtered = state[FILTERED:FILTERED + 6]
    if p[FILTER_HZ] > 0.0 and state[HAS_FILTERED] != 0.0:
        a = low_pass_gain(dt, p[FILTER_HZ])
        for i in range(6):
            filtered[i] = filtered[i] + a * (wrench_ee[i] - filtered[i])
    else:
        filtered[:] = wrench_ee
    state[HAS_FILTERED] = 1.0
    return filtered.copy()


@njit(cache=True)
def to_base_rate_limited(state, p, twist_ee, rotation, dt, out):
    """Steps 5b and 6: twist_base = blockdiag(R, R) twist_ee, then rate limited from the last command."""
    target = np.empty(6)
    target[:3] = rotation @ twist_ee[:3]
    target[3:] = rotation @ twist_ee[3:]
    previous = state[TWIST_BASE:TWIST_BASE + 6]
    rate_limit_into(previous.copy(), target, p[A_MAX] * dt, p[DW_MAX] * dt, out)
    previous[:] = out


class LiftingLawController(LiftingController):
    """Steps 0, 5b and 6 around a controller's own steps 1-5a (`twist_ee`):

    0. low-pass F_ext (first order, cut-off filter_hz) against the sensor noise;
    5b. twist_base = blockdiag(R, R) twist_ee, R = rotation EE -> base;
    6. rate limit, so noise never trips the robot's acceleration reflex."""

    compiled_law: int | None = None  # SP or PATCH, declared beside a built-in twist_ee that is compiled
    twist_base = Field(TWIST_BASE, 6)  # last command (for the rate limiter)
    slipping = Flag(SLIPPING)  # the friction was beyond its margin in the last step

    def reset(self) -> None:
        self.state = allocate(LiftingLawController)  # from rest, the filter empty

    def constants(self) -> np.ndarray:
        """The law's own constants (the patch's plate), as patch_twist_ee reads them."""
        return _NO_CONSTANTS

    def law(self) -> int | None:
        """The compiled law (SP, PATCH) this controller runs: the `compiled_law` declared by the
        class that defines its twist_ee; None when a subclass has its own twist_ee (in Python)."""
        cls = type(self)
        if cls not in _LAWS:
            owner = next(k for k in cls.__mro__ if "twist_ee" in vars(k))
            _LAWS[cls] = vars(owner).get("compiled_law")
        return _LAWS[cls]

    def continue_from(self, twist_base: np.ndarray) -> None:
        """Bumpless take-over: step 6 starts from the running command twist_base (m/s, rad/s, base
        frame) instead of rest, so the first command differs from it by at most a_max dt, dw_max dt."""
        self.twist_base = twist_base

    def step(self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
        p = lifting_vector(params)
        wrench = np.asarray(wrench_ee, dtype=float)
        rotation = np.ascontiguousarray(transform_ee_to_base[:3, :3], dtype=float)
        out = np.empty(6)
        kind = self.law()
        if kind is not None:
            from sim.controllers.builtin import lifting_law_step  # the built-ins import this module

            lifting_law_step(kind, self.state, p, self.constants(), wrench, rotation, dt, out)
            return out
        filtered = low_pass(self.state, wrench, p, dt)  # step 0
        twist_ee = np.asarray(self.twist_ee(filtered, params), float) if params.running else np.zeros(6)
        to_base_rate_limited(self.state, p, twist_ee, rotation, dt, out)  # steps 5b, 6
        return out

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        """Steps 1-5a: the EE twist in the EE frame (m/s, rad/s) from the filtered F_ext."""
        raise NotImplementedError


_NO_CONSTANTS = np.zeros(5)
_LAWS: dict[type, int | None] = {}  # a controller class -> its compiled law (LiftingLawController.law)
