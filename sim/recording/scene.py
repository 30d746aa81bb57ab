"""What the 3D views draw from a Snapshot (the live view, the replay, Foxglove): the state colours,
the force arrows, and the same scene as Foxglove messages (foxglove.FrameTransform per frame,
foxglove.SceneUpdate for the plate, box, palm, robot skeleton and arrows), JSON-encoded.

Frames: `panda_link0` (the base, the root), `panda_link1` ... `panda_link8` (the flange = EE),
`plate`, `box`, `palm`; every one is given relative to the base.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin

from sim.world import Snapshot

BASE_FRAME = "panda_link0"
LINKS = tuple(f"panda_link{i}" for i in range(1, 9))
FORCE_SCALE = 0.01  # m of arrow per N
COLOURS = {  # state -> RGB
    "below": (80, 140, 255),
    "inside": (60, 190, 90),
    "above": (255, 160, 40),
    "slipping": (170, 80, 220),
    "error": (230, 50, 50),
    "idle": (200, 170, 120),
}
ARROW_COLOURS = {"normal": (230, 50, 50), "tangential": (40, 120, 255), "human": (240, 140, 40)}
PALM_COLOUR = (240, 190, 160)
PLATE_COLOUR = (60, 60, 60)
ARROW_HEAD = 0.02  # m, head length (shorter arrows: 30 % head)


def state_of(s: Snapshot) -> str:
    """What the colours tell: error, slipping, below/inside/above the band, or idle."""
    if s.error:
        return "error"
    if s.plate.points_slipping > 0 and s.plate.normal_force > 0:
        return "slipping"
    if not s.lifting.running:
        return "idle"
    f_n = s.plate.normal_force
    if f_n < s.lifting.f_n_min:
        return "below"
    return "above" if f_n > s.lifting.f_n_max else "inside"


def arrows_of(s: Snapshot, plate_offset: float) -> dict[str, np.ndarray]:
    """Arrow segments (start, end) in the base frame: F_ext's normal and tangential parts at the
    plate centre, and the person's push at the palm (FORCE_SCALE m per N)."""
    transform = s.transform_ee_to_base
    rotation = transform[:3, :3]
    centre = transform[:3, 3] + rotation[:, 2] * plate_offset
    force_world = rotation @ s.wrench_ee[:3]  # F_ext in the base frame
    normal = rotation[:, 2]
    f_normal = (force_world @ normal) * normal
    f_tangential = force_world - f_normal
    palm_force = s.palm.force_box
    return {
        "normal": np.array([centre, centre + FORCE_SCALE * f_normal]),
        "tangential": np.array([centre, centre + FORCE_SCALE * f_tangential]),
        "human": np.array([s.palm_position - FORCE_SCALE * palm_force, s.palm_position]),
    }


# --- Foxglove messages (JSON) ------------------------------------------------------------------
def stamp(t: float) -> dict:
    """foxglove time {sec, nsec} of t (s)."""
    sec = math.floor(t)
    return {"sec": int(sec), "nsec": int(round((t - sec) * 1e9)) % 1_000_000_000}


def _xyz(v) -> dict:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def _quat(rotation) -> dict:
    q = pin.Quaternion(np.asarray(rotation, float))
    return {"x": q.x, "y": q.y, "z": q.z, "w": q.w}


def rotation_of(q: dict) -> np.ndarray:
    """3x3 rotation of a {x, y, z, w} quaternion."""
    return pin.Quaternion(q["w"], q["x"], q["y"], q["z"]).normalized().toRotationMatrix()


def _rgba(rgb, a: float = 1.0) -> dict:
    return {"r": rgb[0] / 255.0, "g": rgb[1] / 255.0, "b": rgb[2] / 255.0, "a": a}


def rgb_of(colour: dict) -> tuple[int, int, int]:
    r, g, b = (int(round(colour[k] * 255.0)) for k in ("r", "g", "b"))
    return r, g, b


def frame_transform(t: float, child: str, position, rotation) -> dict:
    """foxglove.FrameTransform of `child` in the base frame."""
    return {
        "timestamp": stamp(t),
        "parent_frame_id": BASE_FRAME,
        "child_frame_id": child,
        "translation": _xyz(position),
        "rotation": _quat(rotation),
    }


class SceneBuilder:
    """Foxglove messages of a Snapshot: link frames from q (pinocchio FK), the plate, box and palm
    frames, and a SceneUpdate with the same shapes, colours and arrows as the live view."""

    def __init__(self, model, plate, box_size, palm_size) -> None:
        self.model = model  # a PandaModel of its own (its pinocchio data is used here)
        self.plate, self.box_size, self.palm_size = plate, tuple(box_size), tuple(palm_size)
        self.link_ids = [model.model.getFrameId(name) for name in LINKS]

    def links(self, q: np.ndarray) -> list[tuple[str, np.ndarray]]:
        """(name, 4x4 transform link -> base) of panda_link1..8."""
        pin.framesForwardKinematics(self.model.model, self.model.data, np.asarray(q, float))
        return [(name, self.model.data.oMf[i].homogeneous.copy()) for name, i in zip(LINKS, self.link_ids)]

    def plate_pose(self, s: Snapshot) -> tuple[np.ndarray, np.ndarray]:
        transform = s.transform_ee_to_base
        return transform[:3, 3] + transform[:3, 2] * self.plate.offset, transform[:3, :3]

    def transforms(self, s: Snapshot) -> list[dict]:
        links = self.links(s.q)
        plate_position, plate_rotation = self.plate_pose(s)
        return [frame_transform(s.time, name, m[:3, 3], m[:3, :3]) for name, m in links] + [
            frame_transform(s.time, "plate", plate_position, plate_rotation),
            frame_transform(s.time, "box", s.box_position, s.box_rotation),
            frame_transform(s.time, "palm", s.palm_position, s.palm_rotation),
        ]

    def scene_update(self, s: Snapshot) -> dict:
        state = state_of(s)
        ts = stamp(s.time)
        identity = {"position": _xyz((0, 0, 0)), "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}

        def entity(id_: str, frame: str, metadata: dict | None = None, **primitives) -> dict:
            return {
                "timestamp": ts,
                "frame_id": frame,
                "id": id_,
                "lifetime": {"sec": 0, "nsec": 0},
                "frame_locked": True,
                "metadata": [{"key": k, "value": str(v)} for k, v in (metadata or {}).items()],
                **{
                    kind: primitives.get(kind, [])
                    for kind in ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models")
                },
            }

        def cube(size, rgb, z: float = 0.0, a: float = 1.0) -> dict:
            return {
                "pose": {"position": _xyz((0, 0, z)), "orientation": identity["orientation"]},
                "size": _xyz(size),
                "color": _rgba(rgb, a),
            }

        origins = [m[:3, 3] for _, m in self.links(s.q)]
        skeleton = {
            "type": 0,
            "pose": identity,
            "thickness": 0.03,
            "scale_invariant": False,
            "points": [_xyz(np.zeros(3))] + [_xyz(p) for p in origins],
            "color": _rgba((235, 235, 235)),
            "colors": [],
            "indices": [],
        }
        arrows = [
            arrow_primitive(points[0], points[1], ARROW_COLOURS[name])
            for name, points in arrows_of(s, self.plate.offset).items()
        ]
        return {
            "deletions": [],
            "entities": [
                entity("robot", BASE_FRAME, lines=[skeleton]),
                entity(
                    "plate",
                    "plate",
                    {"mu": s.lifting.mu},
                    cubes=[cube((self.plate.width, self.plate.height, 0.006), PLATE_COLOUR, -0.003)],
                ),
                entity("box", "box", {"state": state}, cubes=[cube(self.box_size, COLOURS[state])]),
                entity("palm", "palm", cubes=[cube((*self.palm_size, 0.015), PALM_COLOUR)]),
                entity("forces", BASE_FRAME, {"order": ",".join(ARROW_COLOURS)}, arrows=arrows),
            ],
        }


def arrow_primitive(start, end, rgb) -> dict:
    """foxglove ArrowPrimitive from `start` to `end` (m, base frame): it points along its pose's +x."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    vector = end - start
    length = float(np.linalg.norm(vector))
    rotation = np.eye(3)
    if length > 1e-9:
        rotation = pin.Quaternion.FromTwoVectors(np.array([1.0, 0.0, 0.0]), vector / length).toRotationMatrix()
    head = min(ARROW_HEAD, 0.3 * length)
    return {
        "pose": {"position": _xyz(start), "orientation": _quat(rotation)},
        "shaft_length": length - head,
        "shaft_diameter": 0.008,
        "head_length": head,
        "head_diameter": 0.02,
        "color": _rgba(rgb),
    }


def arrow_points(arrow: dict) -> np.ndarray:
    """(start, end) of an ArrowPrimitive: end = start + R e_x (shaft + head)."""
    p = arrow["pose"]["position"]
    start = np.array([p["x"], p["y"], p["z"]])
    length = arrow["shaft_length"] + arrow["head_length"]
    return np.array([start, start + rotation_of(arrow["pose"]["orientation"])[:, 0] * length])


# --- JSON schemas of the Foxglove types used (the fields written above) --------------------------
_NUM = {"type": "number"}
_TIME = {"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}}
_VEC3 = {"type": "object", "properties": {"x": _NUM, "y": _NUM, "z": _NUM}}
_QUAT = {"type": "object", "properties": {"x": _NUM, "y": _NUM, "z": _NUM, "w": _NUM}}
_POSE = {"type": "object", "properties": {"position": _VEC3, "orientation": _QUAT}}
_COLOR = {"type": "object", "properties": {"r": _NUM, "g": _NUM, "b": _NUM, "a": _NUM}}
_ARRAY = {"type": "array"}
FRAME_TRANSFORM_SCHEMA = {
    "title": "foxglove.FrameTransform",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "parent_frame_id": {"type": "string"},
        "child_frame_id": {"type": "string"},
        "translation": _VEC3,
        "rotation": _QUAT,
    },
}
_ENTITY = {
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "frame_id": {"type": "string"},
        "id": {"type": "string"},
        "lifetime": _TIME,
        "frame_locked": {"type": "boolean"},
        "metadata": _ARRAY,
        "arrows": {
            "type": "array",
            "items": {
                "type": "object",
                "properties": {
                    "pose": _POSE,
                    "shaft_length": _NUM,
                    "shaft_diameter": _NUM,
                    "head_length": _NUM,
                    "head_diameter": _NUM,
                    "color": _COLOR,
                },
            },
        },
        "cubes": {
            "type": "array",
            "items": {"type": "object", "properties": {"pose": _POSE, "size": _VEC3, "color": _COLOR}},
        },
        "lines": {
            "type": "array",
            "items": {
                "type": "object",
                "properties": {
                    "type": {"type": "integer"},
                    "pose": _POSE,
                    "thickness": _NUM,
                    "scale_invariant": {"type": "boolean"},
                    "points": {"type": "array", "items": _VEC3},
                    "color": _COLOR,
                    "colors": _ARRAY,
                    "indices": _ARRAY,
                },
            },
        },
        "spheres": _ARRAY,
        "cylinders": _ARRAY,
        "triangles": _ARRAY,
        "texts": _ARRAY,
        "models": _ARRAY,
    },
}
SCENE_UPDATE_SCHEMA = {
    "title": "foxglove.SceneUpdate",
    "type": "object",
    "properties": {"deletions": _ARRAY, "entities": {"type": "array", "items": _ENTITY}},
}


COMPRESSED_IMAGE_SCHEMA = {
    "title": "foxglove.CompressedImage",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "frame_id": {"type": "string"},
        "data": {"type": "string", "contentEncoding": "base64"},
        "format": {"type": "string"},
    },
}


def schema_bytes(schema: dict) -> bytes:
    return json.dumps(schema).encode()
