"""A recording loaded for replay: the scene at each recorded /scene sample (what the 3D views
draw) and every recorded message of the lab's topics (what `hri-lab play` serves).

Everything comes from the file's own channels: q from /joint_states, the plate, box and palm from
/tf, the arrows and the box colour from /scene (drawn live with the same code), mu from the plate
entity's metadata, the status from /contact_state and /lifting_state.
"""

from __future__ import annotations

import bisect
import json
from dataclasses import dataclass
from pathlib import Path
from typing import cast

import numpy as np

from sim.recording import reader
from sim.recording.scene import arrow_points, rgb_of, rotation_of


@dataclass
class Frame:
    time: float  # s since the recording's first message
    q: np.ndarray
    poses: dict[str, tuple[np.ndarray, np.ndarray]]  # plate, box, palm: (position, rotation) in the base frame
    arrows: dict[str, np.ndarray]  # normal, tangential, human: (start, end)
    box_colour: tuple[int, int, int]
    state: str
    mu: float


MAX_REPLAY_BYTES = 512 << 20  # the messages a 3D replay holds (the lab's 10-minute recording: ~250 MiB)


def _vec(d: dict) -> np.ndarray:
    return np.array([d["x"], d["y"], d["z"]], float)


class Playback:
    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.info = reader.info(self.path)
        meta = reader.metadata(self.path).get("hri_lab", {})
        self.world = meta.get("world") or {}
        self.start = self.info.start
        tf: dict[int, dict] = {}
        scenes: dict[int, dict] = {}
        joints: list[tuple[int, np.ndarray]] = []
        self.topics: dict[str, tuple[str, list[int], list[bytes]]] = {}  # name -> (type, log times, raw JSON)
        try:
            self._read(tf, scenes, joints)
            if not scenes or not joints:
                raise reader.RecordingError(
                    f"{self.path}: no /scene or /joint_states messages: not a hri-lab recording"
                )
            joint_times = [t for t, _ in joints]
            self.frames: list[Frame] = []
            for t in sorted(scenes):
                if t not in tf:
                    continue
                i = max(0, bisect.bisect_right(joint_times, t) - 1)
                self.frames.append(self._frame(t, joints[i][1], tf[t], scenes[t]))
        except (ValueError, KeyError, TypeError, IndexError) as exc:  # JSON of another shape (or not JSON)
            raise reader.RecordingError(
                f"{self.path}: its messages are not hri-lab's ({type(exc).__name__}: "
                f"{str(exc)[:100]}): not a hri-lab recording"
            ) from None
        self.times = np.array([f.time for f in self.frames])

    def _read(self, tf: dict[int, dict], scenes: dict[int, dict], joints: list[tuple[int, np.ndarray]]) -> None:
        """Every message of the file into the /tf samples, /scene samples, joint states and topics
        (at most MAX_REPLAY_BYTES of them: a bigger file is refused, `hri-lab bag play` streams it)."""
        held = 0
        for m in reader.messages(self.path, decode=False):
            raw_data = cast(bytes, m.data)  # decode=False: the raw JSON
            held += len(raw_data)
            if held > MAX_REPLAY_BYTES:
                raise reader.RecordingError(
                    f"{self.path}: more than {MAX_REPLAY_BYTES >> 20} MiB of messages, over what the 3D replay holds "
                    "(`hri-lab bag play` streams any size into a lab)"
                )
            if m.topic == "/tf":
                data = json.loads(raw_data)
                tf.setdefault(m.log_time, {})[data["child_frame_id"]] = (
                    _vec(data["translation"]),
                    rotation_of(data["rotation"]),
                )
            elif m.topic == "/scene":
                scenes[m.log_time] = json.loads(raw_data)
            else:
                _kind, times, raw = self.topics.setdefault(m.topic, (m.schema, [], []))
                times.append(m.log_time)
                raw.append(raw_data)
                if m.topic == "/joint_states":
                    joints.append((m.log_time, np.array(json.loads(raw_data)["position"], float)))

    def _frame(self, t: int, q: np.ndarray, frames: dict, scene: dict) -> Frame:
        entities = {e["id"]: e for e in scene["entities"]}

        def meta(entity: dict) -> dict:
            return {kv["key"]: kv["value"] for kv in entity["metadata"]}

        forces = entities["forces"]
        names = meta(forces)["order"].split(",")
        box = entities["box"]
        return Frame(
            time=(t - self.start) / 1e9,
            q=q,
            poses={k: frames[k] for k in ("plate", "box", "palm")},
            arrows={n: arrow_points(a) for n, a in zip(names, forces["arrows"])},
            box_colour=rgb_of(box["cubes"][0]["color"]),
            state=meta(box)["state"],
            mu=float(meta(entities["plate"])["mu"]),
        )

    @property
    def duration(self) -> float:
        """s from the first to the last scene sample."""
        return float(self.times[-1]) if len(self.times) else 0.0

    def frame_at(self, t: float) -> Frame:
        """The last frame at or before t (s since the start)."""
        i = int(np.searchsorted(self.times, t, side="right")) - 1
        return self.frames[min(max(i, 0), len(self.frames) - 1)]

    def message_at(self, topic: str, t: float) -> dict | None:
        """The topic's last recorded message at or before t (s since the start); None if none yet."""
        _, times, raw = self.topics[topic]
        i = bisect.bisect_right(times, self.start + int(round(t * 1e9))) - 1
        return json.loads(raw[i]) if i >= 0 else None
