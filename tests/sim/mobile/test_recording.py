"""A mobile world's recording: /scan as foxglove.LaserScan (Foxglove's 3D panel), /tf, the arena,
the topics; read back for `hri-lab play` at any playback time."""

import json
import math

import pytest

from sim.mobile.messages import TOPICS
from sim.mobile.playback import MobilePlayback, is_mobile
from sim.mobile.recording import MobileRecording
from sim.mobile.world import MobileWorld, seeded_config
from sim.recording import reader


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    path = tmp_path_factory.mktemp("rec") / "drive.mcap"
    world = MobileWorld(seeded_config(3))
    poses = {}
    with_recording = MobileRecording(path, world.config, TOPICS)
    for step in range(600):  # 3 s at 200 Hz
        if step % 20 == 0:
            world.drive(0.2, 0.6)
        world.step()
        with_recording.add(world.snapshot())
        poses[round(world.time, 3)] = world.pose.copy()
    with_recording.close()
    return path, world, poses


def test_the_scan_is_foxgloves_laser_scan(recorded):
    path, world, _ = recorded
    scans = list(reader.messages(path, ["/scan"]))
    assert {m.schema for m in scans} == {"foxglove.LaserScan"}
    assert len(scans) == 16  # 5 Hz: at 0, 0.2, ..., 3.0 s
    last = scans[-1].data
    assert last["frame_id"] == "base_scan"
    assert len(last["ranges"]) == 360
    assert last["end_angle"] == pytest.approx(math.radians(359))
    expected = [None if not math.isfinite(r) else r for r in world.scan_ranges.tolist()]
    assert last["ranges"] == pytest.approx(expected)  # out-of-range rays are null (JSON has no Infinity)


def test_tf_and_the_scene(recorded):
    path, world, _ = recorded
    transforms = [m.data for m in reader.messages(path, ["/tf"])]
    odom = [t for t in transforms if (t["parent_frame_id"], t["child_frame_id"]) == ("odom", "base_footprint")]
    assert odom[-1]["translation"]["x"] == pytest.approx(world.odom_pose[0], abs=0.02)
    assert any(t["child_frame_id"] == "base_scan" for t in transforms)
    (scene,) = [m.data for m in reader.messages(path, ["/scene"])]
    arena = next(e for e in scene["entities"] if e["id"] == "arena")
    assert len(arena["cubes"]) + len(arena["cylinders"]) == 5  # four walls and the obstacle


def test_playback_gives_the_pose_and_topics_at_any_time(recorded):
    path, _world, poses = recorded
    assert is_mobile(path)
    playback = MobilePlayback(path)
    assert playback.duration == pytest.approx(0.005 + 59 * 0.05)  # the topics at 20 Hz from the first step
    assert playback.pose_at(1.0) == pytest.approx(poses[0.955])  # the last sample at or before 1 s
    assert playback.pose_at(10.0) == pytest.approx(poses[round(playback.duration, 3)])
    assert playback.message_at("/odom", 2.0)["child_frame_id"] == "base_footprint"
    assert playback.trail_until(1.0)[-1] == pytest.approx(playback.odom_xy[19])  # 0.005 + 19 * 0.05 s
    assert json.loads(json.dumps(reader.metadata(path)["hri_lab"]["world"]))["kind"] == "mobile"
