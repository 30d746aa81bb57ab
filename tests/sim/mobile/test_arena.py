"""Arenas as data: a seed's obstacle and start pose; the signed distances the world judges with."""

import math

import numpy as np
import pytest

from sim.mobile.arena import (
    BOX_HALF_SIDE_RANGE,
    CYLINDER_RADIUS_RANGE,
    Arena,
    Obstacle,
    draw_arena,
    nearest_surface,
    obstacle_distance,
)
from sim.mobile.world import START_DISTANCE_RANGE, MobileWorld, seeded_config


def test_seeds_draw_both_shapes_in_their_ranges_and_again_the_same():
    shapes = set()
    for seed in range(20):
        arena = draw_arena(seed)
        assert arena == draw_arena(seed)
        (obstacle,) = arena.obstacles
        shapes.add(obstacle.shape)
        low, high = CYLINDER_RADIUS_RANGE if obstacle.shape == "cylinder" else BOX_HALF_SIDE_RANGE
        assert all(low <= s <= high for s in obstacle.size)
    assert shapes == {"cylinder", "box"}


def test_a_seeds_start_pose_is_near_the_obstacle_and_faces_it():
    for seed in range(10):
        world = MobileWorld(seeded_config(seed))
        assert START_DISTANCE_RANGE[0] - 1e-6 <= world.obstacle_distance() <= START_DISTANCE_RANGE[1] + 1e-6
        cx, cy = world.obstacle_center
        x, y, yaw = world.pose
        to_center = math.atan2(cy - y, cx - x)
        assert abs(math.remainder(to_center - yaw, 2 * math.pi)) <= math.radians(30) + 1e-9


def test_signed_distances_and_normals():
    cylinder = Obstacle("cylinder", (1.0, 1.0), (0.5,)).row()
    assert obstacle_distance(cylinder, 2.0, 1.0) == pytest.approx((0.5, 1.0, 0.0))
    box = Obstacle("box", (0.0, 0.0), (0.2, 0.4), math.pi / 2).row()  # turned: 0.4 along x now
    assert obstacle_distance(box, 1.0, 0.0) == pytest.approx((0.6, 1.0, 0.0))
    assert obstacle_distance(box, 0.0, 0.1) == pytest.approx((-0.1, 0.0, 1.0))
    corner = obstacle_distance(box, 0.7, 0.5)  # nearest the corner (0.4, 0.2)
    assert corner[0] == pytest.approx(math.hypot(0.3, 0.3))
    arena = Arena((2.0, 2.0), (Obstacle("cylinder", (1.0, 0.0), (0.5,)),))
    d, nx, ny, which = nearest_surface(arena.walls_xy, arena.obstacle_rows, 1.8, 1.9)
    assert (d, nx, ny, which) == pytest.approx((0.1, 0.0, -1.0, -1))
    assert nearest_surface(arena.walls_xy, arena.obstacle_rows, 1.0, 0.6)[3] == 0


def test_bad_obstacles_are_refused():
    with pytest.raises(ValueError, match="shape"):
        Obstacle("cone", (0.0, 0.0), (0.3,))
    with pytest.raises(ValueError, match="positive"):
        Obstacle("box", (0.0, 0.0), (0.3, np.nan))
