"""sim/recording/writer.py: decimation of the topics and the scene by simulated time, the JSON
schemas inferred from examples, metadata, a reset world sampled again, the size cap and close."""

from collections import Counter

import pytest

from sim.messages import TOPICS
from sim.recording.reader import messages, metadata
from sim.recording.writer import TRIAL_STATE, Recording, schema_of, world_description
from sim.world import World


@pytest.fixture(scope="module")
def world_and_snapshots():
    """A world and 101 snapshots 1 ms apart (0.1 s of simulated time)."""
    world = World()
    snapshots = [world.snapshot()]
    for _ in range(100):
        world.step()
        snapshots.append(world.snapshot())
    return world, snapshots


def test_schemas_are_inferred_from_an_example():
    assert schema_of({"a": 1, "b": [0.5], "c": "x", "d": True, "e": []}) == {
        "type": "object",
        "properties": {
            "a": {"type": "integer"},
            "b": {"type": "array", "items": {"type": "number"}},
            "c": {"type": "string"},
            "d": {"type": "boolean"},
            "e": {"type": "array"},
        },
    }
    with pytest.raises(TypeError, match="not a JSON value"):
        schema_of(object())


def test_the_topics_and_the_scene_are_decimated_by_simulated_time(tmp_path, world_and_snapshots):
    world, snapshots = world_and_snapshots
    path = tmp_path / "r.mcap"
    with Recording(path, world.config, model=world.model, state_period=0.01, scene_period=0.04) as rec:
        for s in snapshots:
            assert rec.add(s)
    counts = Counter(m.topic for m in messages(path))
    # 0.1 s: the topics at 0, 10, ..., 100 ms (11 samples), the scene at 0, 40, 80 ms (3)
    for topic in TOPICS:
        assert counts[topic.name] == 11, topic.name
    assert counts["/scene"] == 3
    assert counts["/tf"] == 3 * 11  # panda_link1..8, plate, box, palm per scene sample
    assert TRIAL_STATE not in counts  # not a trial recording
    assert rec.messages == sum(counts.values())
    times = [m.log_time for m in messages(path, ["/joint_states"])]
    assert times == [round(s.time * 1e9) for s in snapshots[::10]]  # log time = simulated time, ns


def test_due_says_whether_a_sample_would_be_taken(tmp_path, world_and_snapshots):
    world, snapshots = world_and_snapshots
    with Recording(tmp_path / "r.mcap", world.config, model=world.model, state_period=0.01) as rec:
        assert rec.due(snapshots[0].time)
        rec.add(snapshots[0])
        assert not rec.due(snapshots[5].time)
        assert rec.due(snapshots[10].time)


def test_a_world_reset_is_sampled_again_and_the_metadata_says_what_a_replay_needs(tmp_path, world_and_snapshots):
    world, snapshots = world_and_snapshots
    path = tmp_path / "r.mcap"
    with Recording(path, world.config, model=world.model, source="trial", trial_state=True) as rec:
        rec.add(snapshots[50], trial_state={"slip": 0.0})
        rec.add(snapshots[0], trial_state={"slip": 0.001})  # earlier than the last: the world was reset
        rec.add_metadata("result", {"success": True, "reason": "ok"})
    assert [m.data["slip"] for m in messages(path, [TRIAL_STATE])] == [0.0, 0.001]
    found = metadata(path)
    assert found["hri_lab"]["source"] == "trial"
    assert found["hri_lab"]["world"] == world_description(world.config)
    assert found["hri_lab"]["decimation"] == {"topics_hz": 100.0, "scene_hz": 25.0}
    assert found["result"] == {"success": True, "reason": "ok"}


def test_a_recording_over_its_cap_stops_and_says_why(tmp_path, world_and_snapshots):
    world, snapshots = world_and_snapshots
    path = tmp_path / "r.mcap"
    rec = Recording(path, world.config, model=world.model, state_period=0.001, flush_period=0.005, max_bytes=1)
    kept = [rec.add(s) for s in snapshots[:20]]
    assert kept[:5] == [True] * 5
    assert kept[-1] is False
    assert rec.stopped is not None
    assert "cap 0 MiB" in rec.stopped
    assert rec.closed
    assert not rec.add(snapshots[-1])
    assert not rec.add_image(0.0, b"jpeg", "camera")
    assert metadata(path)["end"] == {"stopped": rec.stopped}
    rec.close()  # idempotent


def test_an_image_is_recorded_as_a_base64_jpeg(tmp_path, world_and_snapshots):
    world, _ = world_and_snapshots
    path = tmp_path / "r.mcap"
    with Recording(path, world.config, model=world.model) as rec:
        rec.add_image(1.25, b"\xff\xd8jpeg", "camera_optical")
    (image,) = list(messages(path))
    assert image.schema == "foxglove.CompressedImage"
    assert image.log_time == 1_250_000_000
    assert image.data == {
        "timestamp": {"sec": 1, "nsec": 250_000_000},
        "frame_id": "camera_optical",
        "data": "/9hqcGVn",
        "format": "jpeg",
    }
