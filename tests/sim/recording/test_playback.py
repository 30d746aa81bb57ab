"""sim/recording/playback.py's bound: the 3D replay holds at most MAX_REPLAY_BYTES of a recording's
messages and refuses a larger file with the reason (and what plays any size)."""

import json

import pytest
from mcap.writer import CompressionType, Writer

from sim.recording import playback
from sim.recording.reader import RecordingError


def test_a_recording_over_what_the_replay_holds_is_refused(tmp_path, monkeypatch):
    path = tmp_path / "big.mcap"
    with open(path, "wb") as f:
        writer = Writer(f, compression=CompressionType.ZSTD)
        writer.start(profile="", library="test")
        schema = writer.register_schema("sensor_msgs/JointState", "jsonschema", b"{}")
        channel = writer.register_channel("/joint_states", "json", schema)
        for i in range(100):
            writer.add_message(channel, i, json.dumps({"position": [0.0] * 7}).encode(), i)
        writer.finish()
    monkeypatch.setattr(playback, "MAX_REPLAY_BYTES", 1000)  # 100 messages of ~40 bytes: over it
    with pytest.raises(RecordingError, match="more than 0 MiB of messages, over what the 3D replay holds"):
        playback.Playback(path)
