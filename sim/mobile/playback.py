"""A mobile world's recording (sim/mobile/recording.py) read for `hri-lab play`: the arena from its
metadata, every topic's messages by time (served as `ros2 bag play` publishes them), and the
base's true and odometry poses and the scans at any playback time."""

from __future__ import annotations

import bisect
import json
from pathlib import Path
from typing import cast

import numpy as np

from sim.recording import reader

POSE, ODOM, SCAN = "/ground_truth_pose", "/odom", "/scan"


def is_mobile(path: str | Path) -> bool:
    """The file is a mobile world's recording (its metadata says so)."""
    world = reader.metadata(path).get("hri_lab", {}).get("world")
    return isinstance(world, dict) and world.get("kind") == "mobile"


class MobilePlayback:
    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.info = reader.info(self.path)
        self.world: dict = reader.metadata(self.path).get("hri_lab", {}).get("world") or {}
        self.start = self.info.start
        self.topics: dict[str, tuple[str, list[int], list[bytes]]] = {}  # name -> (type, log times, raw JSON)
        for m in reader.messages(self.path, decode=False):
            _kind, times, raw = self.topics.setdefault(m.topic, (m.schema, [], []))
            times.append(m.log_time)
            raw.append(cast(bytes, m.data))
        if POSE not in self.topics or ODOM not in self.topics:
            raise reader.RecordingError(f"{self.path}: no {POSE} or {ODOM} messages: not a mobile world's recording")
        try:
            _, pose_times, poses = self.topics[POSE]
            self.times = (np.array(pose_times, dtype=np.int64) - self.start) / 1e9
            self.poses = np.array([[p["x"], p["y"], p["theta"]] for p in map(json.loads, poses)])
            _, odom_times, odoms = self.topics[ODOM]
            self.odom_times = (np.array(odom_times, dtype=np.int64) - self.start) / 1e9
            self.odom_xy = np.array([[o["pose"]["pose"]["position"][k] for k in "xy"] for o in map(json.loads, odoms)])
        except (ValueError, KeyError, TypeError) as exc:
            raise reader.RecordingError(f"{self.path}: its messages are not the mobile world's ({exc})") from None

    @property
    def duration(self) -> float:
        return float(self.times[-1]) if len(self.times) else 0.0

    def pose_at(self, t: float) -> np.ndarray:
        """The base's true [x, y, yaw] at playback time t (s): the last sample at or before it."""
        i = int(np.searchsorted(self.times, t, side="right")) - 1
        return self.poses[min(max(i, 0), len(self.poses) - 1)]

    def trail_until(self, t: float) -> np.ndarray:
        """The odometry's positions (x, y) up to playback time t."""
        return self.odom_xy[: max(1, int(np.searchsorted(self.odom_times, t, side="right")))]

    def message_at(self, topic: str, t: float) -> dict | None:
        """The topic's last recorded message at or before t (s since the start); None if none yet."""
        _, times, raw = self.topics[topic]
        i = bisect.bisect_right(times, self.start + int(round(t * 1e9))) - 1
        return json.loads(raw[i]) if i >= 0 else None
