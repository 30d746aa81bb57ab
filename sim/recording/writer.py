"""Recording Snapshots to MCAP (the `mcap` library), as Foxglove opens it without set-up.

Channels (JSON-encoded; JSON schemas):
  /tf       foxglove.FrameTransform  one message per frame (panda_link1..8, plate, box, palm) per scene sample
  /scene    foxglove.SceneUpdate     plate, box (state colour), palm, robot skeleton, the force arrows
  the lab's topics (sim/messages.py), named and laid out as ROS has them:
            /franka_state_controller/F_ext (geometry_msgs/WrenchStamped), /joint_states, the command,
            /object_pose, /human_hand_pose, /contact_state, /lifting_state
  /trial_state (trials only) hri_lab/TrialState: slip in the palm, robot speed, box height
  /image_raw/compressed (live recordings) foxglove.CompressedImage: the camera's image as JPEG
            (`add_image`, at the recorder's image rate; docs/camera.md)

Decimation: the topics every `state_period` (default 10 ms = 100 Hz) and /tf + /scene every
`scene_period` (default 40 ms = 25 Hz) of simulated time, not every 1 ms step.
The file is written in chunks (zstd) and flushed every `flush_period` s of log time, so a file cut
short (its writer killed) keeps all but the last flush period and is still readable (reader.py);
`close()` writes the index and summary. A size cap and a free-disk floor stop a runaway
recording: `add()` then returns False and `stopped` tells why.
"""

from __future__ import annotations

import base64
import json
import shutil
from collections.abc import Iterable
from pathlib import Path

from mcap.well_known import MessageEncoding, SchemaEncoding
from mcap.writer import CompressionType, Writer

from sim.messages import TOPICS, Topic
from sim.recording.scene import (
    COMPRESSED_IMAGE_SCHEMA,
    FRAME_TRANSFORM_SCHEMA,
    SCENE_UPDATE_SCHEMA,
    SceneBuilder,
    schema_bytes,
    stamp,
)
from sim.robot.panda import PandaModel
from sim.world import Snapshot, WorldConfig

STATE_PERIOD = 0.01  # s of simulated time between two samples of the topics (100 Hz)
SCENE_PERIOD = 0.04  # s between two samples of /tf and /scene (25 Hz)
MAX_BYTES = 1 << 30  # 1 GiB per file
MIN_FREE_BYTES = 200 << 20  # stop when the disk has less free space than this (200 MiB)
TRIAL_STATE = "/trial_state"
IMAGE_TOPIC = "/image_raw/compressed"  # the camera's images (image_transport's name for JPEGs of /image_raw)


def schema_of(example) -> dict:
    """A JSON schema inferred from an example message (types of its fields)."""
    if isinstance(example, bool):
        return {"type": "boolean"}
    if isinstance(example, int):
        return {"type": "integer"}
    if isinstance(example, float):
        return {"type": "number"}
    if isinstance(example, str):
        return {"type": "string"}
    if isinstance(example, dict):
        return {"type": "object", "properties": {k: schema_of(v) for k, v in example.items()}}
    if isinstance(example, (list, tuple)):
        return {"type": "array", "items": schema_of(example[0])} if example else {"type": "array"}
    raise TypeError(f"not a JSON value: {example!r}")


def world_description(config: WorldConfig) -> dict:
    """What a replay needs to draw the scene (m)."""
    plate = config.plate
    return {
        "plate": {"width": plate.width, "height": plate.height, "offset": plate.offset},
        "box_size": list(config.box.size),
        "palm_size": list(config.palm_size),
        "dt": config.dt,
    }


class Recording:
    """One MCAP file being written from Snapshots (not thread-safe: one writer thread)."""

    def __init__(
        self,
        path: str | Path,
        config: WorldConfig,
        *,
        source: str = "live",
        model: PandaModel | None = None,
        topics: Iterable[Topic] = TOPICS,
        trial_state: bool = False,
        state_period: float = STATE_PERIOD,
        scene_period: float = SCENE_PERIOD,
        flush_period: float = 1.0,
        max_bytes: int = MAX_BYTES,
        min_free_bytes: int = MIN_FREE_BYTES,
    ) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.topics = list(topics)
        self.state_period, self.scene_period, self.flush_period = state_period, scene_period, flush_period
        self.max_bytes, self.min_free_bytes = max_bytes, min_free_bytes
        self.scene = SceneBuilder(model or PandaModel(), config.plate, config.box.size, config.palm_size)
        self.stopped: str | None = None  # why the recording stopped early (cap), None while running / closed normally
        self.closed = False
        self.messages = 0
        self._file = open(self.path, "wb")  # noqa: SIM115 - the file stays open beyond this block (closed by its owner, or held on purpose)
        self._writer = Writer(self._file, chunk_size=256 * 1024, compression=CompressionType.ZSTD)
        self._writer.start(profile="", library="hri-lab")
        self._channels: dict[str, int] = {}
        self._last_state: float | None = None  # s, simulated
        self._last_scene: float | None = None
        self._last_flush: int | None = None  # ns, log time
        self._last_time: float | None = None
        self._writer.add_metadata(
            "hri_lab",
            {
                "source": source,
                "world": json.dumps(world_description(config)),
                "decimation": json.dumps(
                    {"topics_hz": round(1 / state_period, 3), "scene_hz": round(1 / scene_period, 3)}
                ),
            },
        )
        self._trial_state = trial_state

    def _channel(self, topic: str, schema_name: str, schema: dict) -> int:
        if topic not in self._channels:
            schema_id = self._writer.register_schema(schema_name, SchemaEncoding.JSONSchema, schema_bytes(schema))
            self._channels[topic] = self._writer.register_channel(topic, MessageEncoding.JSON, schema_id)
        return self._channels[topic]

    def _write(
        self, topic: str, schema_name: str, message: dict, log_time: int, publish_time: int, schema=None
    ) -> None:
        channel = self._channel(topic, schema_name, schema if schema is not None else schema_of(message))
        self._writer.add_message(channel, log_time, json.dumps(message, separators=(",", ":")).encode(), publish_time)
        self.messages += 1

    def due(self, t: float) -> bool:
        """Whether a Snapshot at simulated time t (s) would be sampled (saves taking it otherwise)."""
        return (
            self._last_state is None
            or t < self._last_state
            or t - self._last_state >= self.state_period - 1e-9
            or self._last_scene is None
            or t - self._last_scene >= self.scene_period - 1e-9
        )

    def add(self, s: Snapshot, log_time: int | None = None, trial_state: dict | None = None) -> bool:
        """Record `s` if a sample is due (decimation). log_time in ns (default: the simulated
        time). Returns False once the recording has stopped (closed or over a cap)."""
        if self.closed:
            return False
        if self._last_time is not None and s.time < self._last_time:  # the world was reset: sample again
            self._last_state = self._last_scene = None
        self._last_time = s.time
        publish = int(round(s.time * 1e9))
        log_time = publish if log_time is None else int(log_time)
        if self._last_state is None or s.time - self._last_state >= self.state_period - 1e-9:
            self._last_state = s.time
            for topic in self.topics:
                self._write(topic.name, topic.type, topic.build(s), log_time, publish)
            if self._trial_state and trial_state is not None:
                self._write(TRIAL_STATE, "hri_lab/TrialState", trial_state, log_time, publish)
        if self._last_scene is None or s.time - self._last_scene >= self.scene_period - 1e-9:
            self._last_scene = s.time
            for transform in self.scene.transforms(s):
                self._write("/tf", "foxglove.FrameTransform", transform, log_time, publish, FRAME_TRANSFORM_SCHEMA)
            self._write(
                "/scene", "foxglove.SceneUpdate", self.scene.scene_update(s), log_time, publish, SCENE_UPDATE_SCHEMA
            )
        if self._last_flush is None:
            self._last_flush = log_time
        elif log_time - self._last_flush >= self.flush_period * 1e9 or log_time < self._last_flush:
            self._last_flush = log_time
            self._writer.flush()  # a chunk on disk: what a crash would keep
            self._check_caps()
        return not self.closed

    def add_image(self, time: float, jpeg: bytes, frame_id: str, log_time: int | None = None) -> bool:
        """Record one camera image (JPEG bytes) of simulated time `time` (s) on IMAGE_TOPIC as
        foxglove.CompressedImage (its bytes base64 in JSON). False once the recording has stopped."""
        if self.closed:
            return False
        publish = int(round(time * 1e9))
        message = {
            "timestamp": stamp(time),
            "frame_id": frame_id,
            "data": base64.b64encode(jpeg).decode("ascii"),
            "format": "jpeg",
        }
        self._write(
            IMAGE_TOPIC,
            "foxglove.CompressedImage",
            message,
            publish if log_time is None else int(log_time),
            publish,
            COMPRESSED_IMAGE_SCHEMA,
        )
        return not self.closed

    def _check_caps(self) -> None:
        size = self._file.tell()
        if size > self.max_bytes:
            self._stop(
                f"recording stopped: the file reached {size / 2**20:.0f} MiB (cap {self.max_bytes / 2**20:.0f} MiB)"
            )
            return
        free = shutil.disk_usage(self.path.parent).free
        if free < self.min_free_bytes:
            self._stop(
                f"recording stopped: only {free / 2**20:.0f} MiB free on the disk "
                f"(floor {self.min_free_bytes / 2**20:.0f} MiB)"
            )

    def _stop(self, reason: str) -> None:
        self.stopped = reason
        self.close({"stopped": reason})

    def add_metadata(self, name: str, data: dict) -> None:
        """A metadata record (e.g. the trial's result): string values, others as JSON."""
        if not self.closed:
            self._writer.add_metadata(name, {k: v if isinstance(v, str) else json.dumps(v) for k, v in data.items()})

    def close(self, metadata: dict | None = None) -> None:
        """Finish the file: index and summary. Idempotent."""
        if self.closed:
            return
        if metadata:
            self.add_metadata("end", metadata)
        self.closed = True
        try:
            self._writer.finish()
        finally:
            self._file.close()

    @property
    def size(self) -> int:
        """Bytes on disk so far."""
        return self.path.stat().st_size

    def __enter__(self) -> Recording:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
