"""The pieces of the lifting law that the SP and patch controllers share (each step numbered as
in sim/controllers/sp.py). Forces in N, speeds in m/s and rad/s, gains in (m/s)/N.

A controller's state (the last command, the filtered F_ext, the slipping flag) is one array,
`LiftingLawController.state` (sim/state.py), so that the compiled world step can run a built-in
controller's law on it (sim/controllers/compiled_law.py); these classes stay plain Python, the
law of record that students read and subclass."""

from __future__ import annotations

import numpy as np

from sim.controllers.interface import LiftingController, LiftingParams
from sim.signals import cutoff_time_constant, saturate
from sim.spatial import rotate_twist
from sim.state import Field, Flag, allocate

# the controller's state array (sim/state.py)
TWIST_BASE, FILTERED, HAS_FILTERED, SLIPPING = 0, 6, 12, 13
SP, PATCH = 0, 1  # the built-in laws compiled_law.lifting_law_step runs


def band_speed(f_n: float, params: LiftingParams) -> float:
    """Step 2, the normal band [f_n_min, f_n_max]:
    f_n < f_n_min -> +k_n (f_n_min - f_n) (press, along +n); f_n > f_n_max -> -k_n (f_n - f_n_max)
    (release, along -n); inside -> 0."""
    if f_n < params.f_n_min:
        return params.k_n * (params.f_n_min - f_n)
    if f_n > params.f_n_max:
        return -params.k_n * (f_n - params.f_n_max)
    return 0.0


def grip_raise(v_n: float, f_n: float, params: LiftingParams) -> float:
    """Step 3's grip raise while the friction is beyond its margin: v_n = max(v_n, k_n (f_n_max - f_n))
    below f_n_max (press toward the top of the band, never above it)."""
    return max(v_n, params.k_n * (params.f_n_max - f_n)) if f_n < params.f_n_max else v_n


def saturate_twist(v: np.ndarray, w: np.ndarray, params: LiftingParams) -> np.ndarray:
    """Step 5a: twist = [v, w] with |v| <= v_max and |w| <= w_max (directions kept)."""
    return np.concatenate((saturate(v, params.v_max), saturate(w, params.w_max)))


def rate_limit(twist_previous: np.ndarray, twist_target: np.ndarray, params: LiftingParams, dt: float) -> np.ndarray:
    """Step 6: |dv| <= a_max dt and |dw| <= dw_max dt per control period (franka's limitRate idea)."""
    delta = twist_target - twist_previous
    return twist_previous + np.concatenate(
        (saturate(delta[:3], params.a_max * dt), saturate(delta[3:], params.dw_max * dt))
    )


class LiftingLawController(LiftingController):
    """Steps 0, 5b and 6 around a controller's own steps 1-5a (`twist_ee`):

    0. low-pass F_ext (first order, cut-off filter_hz) against the sensor noise;
    5b. twist_base = blockdiag(R, R) twist_ee, R = rotation EE -> base;
    6. rate limit, so noise never trips the robot's acceleration reflex."""

    compiled_law: int | None = None  # SP or PATCH, declared beside a built-in twist_ee (compiled_law.py)
    twist_base = Field(TWIST_BASE, 6)  # last command (for the rate limiter)
    wrench_filtered = Field(FILTERED, 6)  # step 0's output (sim.signals.LowPass's rule)
    has_filtered = Flag(HAS_FILTERED)
    slipping = Flag(SLIPPING)  # the friction was beyond its margin in the last step

    def reset(self) -> None:
        self.state = allocate(LiftingLawController)  # at rest, the filter empty

    def law(self) -> int | None:
        """The built-in law (SP, PATCH) the compiled step may run for this controller: the
        `compiled_law` declared by the class that defines its twist_ee; None when a subclass has
        its own twist_ee or its own step (then its step runs, in Python)."""
        cls = type(self)
        if cls not in _LAWS:
            owner = next(k for k in cls.__mro__ if "twist_ee" in vars(k))
            own_step = cls.step is not LiftingLawController.step
            _LAWS[cls] = None if own_step else vars(owner).get("compiled_law")
        return _LAWS[cls]

    def constants(self) -> np.ndarray:
        """The law's own numbers besides LiftingParams (the patch's plate), as the compiled law reads them."""
        return _NO_CONSTANTS

    def continue_from(self, twist_base: np.ndarray) -> None:
        """Bumpless take-over: step 6 starts from the running command twist_base (m/s, rad/s, base
        frame) instead of rest, so the first command differs from it by at most a_max dt, dw_max dt."""
        self.twist_base = twist_base

    def step(
        self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float
    ) -> np.ndarray:
        # step 0, first-order low-pass (sim.signals.LowPass): y = x without a filter or a first sample
        wrench = np.asarray(wrench_ee, dtype=float)
        time_constant = cutoff_time_constant(params.filter_hz)
        if time_constant is None or not self.has_filtered:
            self.wrench_filtered = wrench
        else:
            self.wrench_filtered = self.wrench_filtered + dt / (time_constant + dt) * (wrench - self.wrench_filtered)
        self.has_filtered = True
        wrench_filtered = self.wrench_filtered.copy()
        twist_ee = self.twist_ee(wrench_filtered, params) if params.running else np.zeros(6)
        twist_target = rotate_twist(transform_ee_to_base[:3, :3], twist_ee)  # step 5b
        self.twist_base = rate_limit(self.twist_base, twist_target, params, dt)  # step 6
        return self.twist_base.copy()

    def twist_ee(self, wrench_ee: np.ndarray, params: LiftingParams) -> np.ndarray:
        """Steps 1-5a: the EE twist in the EE frame (m/s, rad/s) from the filtered F_ext."""
        raise NotImplementedError


_NO_CONSTANTS = np.zeros(5)
_LAWS: dict[type, int | None] = {}  # a controller class -> its compiled law (LiftingLawController.law)
