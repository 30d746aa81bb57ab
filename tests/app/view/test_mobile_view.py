"""The mobile world's 3D view draws what the world says: the base where it is, the scan's returns
where they hit, the odometry's trail."""

import math

import numpy as np
import pytest

from sim.mobile.arena import Arena
from sim.mobile.lidar import LidarSpec
from sim.mobile.world import MobileConfig

from app.mobile.lab import MobileLab
from app.view.mobile_view import MobileView, scan_points


@pytest.fixture(scope="module")
def view():
    lab = MobileLab(MobileConfig(arena=Arena((1.5, 1.5), ()), start_pose=(0.032, 0.0, 0.0)), realtime=False)
    view = MobileView(lab, port=0, light=True)
    yield view
    view.server.stop()


def test_scan_points_land_on_the_walls():
    ranges = np.full(360, math.inf)
    ranges[0], ranges[90] = 1.5, 1.5
    points = scan_points((0.032, 0.0, 0.0), ranges, LidarSpec())  # the scanner at the origin
    assert points[:, :2] == pytest.approx(np.array([[1.5, 0.0], [0.0, 1.5]]), abs=1e-12)
    assert points[:, 2] == pytest.approx([0.182, 0.182])


def test_the_view_follows_the_base_and_its_scan(view):
    world = view.lab.runtime.world
    for _ in range(10):
        world.drive(0.2, 0.5)
        world.run(0.1)
    s = world.snapshot()
    view.update(s)
    assert view.base.position == pytest.approx((s.pose[0], s.pose[1], 0.0), abs=1e-6)
    assert len(view.scan.points) == np.isfinite(s.scan_ranges).sum()
    for _ in range(3):
        world.drive(0.2, 0.5)
        world.run(0.1)
        view.update(world.snapshot())
    end = view.trail.points[-1][1]
    assert end[:2] == pytest.approx(world.odom_pose[:2], abs=1e-3)  # float16/32 in viser
