"""The mobile world: a TurtleBot3 Burger-like base in a walled arena with a convex obstacle
(docs/mobile-lab.md). One `MobileWorld.step()` is one control period (`MobileConfig.dt`): the
command watchdog, the base's compiled kinematic step (sim/mobile/base.py), a scan when one is due
(sim/mobile/lidar.py), the wall-following monitor (sim/mobile/monitor.py). It has what the server's
loop asks of a world (app/runtime/loop.py: step, snapshot, config.dt, commanded, fail, error, time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from sim.mobile.arena import Arena, draw_arena, nearest_surface, obstacle_distance
from sim.mobile.base import NO_CONTACT, BaseSpec, drive_step
from sim.mobile.lidar import LidarSpec, scan
from sim.mobile.monitor import WallMonitor, WallRules, WallState

WHEEL_RADIUS_ERROR_SIGMA = 0.005  # the true wheel radii's relative error, drawn per seeded world


@dataclass(frozen=True)
class MobileConfig:
    arena: Arena = field(default_factory=Arena)
    start_pose: tuple[float, float, float] = (-1.0, 0.0, 0.0)  # x, y (m), yaw (rad), arena frame
    base: BaseSpec = field(default_factory=BaseSpec)
    lidar: LidarSpec = field(default_factory=LidarSpec)
    rules: WallRules = field(default_factory=WallRules)
    dt: float = 0.005  # s: the base's control period (200 Hz)
    seed: int = 0  # the scan's noise


# a seed's start pose: this far from the obstacle's surface (m), facing its centre within this (rad)
START_DISTANCE_RANGE = (0.35, 0.6)
START_HEADING_SPREAD = math.radians(30.0)


def place_at_distance(arena: Arena, bearing: float, distance: float) -> tuple[float, float]:
    """The point at `distance` from the (first) obstacle's surface along `bearing` from its centre."""
    row = arena.obstacle_rows[0]
    cx, cy = row[1], row[2]
    low, high = 0.0, 10.0
    for _ in range(60):  # bisection: the obstacle is convex, so the distance grows along the ray
        mid = 0.5 * (low + high)
        d, _, _ = obstacle_distance(row, cx + mid * math.cos(bearing), cy + mid * math.sin(bearing))
        low, high = (mid, high) if d < distance else (low, mid)
    return cx + low * math.cos(bearing), cy + low * math.sin(bearing)


def seeded_config(seed: int, **changes) -> MobileConfig:
    """The world a seed draws: the arena (obstacle shape, size, place; sim/mobile/arena.py), the start
    pose near the obstacle facing it, the wheels' radius errors and the scan's noise."""
    arena = draw_arena(seed)
    rng = np.random.default_rng([seed, 1])
    bearing = float(rng.uniform(-math.pi, math.pi))
    x, y = place_at_distance(arena, bearing, float(rng.uniform(*START_DISTANCE_RANGE)))
    yaw = math.remainder(
        bearing + math.pi + float(rng.uniform(-START_HEADING_SPREAD, START_HEADING_SPREAD)), 2 * math.pi
    )
    errors = rng.normal(0.0, WHEEL_RADIUS_ERROR_SIGMA, 2)
    base = BaseSpec(wheel_radius_error=(float(errors[0]), float(errors[1])))
    return MobileConfig(**{"arena": arena, "start_pose": (x, y, yaw), "base": base, "seed": seed, **changes})


@dataclass
class MobileSnapshot:
    """A consistent copy of the mobile world's state (what the server publishes)."""

    time: float
    pose: np.ndarray  # true [x, y, yaw] of base_footprint in the arena (odom) frame
    velocity: np.ndarray  # [v, w] the base moves with (m/s, rad/s)
    command: np.ndarray  # [v, w] the base was last commanded (0 after the watchdog)
    wheels: np.ndarray  # [left, right] angle (rad), [left, right] rate (rad/s)
    odom_pose: np.ndarray  # [x, y, yaw] the odometry reckons
    scan_ranges: np.ndarray  # the latest scan (m; inf: no return)
    scan_time: float  # its stamp (s)
    contact: bool  # the base touches something now
    contacts: int  # steps in contact so far
    contact_with: str | None  # what it touched last
    error: str | None
    wall: WallState


class MobileWorld:
    def __init__(self, config: MobileConfig | None = None) -> None:
        self.config = config or MobileConfig()
        self._limits = self.config.base.limits()
        self._noise = self.config.lidar.noise_args()
        self.reset()

    def reset(self) -> None:
        cfg = self.config
        self.time = 0.0
        self.pose = np.array(cfg.start_pose, dtype=np.float64)
        self.odom_pose = self.pose.copy()
        self.velocity = np.zeros(2)
        self.command = np.zeros(2)
        self.wheels = np.zeros(4)
        self.scan_ranges = np.full(cfg.lidar.rays, math.inf)
        self.scan_time = 0.0
        self._next_scan = 0.0
        self._command_time = -math.inf
        self._rng = np.random.default_rng([cfg.seed, 2])
        self.contact = False
        self.contacts = 0
        self.contact_with: str | None = None
        self._error: str | None = None
        self.trial_started = False  # the monitor's clock starts at the first command (a program's first /cmd_vel)
        self.monitor = WallMonitor(cfg.rules, self.obstacle_center, (self.pose[0], self.pose[1]))
        self.monitor.state.distance = self.obstacle_distance()
        self._scan()

    @property
    def obstacle_center(self) -> tuple[float, float]:
        """The (first) obstacle's centre (an arena without one: its own centre)."""
        rows = self.config.arena.obstacle_rows
        if not len(rows):
            return 0.0, 0.0
        row = rows[0]
        return float(row[1]), float(row[2])

    def obstacle_distance(self) -> float:
        """The true distance (m) from base_footprint to the (first) obstacle's surface (inf: none)."""
        if not len(self.config.arena.obstacle_rows):
            return math.inf
        return obstacle_distance(self.config.arena.obstacle_rows[0], self.pose[0], self.pose[1])[0]

    # --- commands ---------------------------------------------------------------------------
    def drive(self, linear_x: float, angular_z: float) -> None:
        """A /cmd_vel: followed (within the base's limits) until the next one or the watchdog.
        Refused while the base is in error; non-finite values are refused."""
        if not (math.isfinite(linear_x) and math.isfinite(angular_z)):
            raise ValueError("a twist's linear.x and angular.z must be finite numbers")
        if self._error is not None:
            raise RuntimeError(f"the base is stopped: {self._error}")
        self.command[:] = linear_x, angular_z
        self._command_time = self.time
        self.trial_started = True

    def fail(self, reason: str) -> None:
        """Stop the base with an error (zero command until recover())."""
        self._error = reason
        self.command[:] = 0.0

    def recover(self) -> None:
        self._error = None

    @property
    def error(self) -> str | None:
        return self._error

    @property
    def commanded(self) -> bool:
        """The base moves or is commanded to (a real-time server keeps its fine granularity then)."""
        return bool(np.any(self.command) or np.any(self.velocity))

    # --- stepping ---------------------------------------------------------------------------
    def step(self) -> None:
        cfg = self.config
        dt = cfg.dt
        if self.time - self._command_time > cfg.base.command_timeout:
            self.command[:] = 0.0  # the watchdog: no fresh command, the base stops
        arena = cfg.arena
        touched = drive_step(
            self.pose,
            self.odom_pose,
            self.velocity,
            self.wheels,
            self.command,
            self._limits,
            arena.walls_xy,
            arena.obstacle_rows,
            dt,
        )
        self.time += dt
        self.contact = touched != NO_CONTACT
        what = None
        if self.contact:
            self.contacts += 1
            what = "the arena's wall" if touched < 0 else "the obstacle"
            self.contact_with = what
        if self.time >= self._next_scan - 1e-9:
            self._scan()
        if self.trial_started:
            distance = self.obstacle_distance()
            self.monitor.update(dt, (float(self.pose[0]), float(self.pose[1])), distance, what)

    def _scan(self) -> None:
        lidar, arena = self.config.lidar, self.config.arena
        x, y, yaw = self.pose
        c, s = math.cos(yaw), math.sin(yaw)
        ox, oy = lidar.offset_xy
        normals = self._rng.standard_normal(lidar.rays)
        scan(
            arena.walls_xy,
            arena.obstacle_rows,
            x + c * ox - s * oy,
            y + s * ox + c * oy,
            yaw,
            normals,
            self._noise,
            self.scan_ranges,
        )
        self.scan_time = self.time
        self._next_scan = self.time + 1.0 / lidar.rate_hz

    def run(self, duration: float) -> None:
        for _ in range(int(round(duration / self.config.dt))):
            self.step()

    def nearest_surface(self) -> tuple[float, int]:
        """The distance (m) from base_footprint to the nearest surface and which (-1 walls, i obstacle i)."""
        arena = self.config.arena
        d, _, _, which = nearest_surface(arena.walls_xy, arena.obstacle_rows, self.pose[0], self.pose[1])
        return d, which

    def snapshot(self) -> MobileSnapshot:
        w = self.monitor.state
        return MobileSnapshot(
            time=self.time,
            pose=self.pose.copy(),
            velocity=self.velocity.copy(),
            command=self.command.copy(),
            wheels=self.wheels.copy(),
            odom_pose=self.odom_pose.copy(),
            scan_ranges=self.scan_ranges.copy(),
            scan_time=self.scan_time,
            contact=self.contact,
            contacts=self.contacts,
            contact_with=self.contact_with,
            error=self._error,
            wall=WallState(
                w.elapsed, w.distance, w.min_distance, w.circuit, w.outside_band, w.done, w.passed, w.verdict
            ),
        )
