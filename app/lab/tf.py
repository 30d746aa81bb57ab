"""The lab's frames as tf2 has them (/tf and /tf_static, tf2_msgs/TFMessage), from a snapshot: the
Panda's links from pinocchio's frames (the robot model of record) at the snapshot's q, the plate
on the flange, the box and the palm in the base frame. A rosbridge viewer (Foxglove, ros3djs)
shows the scene live from them; roslibpy's TFClient reads them through /republish_tfs
(app/rosbridge/tf_republisher.py).

The tree: world -> panda_link0 (the robot stands at the origin) -> panda_link1 ... panda_link8
(the flange) -> plate; panda_link0 -> box, palm, camera_optical (the camera's optical frame, fixed:
sim/camera.py; /image_raw's frame). A transform is the child's pose in its parent's
frame. Fixed ones (world, the fixed joints, the plate) are /tf_static; the rest /tf."""

from __future__ import annotations

import threading

import numpy as np
import pinocchio as pin

from sim import camera
from sim.robot.panda import PandaModel
from sim.world import Snapshot

from app.lab.robot_description import robot_description
from app.ros.tf_messages import WORLD, relative_stamped

BASE = "panda_link0"
PLATE, BOX, PALM = "plate", "box", "palm"
CAMERA = camera.OPTICAL_FRAME

_LOCK = threading.Lock()  # pinocchio's data is not thread-safe
_MODEL: list[PandaModel] = []
_TREE: list[tuple[str, str, bool]] = []  # the URDF's joints, read once
_FIXED: dict[tuple[str, str], np.ndarray] = {}  # (parent, child) -> transform of a fixed joint


def _model() -> PandaModel:
    if not _MODEL:
        _MODEL.append(PandaModel())
    return _MODEL[0]


def _link_tree(model: PandaModel) -> list[tuple[str, str, bool]]:
    """(parent, child, fixed) for every joint of the URDF the model is built from; fixed = the
    joint is not one of the model's moving joints (a fixed joint, or a finger the model locks)."""
    moving = set(model.model.names)
    return [(j["parent"], j["child"], j["name"] not in moving) for j in robot_description()["joints"]]


def _pose(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    transform = np.eye(4)
    transform[:3, :3], transform[:3, 3] = rotation, translation
    return transform


def frames_in_world(s: Snapshot) -> dict[str, np.ndarray]:
    """Every frame's pose (4x4) in the world frame."""
    with _LOCK:
        model = _model()
        pin.framesForwardKinematics(model.model, model.data, np.asarray(s.q, dtype=float))
        poses = {
            f.name: f_pose.homogeneous.copy()
            for f, f_pose in zip(model.model.frames, model.data.oMf)
            if f.type == pin.FrameType.BODY
        }  # the links (pinocchio's BODY frames)
        flange = model.flange_name
    poses[WORLD] = np.eye(4)
    poses[PLATE] = poses[flange] @ _pose(np.eye(3), np.array([0.0, 0.0, s.lifting.plate_offset]))
    poses[BOX] = poses[BASE] @ _pose(s.box_rotation, s.box_position)
    poses[PALM] = poses[BASE] @ _pose(s.palm_rotation, s.palm_position)
    poses[CAMERA] = poses[BASE] @ camera.transform_optical_to_base()
    return poses


def tree() -> list[tuple[str, str, bool]]:
    """(parent, child, fixed) of every transform the lab publishes."""
    if not _TREE:
        with _LOCK:
            _TREE.extend(_link_tree(_model()))
    links, flange = _TREE, PandaModel.flange_name
    return [
        (WORLD, BASE, True),
        *links,
        (flange, PLATE, True),
        (BASE, BOX, False),
        (BASE, PALM, False),
        (BASE, CAMERA, True),
    ]


def transform_stamped(s: Snapshot, parent: str, child: str, pose_parent: np.ndarray, pose_child: np.ndarray) -> dict:
    """geometry_msgs/TransformStamped: the child's pose in the parent's frame."""
    return relative_stamped(s, parent, child, np.linalg.solve(pose_parent, pose_child))


def _fixed_links() -> dict[tuple[str, str], np.ndarray]:
    """The fixed joints' transforms, computed once (at the model's neutral q: they do not depend on
    it), so /tf_static is the same message at every q."""
    if not _FIXED:
        with _LOCK:
            model = _model()
            pin.framesForwardKinematics(model.model, model.data, pin.neutral(model.model))
            poses = {f.name: p.homogeneous.copy() for f, p in zip(model.model.frames, model.data.oMf)}
        for parent, child, fixed in tree():
            if fixed and parent in poses and child in poses:
                _FIXED[(parent, child)] = np.linalg.solve(poses[parent], poses[child])
        _FIXED[(WORLD, BASE)] = np.eye(4)
        _FIXED[(BASE, CAMERA)] = camera.transform_optical_to_base()
    return _FIXED


def tf(s: Snapshot) -> dict:
    """/tf: the transforms that move (the joints' links, the box, the palm)."""
    poses = frames_in_world(s)
    return {
        "transforms": [
            transform_stamped(s, parent, child, poses[parent], poses[child])
            for parent, child, fixed in tree()
            if not fixed
        ]
    }


def tf_static(s: Snapshot) -> dict:
    """/tf_static: the fixed ones (world, fixed joints, the plate on the flange, the camera), stamped 0 (they
    hold at any time), so the message changes only when they do (the plate's offset)."""
    fixed = dict(_fixed_links())
    fixed[(PandaModel.flange_name, PLATE)] = _pose(np.eye(3), np.array([0.0, 0.0, s.lifting.plate_offset]))
    transforms = [
        relative_stamped(s, parent, child, fixed[(parent, child)]) for parent, child, is_fixed in tree() if is_fixed
    ]
    for transform in transforms:
        transform["header"]["stamp"] = {"sec": 0, "nanosec": 0}
    return {"transforms": transforms}
