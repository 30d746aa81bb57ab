"""Wall following around the obstacle, judged from the world's true state after every step (the
grader's rule: docs/mobile-lab.md, "The grading rule"; the numbers are `WallRules`'s).

A trial passes when the robot goes once around the obstacle (its position's angle about the
obstacle's centre turns through a full 360 degrees, either way) within the time limit, and before
that never touches anything (contact), never stands still (it moves less than `stall_distance` in
`stall_window` seconds) and spends at most `outside_band_max` seconds of the trial with its distance
to the obstacle's surface outside the band. The distance is measured from base_footprint (the
robot's centre, about where its scanner is) to the nearest point of the obstacle's surface: what the
scan reads towards the obstacle. The first rule broken ends the trial with its reason and figures.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class WallRules:
    band: tuple[float, float] = (0.20, 0.70)  # m from the obstacle's surface
    outside_band_max: float = 20.0  # s of the trial outside the band, at most
    time_limit: float = 120.0  # s for the full circuit
    stall_distance: float = 0.05  # m
    stall_window: float = 10.0  # s


@dataclass
class WallState:
    """The monitor's figures (published with every snapshot)."""

    elapsed: float = 0.0  # s since the trial started
    distance: float = 0.0  # m from the obstacle's surface (now)
    min_distance: float = math.inf
    circuit: float = 0.0  # rad turned about the obstacle's centre (signed: + counter-clockwise)
    outside_band: float = 0.0  # s outside the band so far
    done: bool = False
    passed: bool = False
    verdict: str | None = None  # why it passed or failed (None while running)


class WallMonitor:
    """The rule above, updated once per step with the true pose."""

    def __init__(self, rules: WallRules, center_xy: tuple[float, float], position_xy: tuple[float, float]) -> None:
        self.rules = rules
        self.center = center_xy
        self.state = WallState()
        self._bearing = self._bearing_of(position_xy)
        self._anchor, self._anchor_time = position_xy, 0.0

    def _bearing_of(self, xy: tuple[float, float]) -> float:
        return math.atan2(xy[1] - self.center[1], xy[0] - self.center[0])

    def _end(self, passed: bool, verdict: str) -> None:
        self.state.done, self.state.passed, self.state.verdict = True, passed, verdict

    def update(self, dt: float, xy: tuple[float, float], distance: float, contact: str | None) -> None:
        """After a step: the true position, its distance to the obstacle's surface, what it touched."""
        s, rules = self.state, self.rules
        if s.done:
            return
        s.elapsed += dt
        s.distance = distance
        s.min_distance = min(s.min_distance, distance)
        bearing = self._bearing_of(xy)
        s.circuit += math.remainder(bearing - self._bearing, 2.0 * math.pi)
        self._bearing = bearing
        low, high = rules.band
        if not low <= distance <= high:
            s.outside_band += dt
        at = f"at {s.elapsed:.1f} s"
        if contact is not None:
            self._end(False, f"collision: {at} the robot touched {contact} ({distance:.2f} m from the obstacle)")
        elif s.outside_band > rules.outside_band_max:
            side = f"inside {low:.2f} m" if distance < low else f"beyond {high:.2f} m"
            self._end(
                False,
                f"band: {at} the robot had been outside the {low:.2f}-{high:.2f} m band for more than "
                f"{rules.outside_band_max:.0f} s (now {distance:.2f} m from the obstacle, {side})",
            )
        elif abs(s.circuit) >= 2.0 * math.pi:
            way = "counter-clockwise" if s.circuit > 0 else "clockwise"
            self._end(
                True,
                f"circuit: {at} the robot had gone once around the obstacle ({way}), "
                f"{s.outside_band:.1f} s outside the band, at least {s.min_distance:.2f} m from it",
            )
        elif math.dist(xy, self._anchor) > rules.stall_distance:
            self._anchor, self._anchor_time = xy, s.elapsed
        elif s.elapsed - self._anchor_time >= rules.stall_window:
            self._end(
                False,
                f"stall: {at} the robot had moved less than {rules.stall_distance:.2f} m in "
                f"{rules.stall_window:.0f} s (at ({xy[0]:.2f}, {xy[1]:.2f}), {distance:.2f} m from the obstacle)",
            )
        if not s.done and s.elapsed >= rules.time_limit:
            self._end(
                False,
                f"time: at {rules.time_limit:.0f} s the robot had gone {math.degrees(abs(s.circuit)):.0f} of 360 "
                f"degrees around the obstacle",
            )
