"""The base's kinematic step against hand-computed arcs, turns, limits, the watchdog and walls."""

import math

import numpy as np
import pytest

from sim.mobile.arena import Arena, Obstacle
from sim.mobile.base import BaseSpec
from sim.mobile.world import MobileConfig, MobileWorld

INSTANT = BaseSpec(max_linear_acceleration=1e9, max_angular_acceleration=1e9)  # no ramp: exact arcs
OPEN = Arena((5.0, 5.0), ())  # no obstacle, walls far away


def world(base=INSTANT, arena=OPEN, start=(0.0, 0.0, 0.0)) -> MobileWorld:
    return MobileWorld(MobileConfig(arena=arena, start_pose=start, base=base))


def drive_for(w: MobileWorld, v: float, omega: float, seconds: float) -> None:
    """Commands (v, omega) every 0.1 s, as a node publishing at 10 Hz does."""
    for _ in range(int(round(seconds / 0.1))):
        w.drive(v, omega)
        w.run(0.1)


def test_an_arc_ends_where_the_circle_says():
    w = world()
    drive_for(w, 0.1, 0.5, 2.0)  # radius 0.2 m, 1 rad
    x, y, yaw = w.pose
    assert x == pytest.approx(0.2 * math.sin(1.0), abs=1e-9)
    assert y == pytest.approx(0.2 * (1 - math.cos(1.0)), abs=1e-9)
    assert yaw == pytest.approx(1.0, abs=1e-9)


def test_a_turn_in_place_keeps_the_position():
    w = world()
    drive_for(w, 0.0, 1.0, 1.5)
    assert w.pose[:2] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert w.pose[2] == pytest.approx(1.5, abs=1e-9)


def test_wheels_turn_as_the_twist_asks():
    w = world()
    drive_for(w, 0.1, 0.5, 1.0)
    left, right = (0.1 - 0.5 * 0.08) / 0.033, (0.1 + 0.5 * 0.08) / 0.033  # (v -+ w L/2) / r
    assert w.wheels[2:] == pytest.approx([left, right])
    assert w.wheels[:2] == pytest.approx([left * 1.0, right * 1.0], rel=1e-9)


def test_commands_are_held_to_the_burgers_limits():
    w = world()
    drive_for(w, 1.0, 10.0, 0.5)
    assert w.velocity == pytest.approx([0.22, 2.84])
    drive_for(w, -1.0, -10.0, 0.5)
    assert w.velocity == pytest.approx([-0.22, -2.84])


def test_accelerations_are_limited():
    w = world(base=BaseSpec())
    w.drive(0.2, 0.0)
    w.run(0.1)  # 1 m/s^2: 0.1 m/s after 0.1 s
    assert w.velocity[0] == pytest.approx(0.1)
    w.run(0.2)
    assert w.velocity[0] == pytest.approx(0.2)
    # 40 steps of 5 ms, each 0.005 m/s faster (0.005 * 820 * 0.005 m), then 20 at 0.2 m/s
    assert w.pose[0] == pytest.approx(0.005 * (0.005 * 820 + 20 * 0.2), abs=1e-12)


def test_the_watchdog_stops_a_base_nobody_commands():
    w = world()
    w.drive(0.2, 0.0)
    w.run(0.45)
    assert w.velocity[0] == pytest.approx(0.2)
    w.run(0.1)  # 0.55 s after the last command: past the 0.5 s timeout
    assert w.velocity[0] == 0.0
    assert not w.commanded
    x = w.pose[0]
    w.run(0.5)
    assert w.pose[0] == x


def test_non_finite_commands_are_refused():
    w = world()
    with pytest.raises(ValueError, match="finite"):
        w.drive(math.nan, 0.0)
    with pytest.raises(ValueError, match="finite"):
        w.drive(0.1, math.inf)


def test_a_wall_stops_the_motion_into_it_and_is_reported():
    w = world(arena=Arena((1.0, 1.0), ()), start=(0.5, 0.0, 0.0))
    drive_for(w, 0.2, 0.0, 5.0)
    assert w.pose[0] == pytest.approx(1.0 - 0.105, abs=1e-9)  # touching: the footprint's radius away
    assert w.contact
    assert w.contact_with == "the arena's wall"
    assert w.contacts > 0
    assert w.odom_pose[0] > 1.3  # the wheels slip on: the odometry runs past the wall


def test_along_a_wall_the_base_slides_and_cannot_enter_an_obstacle():
    arena = Arena((3.0, 3.0), (Obstacle("cylinder", (1.0, 0.0), (0.3,)),))
    w = world(arena=arena, start=(0.0, 0.05, 0.0))
    drive_for(w, 0.2, 0.0, 8.0)
    d, which = w.nearest_surface()
    assert which == 0
    assert d >= 0.105 - 1e-9
    assert w.contact_with == "the obstacle"


def test_wheel_radius_errors_make_the_odometry_drift():
    w = world(base=BaseSpec(max_linear_acceleration=1e9, wheel_radius_error=(0.0, 0.01)))
    drive_for(w, 0.2, 0.0, 5.0)
    # the odometry goes straight 1 m; the true base turns: w = v * 0.01 / (L (1 + 0.005)) ... by hand:
    assert w.odom_pose[:3] == pytest.approx([1.0, 0.0, 0.0], abs=1e-9)
    right, left = 0.2 / 0.033 * 0.033 * 1.01, 0.2
    omega = (right - left) / 0.16
    assert w.pose[2] == pytest.approx(omega * 5.0, abs=1e-9)
    v = 0.5 * (left + right)
    assert w.pose[0] == pytest.approx(v / omega * math.sin(omega * 5.0), abs=1e-9)
    assert np.hypot(*(w.pose[:2] - w.odom_pose[:2])) > 0.01
