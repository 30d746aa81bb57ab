"""The frames programs publish on /tf and /tf_static (tf2_msgs/TFMessage), joined to the lab's tree
(the served world's own /tf and /tf_static), as tf2 joins every broadcaster's frames.

A program's transform names its parent and child; it is taken when its numbers are finite and its
child is neither one of the served world's frames nor a frame another program publishes, and its
parent does not hang below it (a loop is refused): a program cannot move the lab's frames (the
lifting world's links, box, palm and camera; the mobile world's odom, base and wheels) nor another
program's. A
refused transform is reported to the program that sent it (a status error naming the frame and why);
the message's other transforms are taken. The newest transform of each frame is kept while its
program is connected: the lab's /tf and /tf_static carry them with its own (the static ones latched,
as tf2_ros' static broadcaster's), and /republish_tfs and the tf2_web_republisher action resolve them
through the tree those topics carry (app/rosbridge/tf_republisher.py).
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from app.ros.node_services import NodeClient

MAX_FRAMES = 1000  # frames programs may publish, all together
TF_TOPICS = {"/tf": False, "/tf_static": True}  # topic -> static
# their type, and ROS 1's tf/tfMessage: the same definition (the same md5sum), which is why ROS 1 connects
# a tf publisher to tf2's subscribers (the tf tutorial's fixed_tf_broadcaster publishes tf.msg.tfMessage)
TF_TYPES = ("tf2_msgs/TFMessage", "tf/tfMessage")


@dataclass
class Published:
    parent: str
    child: str
    transform: dict  # geometry_msgs/TransformStamped as JSON
    static: bool
    session: NodeClient  # the program that published it


def _number(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{value!r} is not a finite number")
    return float(value)


def transform_pose(transform: dict) -> tuple[np.ndarray, np.ndarray]:
    """A geometry_msgs/Transform's 4x4 and its unit quaternion (x, y, z, w), sign as given (ValueError
    naming the field when it is not one)."""
    translation, rotation = transform.get("translation", {}), transform.get("rotation", {})
    if not isinstance(translation, dict) or not isinstance(rotation, dict):
        raise ValueError("transform must have 'translation' {x, y, z} and 'rotation' {x, y, z, w}")
    t = [_number(translation.get(a, 0.0)) for a in "xyz"]
    x, y, z, w = (_number(rotation.get(a, 1.0 if a == "w" else 0.0)) for a in "xyzw")
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if norm < 1e-9:
        raise ValueError("rotation is not a quaternion (zero norm)")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    matrix = np.eye(4)
    matrix[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    matrix[:3, 3] = t
    return matrix, np.array([x, y, z, w])


def no_frames() -> set[str]:
    """A lab that publishes no frame of its own."""
    return set()


class NodeFrames:
    def __init__(self, lab_frames: Callable[[], set[str]] = no_frames) -> None:
        self._frames: dict[str, Published] = {}  # child -> its newest transform
        self._lock = threading.Lock()
        self._lab_frames = lab_frames  # the served world's own frames, asked once (the first offer)
        self._lab: set[str] | None = None
        self.version = 0  # changes with every frame taken or dropped (the tf tree is rebuilt then)

    def lab_frames(self) -> set[str]:
        if self._lab is None:
            self._lab = set(self._lab_frames())
        return self._lab

    def offer(self, session: NodeClient, message: dict, static: bool) -> list[str]:
        """Take a TFMessage's transforms from `session`; the reasons of those refused."""
        transforms = message.get("transforms")
        if not isinstance(transforms, list):
            return ["a tf2_msgs/TFMessage needs 'transforms': a list of geometry_msgs/TransformStamped"]
        lab, refused = self.lab_frames(), []
        for item in transforms:
            reason = self._take(session, item, static, lab)
            if reason:
                refused.append(reason)
        return refused

    def _take(self, session: NodeClient, item: Any, static: bool, lab: set[str]) -> str:
        if not isinstance(item, dict):
            return "a transform must be a geometry_msgs/TransformStamped object"
        header = item["header"] if isinstance(item.get("header"), dict) else {}
        parent = str(header.get("frame_id", "")).strip().strip("/")
        child = str(item.get("child_frame_id", "")).strip().strip("/")
        if not parent or not child:
            return "a transform needs header.frame_id (the parent) and child_frame_id"
        if parent == child:
            return f"frame {child[:80]}: a frame cannot be its own parent"
        if child in lab:
            return f"frame {child[:80]} is the lab's: a program cannot move it (publish frames of your own, below it)"
        try:
            transform_pose(item["transform"] if isinstance(item.get("transform"), dict) else {})
        except ValueError as bad:
            return f"frame {child[:80]}: {bad}"
        with self._lock:
            current = self._frames.get(child)
            if current is not None and current.session is not session:
                return f"frame {child[:80]} is published by node {current.session.name}"
            if current is None and len(self._frames) >= MAX_FRAMES:
                return f"frame {child[:80]}: {MAX_FRAMES} frames are published already"
            if self._below(parent, child):
                return (
                    f"frame {child[:80]}: its parent {parent[:80]} hangs below it: the transform would close a "
                    "loop in the tree"
                )
            self._frames[child] = Published(parent, child, dict(item, child_frame_id=child), static, session)
            self.version += 1
        return ""

    def _below(self, frame: str, ancestor: str) -> bool:
        """`frame` hangs below `ancestor` through the programs' frames (the lab's tree has no loop and
        no program's frame above its own: a walk of at most MAX_FRAMES steps)."""
        for _ in range(MAX_FRAMES + 1):
            if frame == ancestor:
                return True
            published = self._frames.get(frame)
            if published is None:
                return False
            frame = published.parent
        return True  # a loop already (none is taken): refused all the same

    def drop(self, session: NodeClient) -> None:
        """A program disconnected: its frames go with it."""
        with self._lock:
            for child in [c for c, p in self._frames.items() if p.session is session]:
                del self._frames[child]
                self.version += 1

    def transforms(self, static: bool) -> list[dict]:
        with self._lock:
            return [p.transform for p in self._frames.values() if p.static == static]

    def names(self) -> set[str]:
        with self._lock:
            return set(self._frames)
