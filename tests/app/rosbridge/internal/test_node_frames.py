"""Programs' frames on /tf and /tf_static (app/rosbridge/internal/node_frames.py): taken below any
frame, refused when they would move the lab's frames or another program's, placed in the world
through their parents (hand-computed poses, app/rosbridge/tf_republisher.py's tree), gone with their program."""

import math
from types import SimpleNamespace

import numpy as np

from app.lab import tf
from app.rosbridge.internal.node_frames import NodeFrames
from app.rosbridge.tf_republisher import relative, tree_poses


def world_poses(frames: NodeFrames) -> dict[str, np.ndarray]:
    """The programs' frames placed in the world (a lab publishing no tf of its own: `serve --replay`)."""
    poses = tree_poses({}, frames, None)
    return {name: pose.matrix for name in poses if (pose := relative(poses, "world", name)) is not None}


def stamped(parent: str, child: str, xyz=(0.0, 0.0, 0.0), xyzw=(0.0, 0.0, 0.0, 1.0)) -> dict:
    return {
        "header": {"frame_id": parent, "stamp": {"sec": 1, "nanosec": 0}},
        "child_frame_id": child,
        "transform": {
            "translation": dict(zip("xyz", xyz)),
            "rotation": dict(zip("xyzw", xyzw)),
        },
    }


ADA, BOB = SimpleNamespace(name="/ada"), SimpleNamespace(name="/bob")
QUARTER_TURN_Z = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))


def test_a_programs_frames_are_placed_in_the_world_through_their_parents():
    frames = NodeFrames()
    assert frames.offer(ADA, {"transforms": [stamped("world", "a", (1, 2, 3), QUARTER_TURN_Z)]}, static=True) == []
    assert frames.offer(ADA, {"transforms": [stamped("a", "b", (1, 0, 0))]}, static=False) == []
    poses = world_poses(frames)
    assert np.allclose(poses["a"][:3, 3], [1, 2, 3])
    assert np.allclose(poses["b"][:3, 3], [1, 3, 3])  # a's x axis is the world's y after the quarter turn
    assert np.allclose(poses["b"][:3, :3], poses["a"][:3, :3])
    assert [t["child_frame_id"] for t in frames.transforms(static=True)] == ["a"]
    assert [t["child_frame_id"] for t in frames.transforms(static=False)] == ["b"]


def test_the_labs_frames_and_another_programs_are_refused_the_rest_taken():
    frames = NodeFrames(lambda: {child for _, child, _ in tf.tree()} | {tf.WORLD})  # the lifting world's frames
    lab_child = next(child for _, child, _ in tf.tree() if child == tf.BOX)
    refused = frames.offer(
        ADA, {"transforms": [stamped("panda_link0", lab_child), stamped("plate", "marker", (0, 0, 0.05))]}, static=False
    )
    assert len(refused) == 1
    assert f"frame {tf.BOX} is the lab's" in refused[0]
    assert frames.names() == {"marker"}
    assert frames.offer(BOB, {"transforms": [stamped("plate", "marker")]}, static=False) == [
        "frame marker is published by node /ada"
    ]
    assert "finite" in frames.offer(ADA, {"transforms": [stamped("plate", "c", (math.nan, 0, 0))]}, static=False)[0]
    assert "own parent" in frames.offer(ADA, {"transforms": [stamped("c", "c")]}, static=False)[0]
    assert "transforms" in frames.offer(ADA, {"transform": []}, static=False)[0]


def test_a_programs_frames_go_with_it_and_a_frame_of_another_tree_has_no_pose_in_the_world():
    frames = NodeFrames()
    frames.offer(ADA, {"transforms": [stamped("nowhere", "lost"), stamped("world", "kept")]}, static=False)
    poses = world_poses(frames)
    assert "kept" in poses
    assert "lost" not in poses
    frames.drop(ADA)
    assert frames.names() == set()
