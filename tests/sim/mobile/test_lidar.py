"""The scan against hand-computed ranges (walls, a cylinder, boxes), its noise and its range limits."""

import math

import numpy as np
import pytest

from sim.mobile.arena import Arena, Obstacle
from sim.mobile.lidar import LidarSpec, scan

SPEC = LidarSpec()


def ranges(arena: Arena, x=0.0, y=0.0, yaw=0.0, normals=None) -> np.ndarray:
    out = np.empty(360)
    normals = np.zeros(360) if normals is None else normals
    scan(arena.walls_xy, arena.obstacle_rows, x, y, yaw, normals, SPEC.noise_args(), out)
    return out


def test_walls_read_their_distance_ray_by_ray():
    r = ranges(Arena((2.0, 1.5), ()), x=0.5)
    assert r[0] == pytest.approx(1.5)  # straight ahead (+x)
    assert r[90] == pytest.approx(1.5)  # left (+y)
    assert r[180] == pytest.approx(2.5)  # behind
    assert r[270] == pytest.approx(1.5)  # right
    assert r[45] == pytest.approx(1.5 * math.sqrt(2))  # to the corner (2, 1.5)


def test_rays_turn_with_the_sensor():
    r = ranges(Arena((2.0, 1.5), ()), yaw=math.pi / 2)
    assert r[0] == pytest.approx(1.5)
    assert r[90] == pytest.approx(2.0)


def test_a_cylinder_in_front_and_beside():
    arena = Arena((3.0, 3.0), (Obstacle("cylinder", (1.0, 0.0), (0.5,)),))
    r = ranges(arena)
    assert r[0] == pytest.approx(0.5)
    half_angle = math.degrees(math.asin(0.5))  # 30 degrees: the tangent
    assert r[29] < 3.0
    assert r[31] == pytest.approx(3.0 / math.cos(math.radians(31)))
    # ray 20: |p + t d - c| = 0.5 with d at 20 degrees, by the quadratic
    d = math.radians(20)
    b = -math.cos(d)
    assert r[20] == pytest.approx(-b - math.sqrt(b * b - (1 - 0.25)))
    assert half_angle == pytest.approx(30.0)


def test_boxes_straight_and_turned():
    straight = Arena((3.0, 3.0), (Obstacle("box", (1.0, 0.0), (0.2, 0.3)),))
    assert ranges(straight)[0] == pytest.approx(0.8)
    turned = Arena((3.0, 3.0), (Obstacle("box", (1.0, 0.0), (0.2, 0.2), math.pi / 4),))
    assert ranges(turned)[0] == pytest.approx(1.0 - 0.2 * math.sqrt(2))  # its corner faces us
    behind = ranges(straight, x=2.0, yaw=math.pi)
    assert behind[0] == pytest.approx(0.8)


def test_out_of_range_reads_inf():
    r = ranges(Arena((5.0, 5.0), (Obstacle("cylinder", (0.15, 0.0), (0.1,)),)))
    assert r[90] == math.inf  # 5 m > 3.5 m
    assert r[0] == math.inf  # 0.05 m < 0.12 m


def test_noise_is_the_lds01s():
    rng = np.random.default_rng(3)
    near, far = [], []
    for _ in range(200):
        r = ranges(Arena((1.0, 0.3), ()), normals=rng.standard_normal(360))
        far.append(r[0])  # 1.0 m: +-5 % as 2 sigma = 0.025 m
        near.append(r[90])  # 0.3 m: +-15 mm as 2 sigma = 0.0075 m
    assert np.mean(far) == pytest.approx(1.0, abs=0.01)
    assert np.std(far) == pytest.approx(0.025, rel=0.15)
    assert np.std(near) == pytest.approx(0.0075, rel=0.15)
