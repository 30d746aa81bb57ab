"""Topics: the latest message of each, built from the simulation's snapshot, shaped like the ROS
message it mirrors. One declaration per topic (`Topic`: name, type, build(snapshot) -> dict); the
lab's are in app/lab/topics.py, their HTTP and WebSocket routes in app/api/topics.py. Here: the
declaration and the pieces of common ROS messages."""
from dataclasses import dataclass
from typing import Callable

import numpy as np
import pinocchio as pin

from sim.world import Snapshot



def header(s: Snapshot, frame_id: str) -> dict:
    sec = int(s.time)
    return {"stamp": {"sec": sec, "nanosec": int(round((s.time - sec) * 1e9))}, "frame_id": frame_id}


def vector3(v) -> dict:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def pose(position, rotation) -> dict:
    q = pin.Quaternion(np.asarray(rotation))  # ROS orders x, y, z, w
    return {"position": vector3(position), "orientation": {"x": q.x, "y": q.y, "z": q.z, "w": q.w}}


@dataclass(frozen=True)
class Topic:
    name: str
    type: str
    build: Callable[[Snapshot], dict]
