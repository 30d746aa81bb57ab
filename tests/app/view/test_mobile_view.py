"""The mobile world's 3D view draws what the world says: the base where it is, the scan's returns
where they hit, the odometry's trail."""

import math

import numpy as np
import pytest

from sim.mobile.arena import Arena
from sim.mobile.lidar import LidarSpec
from sim.mobile.messages import TOPICS
from sim.mobile.playback import MobilePlayback
from sim.mobile.recording import MobileRecording
from sim.mobile.world import MobileConfig, MobileWorld, seeded_config

from app.mobile.lab import MobileLab
from app.view.mobile_view import MobileReplayView, MobileView, scan_points
from tests.app.view.looking import a_browser
from tests.waiting import wait_for


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
    assert view.scene.base.position == pytest.approx((s.pose[0], s.pose[1], 0.0), abs=1e-6)
    assert len(view.scene.scan.points) == np.isfinite(s.scan_ranges).sum()
    for _ in range(3):
        world.drive(0.2, 0.5)
        world.run(0.1)
        view.update(world.snapshot())
    end = view.scene.trail.points[-1][1]
    assert end[:2] == pytest.approx(world.odom_pose[:2], abs=1e-3)  # float16/32 in viser


def test_it_draws_only_while_a_browser_looks():
    """Nobody looking, the view's thread keeps the odometry's trail and draws nothing; a browser
    that connects is drawn for; once it leaves, nothing again."""
    lab = MobileLab(MobileConfig(arena=Arena((1.5, 1.5), ())), realtime=False)
    view = MobileView(lab, port=0, light=True, rate_hz=200.0)
    draws: list[float] = []
    draw = view.scene.draw
    view.scene.draw = lambda *args: (draws.append(1.0), draw(*args))  # type: ignore[method-assign]  # a spy
    view.start()  # the first frame, drawn at the start
    try:
        drawn, kept = len(draws), len(view._trail)
        wait_for(lambda: len(view._trail) >= kept + 5)  # five periods of the thread
        assert len(draws) == drawn == 1
        with a_browser(view.server):
            wait_for(lambda: len(draws) >= drawn + 3)
        drawn, kept = len(draws), len(view._trail)
        wait_for(lambda: len(view._trail) >= kept + 5)
        assert len(draws) <= drawn + 1  # at most the frame begun as the browser left
    finally:
        view.stop()
        lab.stop()


def test_a_recording_replays_in_the_view(tmp_path):
    world = MobileWorld(seeded_config(2))
    path = tmp_path / "drive.mcap"
    recording = MobileRecording(path, world.config, TOPICS)
    for step in range(400):
        if step % 20 == 0:
            world.drive(0.2, -0.4)
        world.step()
        recording.add(world.snapshot())
    recording.close()
    playback = MobilePlayback(path)
    replay = MobileReplayView(playback, port=0, light=True)
    try:
        replay.seek(1.0)
        assert replay.time == 1.0
        assert replay.scene.base.position[:2] == pytest.approx(playback.pose_at(1.0)[:2], abs=1e-6)
        assert len(replay.scene.scan.points) > 100  # the scan taken at 0.8 s, drawn
        replay.seek(99.0)  # past the end: the last sample
        assert replay.time == pytest.approx(playback.duration)
    finally:
        replay.server.stop()
