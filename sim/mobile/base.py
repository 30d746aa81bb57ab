"""The differential-drive base, TurtleBot3 Burger-like: its figures and its compiled kinematic step.

The base is kinematic (no masses, no forces): it follows the commanded twist (v forward, w about z)
within its limits, reaching it at most as fast as its accelerations allow; the wheels turn as the
twist asks ((v -+ w L/2) / r); the body moves as the wheels' true rolling radii carry it; the
odometry integrates the wheels with the nominal radius. A wheel whose true radius differs from the
nominal (`BaseSpec.wheel_radius_error`, drawn per world: wheel-slip and tyre wear) makes the
odometry drift from the true pose, as a real base's does.

Contact: the base is a disc (`footprint_radius`); a step that would take it into a wall or an
obstacle leaves it touching the surface (the motion into it is stopped, the motion along it is
kept: a bumper sliding along a wall), and the step reports what it touched. The wheels still turn
(they slip), so the odometry runs on while the true pose does not.

Each pose is integrated exactly over the step along an arc of constant v and w.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from sim.mobile.arena import nearest_surface

NO_CONTACT = -2  # the step's contact code when nothing was touched (-1: the walls, i >= 0: obstacle i)


@dataclass(frozen=True)
class BaseSpec:
    """TurtleBot3 Burger's published figures (ROBOTIS e-Manual, turtlebot3_description) and the
    lab's choices where it publishes none (accelerations, the watchdog's timeout)."""

    wheel_separation: float = 0.160  # m
    wheel_radius: float = 0.033  # m (nominal: what the odometry assumes)
    max_linear: float = 0.22  # m/s
    max_angular: float = 2.84  # rad/s
    max_linear_acceleration: float = 1.0  # m/s^2 (the lab's choice)
    max_angular_acceleration: float = 6.0  # rad/s^2 (the lab's choice)
    footprint_radius: float = 0.105  # m (turtlebot3_navigation2's robot_radius)
    command_timeout: float = 0.5  # s without a /cmd_vel and the base stops (OpenCR's motor timeout)
    wheel_radius_error: tuple[float, float] = (0.0, 0.0)  # the true radii's relative errors (left, right)

    def limits(self) -> np.ndarray:
        """The kernel's view: [max v, max w, max dv/dt, max dw/dt, L, r, r_left true, r_right true, footprint]."""
        r = self.wheel_radius
        return np.array(
            [
                self.max_linear,
                self.max_angular,
                self.max_linear_acceleration,
                self.max_angular_acceleration,
                self.wheel_separation,
                r,
                r * (1.0 + self.wheel_radius_error[0]),
                r * (1.0 + self.wheel_radius_error[1]),
                self.footprint_radius,
            ]
        )


@njit(cache=True)
def _toward(value: float, target: float, max_change: float) -> float:
    if target > value + max_change:
        return value + max_change
    if target < value - max_change:
        return value - max_change
    return target


@njit(cache=True)
def integrate_arc(pose: np.ndarray, v: float, w: float, dt: float) -> None:
    """pose = [x, y, yaw] moved in place along the arc of constant v (m/s) and w (rad/s) for dt."""
    yaw = pose[2]
    if abs(w) < 1e-9:
        pose[0] += v * dt * math.cos(yaw)
        pose[1] += v * dt * math.sin(yaw)
    else:
        yaw_end = yaw + w * dt
        pose[0] += v / w * (math.sin(yaw_end) - math.sin(yaw))
        pose[1] -= v / w * (math.cos(yaw_end) - math.cos(yaw))
    pose[2] = math.atan2(math.sin(yaw + w * dt), math.cos(yaw + w * dt))


@njit(cache=True)
def drive_step(
    pose: np.ndarray,
    odom_pose: np.ndarray,
    velocity: np.ndarray,
    wheels: np.ndarray,
    command: np.ndarray,
    limits: np.ndarray,
    walls_xy: np.ndarray,
    obstacles: np.ndarray,
    dt: float,
) -> int:
    """One step of the base (in place): velocity = [v, w] toward command = [v, w] within the limits;
    wheels = [left angle, right angle, left rate, right rate] (rad, rad/s); the true pose and the
    odometry's pose ([x, y, yaw], arena frame) integrated. Returns what the base touched
    (NO_CONTACT, -1 the walls, i >= 0 obstacle i)."""
    v_cmd = min(max(command[0], -limits[0]), limits[0])
    w_cmd = min(max(command[1], -limits[1]), limits[1])
    v = _toward(velocity[0], v_cmd, limits[2] * dt)
    w = _toward(velocity[1], w_cmd, limits[3] * dt)
    velocity[0], velocity[1] = v, w
    half, r = 0.5 * limits[4], limits[5]
    rate_left, rate_right = (v - w * half) / r, (v + w * half) / r
    wheels[0] += rate_left * dt
    wheels[1] += rate_right * dt
    wheels[2], wheels[3] = rate_left, rate_right
    integrate_arc(odom_pose, v, w, dt)  # the encoders with the nominal radius
    true_left, true_right = rate_left * limits[6], rate_right * limits[7]
    integrate_arc(pose, 0.5 * (true_left + true_right), (true_right - true_left) / limits[4], dt)
    touched = NO_CONTACT
    for _ in range(3):  # into a surface: back out along its normal to touching it (the motion along
        d, nx, ny, which = nearest_surface(walls_xy, obstacles, pose[0], pose[1])  # it is kept); again
        if d >= limits[8] - 1e-12:  # for a second surface (a corner)
            break
        touched = which if touched == NO_CONTACT else touched
        pose[0] += (limits[8] - d) * nx
        pose[1] += (limits[8] - d) * ny
    return touched
