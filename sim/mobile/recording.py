"""The mobile world's recordings: MCAP files Foxglove opens without set-up, and `hri-lab play` replays.

Channels (JSON-encoded; JSON schemas), stamped with the simulated time:
  /scan      foxglove.LaserScan       each scan once, in base_scan (out-of-range rays as null: JSON
                                      has no Infinity), so Foxglove's 3D panel draws it
  /tf        foxglove.FrameTransform  odom -> base_footprint (the odometry's pose, as /tf has it),
                                      base_footprint -> base_scan, at every sample
  /scene     foxglove.SceneUpdate     the arena (walls, obstacle) in odom and the base's body, once
  the world's topics (sim/mobile/messages.py and the served ones), laid out as ROS has them, every
  `state_period`: /odom, /joint_states, /cmd_vel_followed, /ground_truth_pose, /wall_following.
The metadata record "hri_lab" says `world: mobile` and the arena (what a replay draws).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from mcap.well_known import MessageEncoding, SchemaEncoding
from mcap.writer import CompressionType, Writer

from sim.messages import Topic
from sim.mobile.messages import FOOTPRINT, ODOM, SCAN, SCAN_FRAME, static_transforms
from sim.mobile.world import MobileConfig, MobileSnapshot
from sim.recording.scene import FRAME_TRANSFORM_SCHEMA, SCENE_UPDATE_SCHEMA, schema_bytes, stamp
from sim.recording.writer import schema_of

STATE_PERIOD = 0.05  # s of simulated time between two samples of the topics and /tf (20 Hz)
_NUM = {"type": "number"}
LASER_SCAN_SCHEMA = {
    "title": "foxglove.LaserScan",
    "type": "object",
    "properties": {
        "timestamp": {"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}},
        "frame_id": {"type": "string"},
        "pose": {
            "type": "object",
            "properties": {
                "position": {"type": "object", "properties": {"x": _NUM, "y": _NUM, "z": _NUM}},
                "orientation": {"type": "object", "properties": {"x": _NUM, "y": _NUM, "z": _NUM, "w": _NUM}},
            },
        },
        "start_angle": _NUM,
        "end_angle": _NUM,
        "ranges": {"type": "array", "items": {"type": ["number", "null"]}},
        "intensities": {"type": "array", "items": _NUM},
    },
}
_IDENTITY = {"position": {"x": 0.0, "y": 0.0, "z": 0.0}, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}


def _rotation_z(yaw: float) -> dict:
    return {"x": 0.0, "y": 0.0, "z": math.sin(0.5 * yaw), "w": math.cos(0.5 * yaw)}


def arena_description(config: MobileConfig) -> dict:
    """What a replay draws (m, rad): the arena, the base's footprint, the scanner's place."""
    arena = config.arena
    return {
        "kind": "mobile",
        "half_size_xy": list(arena.half_size_xy),
        "wall_height": arena.wall_height,
        "wall_thickness": arena.wall_thickness,
        "obstacles": [
            {"shape": o.shape, "center_xy": list(o.center_xy), "size": list(o.size), "yaw": o.yaw}
            for o in arena.obstacles
        ],
        "footprint_radius": config.base.footprint_radius,
        "dt": config.dt,
    }


def laser_scan(s: MobileSnapshot, config: MobileConfig) -> dict:
    """foxglove.LaserScan of the snapshot's scan, in base_scan."""
    lidar = config.lidar
    return {
        "timestamp": stamp(s.scan_time),
        "frame_id": SCAN_FRAME,
        "pose": _IDENTITY,
        "start_angle": 0.0,
        "end_angle": (lidar.rays - 1) * lidar.angle_increment,
        "ranges": [r if math.isfinite(r) else None for r in s.scan_ranges.tolist()],
        "intensities": [],
    }


def scene_update(config: MobileConfig, time: float) -> dict:
    """The arena in odom (the odometry starts at the true start pose, so odom is the arena's frame)."""
    arena, ts = config.arena, stamp(time)
    hx, hy = arena.half_size_xy
    t, h = arena.wall_thickness, arena.wall_height
    grey, orange = {"r": 0.6, "g": 0.6, "b": 0.63, "a": 1.0}, {"r": 0.9, "g": 0.63, "b": 0.24, "a": 1.0}

    def pose(x: float, y: float, z: float, yaw: float = 0.0) -> dict:
        return {"position": {"x": x, "y": y, "z": z}, "orientation": _rotation_z(yaw)}

    def size(x: float, y: float, z: float) -> dict:
        return {"x": x, "y": y, "z": z}

    cubes = [
        {"pose": pose(cx, cy, h / 2), "size": size(sx, sy, h), "color": grey}
        for cx, cy, sx, sy in (
            (hx + t / 2, 0.0, t, 2 * hy + 2 * t),
            (-hx - t / 2, 0.0, t, 2 * hy + 2 * t),
            (0.0, hy + t / 2, 2 * hx, t),
            (0.0, -hy - t / 2, 2 * hx, t),
        )
    ]
    cylinders = []
    for o in arena.obstacles:
        (cx, cy), o_size = o.center_xy, o.size
        if o.shape == "cylinder":
            d = 2 * o_size[0]
            cylinders.append(
                {
                    "pose": pose(cx, cy, h / 2),
                    "size": size(d, d, h),
                    "bottom_scale": 1.0,
                    "top_scale": 1.0,
                    "color": orange,
                }
            )
        else:
            cubes.append(
                {"pose": pose(cx, cy, h / 2, o.yaw), "size": size(2 * o_size[0], 2 * o_size[1], h), "color": orange}
            )
    radius = config.base.footprint_radius

    def entity(id_: str, frame: str, **primitives) -> dict:
        return {
            "timestamp": ts,
            "frame_id": frame,
            "id": id_,
            "lifetime": {"sec": 0, "nsec": 0},
            "frame_locked": True,
            "metadata": [],
            **{
                k: primitives.get(k, [])
                for k in ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models")
            },
        }

    body = {
        "pose": pose(0.0, 0.0, 0.0715),
        "size": size(2 * radius, 2 * radius, 0.143),
        "bottom_scale": 1.0,
        "top_scale": 1.0,
        "color": {"r": 0.24, "g": 0.24, "b": 0.28, "a": 1.0},
    }
    return {
        "deletions": [],
        "entities": [
            entity("arena", ODOM, cubes=cubes, cylinders=cylinders),
            entity("base", FOOTPRINT, cylinders=[body]),
        ],
    }


class MobileRecording:
    """One MCAP file being written from MobileSnapshots (one writer thread)."""

    def __init__(
        self,
        path: str | Path,
        config: MobileConfig,
        topics: list[Topic],
        *,
        source: str = "live",
        state_period: float = STATE_PERIOD,
    ) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.config, self.topics, self.state_period = (
            config,
            [t for t in topics if t.name not in (SCAN, "/tf", "/tf_static", "/robot_description", "/clock")],
            state_period,
        )
        self.closed = False
        self.messages = 0
        self._file = open(self.path, "wb")  # noqa: SIM115 - the file stays open beyond this block (closed by its owner, or held on purpose)
        self._writer = Writer(self._file, chunk_size=256 * 1024, compression=CompressionType.ZSTD)
        self._writer.start(profile="", library="hri-lab")
        self._writer.add_metadata(
            "hri_lab",
            {
                "source": source,
                "world": json.dumps(arena_description(config)),
                "decimation": json.dumps({"topics_hz": 1 / state_period}),
            },
        )
        self._channels: dict[str, int] = {}
        self._last_state: float | None = None
        self._last_scan: float | None = None
        self._scene_written = False

    def _write(self, topic: str, schema_name: str, message: dict, time: float, schema: dict | None = None) -> None:
        if topic not in self._channels:
            schema_id = self._writer.register_schema(
                schema_name,
                SchemaEncoding.JSONSchema,
                schema_bytes(schema if schema is not None else schema_of(message)),
            )
            self._channels[topic] = self._writer.register_channel(topic, MessageEncoding.JSON, schema_id)
        ns = int(round(time * 1e9))
        self._writer.add_message(self._channels[topic], ns, json.dumps(message, separators=(",", ":")).encode(), ns)
        self.messages += 1

    def add(self, s: MobileSnapshot) -> bool:
        """Record `s` where a sample is due; False once closed."""
        if self.closed:
            return False
        if not self._scene_written:
            self._write(
                "/scene", "foxglove.SceneUpdate", scene_update(self.config, s.time), s.time, SCENE_UPDATE_SCHEMA
            )
            self._scene_written = True
        if self._last_scan is None or s.scan_time != self._last_scan:
            self._last_scan = s.scan_time
            self._write(SCAN, "foxglove.LaserScan", laser_scan(s, self.config), s.scan_time, LASER_SCAN_SCHEMA)
        if (
            self._last_state is None
            or s.time < self._last_state
            or s.time - self._last_state >= self.state_period - 1e-9
        ):
            self._last_state = s.time
            for topic in self.topics:
                self._write(topic.name, topic.type, topic.build(s), s.time)
            x, y, yaw = (float(v) for v in s.odom_pose)
            transforms = [(ODOM, FOOTPRINT, (x, y, 0.0), yaw)]
            transforms += [(p, c, xyz, 0.0) for p, c, xyz in static_transforms()]
            for parent, child, xyz, angle in transforms:
                message = {
                    "timestamp": stamp(s.time),
                    "parent_frame_id": parent,
                    "child_frame_id": child,
                    "translation": {"x": xyz[0], "y": xyz[1], "z": xyz[2]},
                    "rotation": _rotation_z(angle),
                }
                self._write("/tf", "foxglove.FrameTransform", message, s.time, FRAME_TRANSFORM_SCHEMA)
        return True

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        try:
            self._writer.finish()
        finally:
            self._file.close()
