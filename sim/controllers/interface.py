"""The controller interface (the grading plug-in point) and the lifting parameters.

A controller maps the measured F_ext to an EE twist command:
    step(wrench_ee, transform_ee_to_base, params, dt) -> twist_base
wrench_ee = [fx, fy, fz, mx, my, mz] (N, Nm), the wrench the robot applies, at the EE origin, in
the EE frame; the twist [vx, vy, vz, wx, wy, wz] (m/s, rad/s) is the EE's, in the base frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from sim.ranges import range_refusal
from sim.robot.plate import Plate


@dataclass
class LiftingParams:
    """Parameters of cooperative lifting (node `cooperative_lifting`)."""

    running: bool = False  # set by start/stop_cooperative_lifting
    f_n_min: float = 0.0  # N, lower end of the normal-force band
    f_n_band: float = 5.0  # N, f_n_max = f_n_min + f_n_band
    mu: float = 0.5  # friction coefficient the controller assumes (plate on box)
    alpha: float = 0.5  # safety margin on the friction cone (< 1); chosen from bench/margin_sweep.py (docs/method.md)
    k_n: float = 0.005  # (m/s)/N, normal force -> normal speed
    k_t: float = 0.1  # (m/s)/N, tangential excess force -> tangential speed
    k_w: float = 1.0  # (rad/s)/Nm, moment at the plate centre -> angular speed
    moment_deadband: float = 0.1  # Nm, moments below this are noise
    f_contact: float = 1.0  # N, f_n above which the plate is considered in contact
    v_max: float = 0.5  # m/s, twist saturation (linear)
    w_max: float = 1.0  # rad/s, twist saturation (angular)
    a_max: float = 1.0  # m/s^2, rate limit of the commanded linear velocity
    dw_max: float = 2.0  # rad/s^2, rate limit of the commanded angular velocity
    filter_hz: float = 10.0  # Hz, cut-off of the controller's low-pass on F_ext (0 = none)
    plate_offset: float = Plate.offset  # m, plate centre along EE +z (the mounted plate's)

    @property
    def f_n_max(self) -> float:
        """Upper end of the band (N): f_n_min + f_n_band (= force + f_n_band after start; docs/method.md, step 2)."""
        return self.f_n_min + self.f_n_band


# the declared range of each lifting parameter the lab lets be set (app/lab/params.py declares them
# with these; the start service's force is f_n_min's): a plug-in's start()/stop() is held to them too
LIFTING_RANGES: dict[str, tuple[float, float]] = {
    "f_n_min": (0.0, 60.0),  # N
    "f_n_band": (0.5, 30.0),  # N
    "mu": (0.05, 2.0),
    "alpha": (0.1, 1.0),
    "k_n": (0.0, 0.1),  # (m/s)/N
    "k_t": (0.0, 1.0),  # (m/s)/N
    "k_w": (0.0, 10.0),  # (rad/s)/Nm
    "moment_deadband": (0.0, 2.0),  # Nm
    "v_max": (0.0, 1.7),  # m/s
    "w_max": (0.0, 2.5),  # rad/s
    "filter_hz": (0.0, 500.0),  # Hz
}


def lifting_refusal(values: dict[str, float]) -> str:
    """Why these lifting values cannot be taken (the parameter server's refusal of the first out of
    its declared range, with the value and the range), '' when all comply."""
    for name, value in values.items():
        if name in LIFTING_RANGES:
            low, high = LIFTING_RANGES[name]
            if refusal := range_refusal(name, value, low, high):
                return f"{refusal} ({name} = {value!r}, range {low:g} to {high:g})"
    return ""


LIFTING_FIELDS = tuple(LiftingParams.__dataclass_fields__)  # the order of lifting_vector
(
    RUNNING,
    F_N_MIN,
    F_N_BAND,
    MU,
    ALPHA,
    K_N,
    K_T,
    K_W,
    MOMENT_DEADBAND,
    F_CONTACT,
    V_MAX,
    W_MAX,
    A_MAX,
    DW_MAX,
    FILTER_HZ,
    PLATE_OFFSET,
) = range(len(LIFTING_FIELDS))


def lifting_vector(params: LiftingParams) -> np.ndarray:
    """The parameters as the compiled controllers read them (indices RUNNING ... PLATE_OFFSET)."""
    return np.array([float(getattr(params, name)) for name in LIFTING_FIELDS])


def start_lifting(params: LiftingParams, force: float) -> str:
    """The start_cooperative_lifting service: f_n_min = force, f_n_max = force + band, start."""
    force = float(force)
    if not np.isfinite(force) or force < 0.0:
        raise ValueError(f"force must be a finite number >= 0, got {force}")
    params.f_n_min = force
    params.running = True
    return f"Cooperative Lifting started with f_n_min = {force:g} N, f_n_max = {params.f_n_max:g} N."


def stop_lifting(params: LiftingParams) -> str:
    """The stop_cooperative_lifting service: f_n_min = 0, stop (zero twist)."""
    params.f_n_min = 0.0
    params.running = False
    return "Cooperative Lifting was stopped! Force limit f_n_min reset to 0 N."


class ControllerFault(Exception):
    """Why a controller was stopped (a student's plug-in: sim/controllers/sandbox/); the world
    turns it into an error state, the message is for the student."""


@runtime_checkable
class Controller(Protocol):
    def reset(self) -> None: ...

    def step(
        self, wrench_ee: np.ndarray, transform_ee_to_base: np.ndarray, params: LiftingParams, dt: float
    ) -> np.ndarray:
        """wrench_ee: F_ext (6,) in the EE frame. Returns the twist (6,) of the EE in the base frame."""
        ...

    def start(self, params: LiftingParams, force: float) -> str:
        """The start_cooperative_lifting handler (its message)."""
        ...

    def stop(self, params: LiftingParams) -> str:
        """The stop_cooperative_lifting handler (its message)."""
        ...


class LiftingController:
    """Base of the lab's controllers: the lab's start/stop semantics."""

    def reset(self) -> None:
        pass

    def start(self, params: LiftingParams, force: float) -> str:
        return start_lifting(params, force)

    def stop(self, params: LiftingParams) -> str:
        return stop_lifting(params)


class ZeroController(LiftingController):
    """Commands zero twist (a robot that does not follow)."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt) -> np.ndarray:
        return np.zeros(6)
