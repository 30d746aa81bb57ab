"""The mobile world's arena as data: a walled rectangle and convex obstacles (cylinders and boxes),
drawn from a seed; and the compiled geometry every part of the world shares (the signed distance
from a point to the walls and to each obstacle, with its outward normal).

Frames: `odom` is the arena's frame (z up, the arena centred on its origin); an obstacle's box is
given by its centre, its half sides along its own x and y, and its yaw in the arena frame.

The kernels take the arena as two arrays (`Arena.walls_xy`, `Arena.obstacle_rows`): the walls'
inner bounds (x_min, x_max, y_min, y_max) and one row per obstacle (kind, centre x, centre y,
radius or half side x, half side y, yaw), kind CYLINDER or BOX.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

CYLINDER, BOX = 0, 1
KINDS = {"cylinder": CYLINDER, "box": BOX}


@dataclass(frozen=True)
class Obstacle:
    """A convex obstacle: a cylinder (size = (radius,)) or a box (size = (half side x, half side y))."""

    shape: str  # "cylinder" or "box"
    center_xy: tuple[float, float]  # m, arena frame
    size: tuple[float, ...]  # m
    yaw: float = 0.0  # rad (a box's)

    def __post_init__(self) -> None:
        if self.shape not in KINDS:
            raise ValueError(f"obstacle shape must be one of {sorted(KINDS)}, got {self.shape!r}")
        needed = 1 if self.shape == "cylinder" else 2
        if len(self.size) != needed or not all(math.isfinite(s) and s > 0 for s in self.size):
            raise ValueError(f"a {self.shape}'s size is {needed} positive length(s) in m, got {self.size}")

    def row(self) -> np.ndarray:
        half_y = self.size[1] if self.shape == "box" else self.size[0]
        return np.array([KINDS[self.shape], *self.center_xy, self.size[0], half_y, self.yaw], dtype=np.float64)

    def describe(self) -> str:
        if self.shape == "cylinder":
            return f"a cylinder of radius {self.size[0]:.2f} m at ({self.center_xy[0]:.2f}, {self.center_xy[1]:.2f})"
        return (
            f"a {2 * self.size[0]:.2f} x {2 * self.size[1]:.2f} m box at "
            f"({self.center_xy[0]:.2f}, {self.center_xy[1]:.2f}), yaw {math.degrees(self.yaw):.0f} deg"
        )


@dataclass(frozen=True)
class Arena:
    """A rectangle of walls (inner half sides, m, centred on the origin) and its obstacles."""

    half_size_xy: tuple[float, float] = (2.0, 2.0)
    obstacles: tuple[Obstacle, ...] = (Obstacle("cylinder", (0.0, 0.0), (0.4,)),)
    wall_height: float = 0.25  # m (drawn only)
    wall_thickness: float = 0.05  # m (drawn only)
    walls_xy: np.ndarray = field(init=False, repr=False, compare=False)
    obstacle_rows: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        hx, hy = self.half_size_xy
        object.__setattr__(self, "walls_xy", np.array([-hx, hx, -hy, hy], dtype=np.float64))
        rows = np.array([o.row() for o in self.obstacles], dtype=np.float64).reshape(len(self.obstacles), 6)
        object.__setattr__(self, "obstacle_rows", rows)


# a seed's arena: the obstacle's shape, size and place are drawn in these ranges (m)
DRAWN_HALF_SIZE_XY = (2.0, 2.0)
CYLINDER_RADIUS_RANGE = (0.25, 0.5)
BOX_HALF_SIDE_RANGE = (0.2, 0.45)
CENTER_OFFSET_MAX = 0.3  # the obstacle's centre within this of the arena's centre, per axis


def draw_arena(seed: int) -> Arena:
    """The arena a seed draws: one obstacle, a cylinder or a box, its size and place."""
    rng = np.random.default_rng(seed)
    center = tuple(float(c) for c in rng.uniform(-CENTER_OFFSET_MAX, CENTER_OFFSET_MAX, 2))
    if rng.random() < 0.5:
        obstacle = Obstacle("cylinder", center, (float(rng.uniform(*CYLINDER_RADIUS_RANGE)),))  # type: ignore[arg-type]
    else:
        sides = tuple(float(s) for s in rng.uniform(*BOX_HALF_SIDE_RANGE, 2))
        obstacle = Obstacle("box", center, sides, float(rng.uniform(-math.pi, math.pi)))  # type: ignore[arg-type]
    return Arena(DRAWN_HALF_SIZE_XY, (obstacle,))


@njit(cache=True)
def obstacle_distance(row: np.ndarray, x: float, y: float) -> tuple[float, float, float]:
    """Signed distance (m) from (x, y) to one obstacle's surface (negative inside) and the unit
    outward normal at the nearest surface point."""
    dx, dy = x - row[1], y - row[2]
    if row[0] == CYLINDER:
        r = math.hypot(dx, dy)
        if r < 1e-12:
            return -row[3], 1.0, 0.0
        return r - row[3], dx / r, dy / r
    c, s = math.cos(row[5]), math.sin(row[5])
    lx, ly = c * dx + s * dy, -s * dx + c * dy  # in the box's frame
    qx, qy = abs(lx) - row[3], abs(ly) - row[4]
    sx = 1.0 if lx >= 0.0 else -1.0
    sy = 1.0 if ly >= 0.0 else -1.0
    if qx > 0.0 or qy > 0.0:  # outside: to the nearest point of the box
        ox, oy = max(qx, 0.0) * sx, max(qy, 0.0) * sy
        d = math.hypot(ox, oy)
        nx, ny = ox / d, oy / d
    elif qx > qy:  # inside, nearest to an x face
        d, nx, ny = qx, sx, 0.0
    else:
        d, nx, ny = qy, 0.0, sy
    return d, c * nx - s * ny, s * nx + c * ny


@njit(cache=True)
def nearest_surface(walls_xy: np.ndarray, obstacles: np.ndarray, x: float, y: float) -> tuple[float, float, float, int]:
    """The nearest surface to (x, y): its signed distance (m), its unit normal pointing away from
    it (towards the free space), and which it is (-1 the walls, i >= 0 obstacle i)."""
    best, nx, ny, which = x - walls_xy[0], 1.0, 0.0, -1
    for d, ux, uy in ((walls_xy[1] - x, -1.0, 0.0), (y - walls_xy[2], 0.0, 1.0), (walls_xy[3] - y, 0.0, -1.0)):
        if d < best:
            best, nx, ny = d, ux, uy
    for i in range(obstacles.shape[0]):
        d, ux, uy = obstacle_distance(obstacles[i], x, y)
        if d < best:
            best, nx, ny, which = d, ux, uy, i
    return best, nx, ny, which
