"""The laser scanner, ROBOTIS LDS-01-like (the TurtleBot3 Burger's): 360 rays one degree apart,
counter-clockwise from straight ahead, 0.12-3.5 m, 5 Hz; its ranges cast in a compiled kernel
against the arena's walls and obstacles, with the LDS-01's noise.

The LDS-01's datasheet gives its accuracy as +-15 mm from 0.12 to 0.499 m and +-5 % from 0.5 to
3.5 m; the lab reads each bound as two standard deviations of a Gaussian error. A ray with no
return inside [range_min, range_max] reads +inf, as Gazebo's TurtleBot3 publishes it (REP 117). The
scan is taken at one instant (its stamp); `time_increment` says how long a real one's sweep takes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from sim.mobile.arena import CYLINDER


@dataclass(frozen=True)
class LidarSpec:
    rays: int = 360
    range_min: float = 0.12  # m
    range_max: float = 3.5  # m
    rate_hz: float = 5.0  # scans per second (300 rpm)
    near_sigma: float = 0.0075  # m: +-15 mm as 2 sigma, below near_limit
    far_sigma_ratio: float = 0.025  # of the range: +-5 % as 2 sigma, from near_limit on
    near_limit: float = 0.5  # m
    offset_xy: tuple[float, float] = (-0.032, 0.0)  # base_scan in base_footprint (m; turtlebot3_burger.urdf)
    height: float = 0.182  # m, base_scan above base_footprint (0.010 + 0.172)

    @property
    def angle_increment(self) -> float:
        return 2.0 * math.pi / self.rays

    def noise_args(self) -> np.ndarray:
        return np.array([self.range_min, self.range_max, self.near_sigma, self.far_sigma_ratio, self.near_limit])


@njit(cache=True)
def _ray_cylinder(ox: float, oy: float, radius: float, dx: float, dy: float) -> float:
    """Distance along the unit ray (dx, dy) from (ox, oy), relative to a cylinder's centre, to its
    surface (inf: none; from inside: to where the ray leaves it)."""
    b = ox * dx + oy * dy
    c = ox * ox + oy * oy - radius * radius
    disc = b * b - c
    if disc < 0.0:
        return math.inf
    root = math.sqrt(disc)
    t = -b - root
    if t >= 0.0:
        return t
    t = -b + root
    return t if t >= 0.0 and c < 0.0 else math.inf


@njit(cache=True)
def _slab(p: float, d: float, h: float, t_near: float, t_far: float) -> tuple[float, float]:
    """The ray's interval inside the slab |p + t d| <= h, intersected with (t_near, t_far)."""
    if abs(d) < 1e-12:
        return (t_near, t_far) if abs(p) <= h else (math.inf, -math.inf)
    t1, t2 = (-h - p) / d, (h - p) / d
    if t1 > t2:
        t1, t2 = t2, t1
    return max(t_near, t1), min(t_far, t2)


@njit(cache=True)
def _ray_box(lx: float, ly: float, hx: float, hy: float, ldx: float, ldy: float) -> float:
    """Distance along the unit ray (ldx, ldy) from (lx, ly), both in a box's frame, to its surface."""
    t_near, t_far = _slab(lx, ldx, hx, -math.inf, math.inf)
    t_near, t_far = _slab(ly, ldy, hy, t_near, t_far)
    if t_near > t_far or t_far < 0.0:
        return math.inf
    return t_near if t_near >= 0.0 else t_far


@njit(cache=True)
def _ray_walls(walls_xy: np.ndarray, px: float, py: float, dx: float, dy: float) -> float:
    best = math.inf
    if dx > 1e-12:
        best = (walls_xy[1] - px) / dx
    elif dx < -1e-12:
        best = (walls_xy[0] - px) / dx
    if dy > 1e-12:
        best = min(best, (walls_xy[3] - py) / dy)
    elif dy < -1e-12:
        best = min(best, (walls_xy[2] - py) / dy)
    return best


@njit(cache=True)
def _local(obstacles: np.ndarray, px: float, py: float) -> np.ndarray:
    """Per obstacle: the ray origin in its frame (x, y) and its yaw's cosine and sine."""
    local = np.empty((obstacles.shape[0], 4))
    for i in range(obstacles.shape[0]):
        row = obstacles[i]
        c, s = math.cos(row[5]), math.sin(row[5])
        ox, oy = px - row[1], py - row[2]
        local[i, 0], local[i, 1], local[i, 2], local[i, 3] = c * ox + s * oy, -s * ox + c * oy, c, s
    return local


@njit(cache=True)
def _cast(
    walls_xy: np.ndarray, obstacles: np.ndarray, local: np.ndarray, px: float, py: float, dx: float, dy: float
) -> float:
    best = _ray_walls(walls_xy, px, py, dx, dy)
    for i in range(obstacles.shape[0]):
        row = obstacles[i]
        if row[0] == CYLINDER:
            t = _ray_cylinder(px - row[1], py - row[2], row[3], dx, dy)
        else:
            c, s = local[i, 2], local[i, 3]
            t = _ray_box(local[i, 0], local[i, 1], row[3], row[4], c * dx + s * dy, -s * dx + c * dy)
        best = min(best, t)
    return best


@njit(cache=True)
def cast_ray(walls_xy: np.ndarray, obstacles: np.ndarray, px: float, py: float, angle: float) -> float:
    """Distance (m) from (px, py) along `angle` (arena frame) to the first surface."""
    return _cast(walls_xy, obstacles, _local(obstacles, px, py), px, py, math.cos(angle), math.sin(angle))


@njit(cache=True)
def scan(
    walls_xy: np.ndarray,
    obstacles: np.ndarray,
    sensor_x: float,
    sensor_y: float,
    sensor_yaw: float,
    normals: np.ndarray,
    noise: np.ndarray,
    ranges: np.ndarray,
) -> None:
    """ranges[i] (m) of ray i at sensor_yaw + i * 2 pi / n from the sensor's place (arena frame),
    plus normals[i] standard deviations of the LDS-01's error (noise_args: range_min, range_max,
    near sigma, far sigma ratio, near limit); +inf outside [range_min, range_max]. The rays'
    directions turn by one increment's rotation each (no trigonometry per ray)."""
    n = ranges.shape[0]
    step = 2.0 * math.pi / n
    cos_step, sin_step = math.cos(step), math.sin(step)
    dx, dy = math.cos(sensor_yaw), math.sin(sensor_yaw)
    local = _local(obstacles, sensor_x, sensor_y)
    for i in range(n):
        r = _cast(walls_xy, obstacles, local, sensor_x, sensor_y, dx, dy)
        sigma = noise[2] if r < noise[4] else noise[3] * r
        r += sigma * normals[i]
        ranges[i] = r if noise[0] <= r <= noise[1] else math.inf
        dx, dy = dx * cos_step - dy * sin_step, dy * cos_step + dx * sin_step
