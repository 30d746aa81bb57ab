"""/tf and /tf_static (app/lab/tf.py) compose to the poses the simulation has: the chain of
transforms from world to the flange is the snapshot's transform_ee_to_base, the box's is its pose."""

import numpy as np
import pinocchio as pin

from sim.world import World

from app.lab import tf


def _matrix(transform: dict) -> np.ndarray:
    t, r = transform["translation"], transform["rotation"]
    out = np.eye(4)
    out[:3, :3] = pin.Quaternion(r["w"], r["x"], r["y"], r["z"]).toRotationMatrix()
    out[:3, 3] = [t["x"], t["y"], t["z"]]
    return out


def _in_world(snapshot, frame: str) -> np.ndarray:
    edges = {
        t["child_frame_id"]: (t["header"]["frame_id"], _matrix(t["transform"]))
        for message in (tf.tf(snapshot), tf.tf_static(snapshot))
        for t in message["transforms"]
    }
    pose = np.eye(4)
    while frame != tf.WORLD:
        frame, relative = edges[frame]
        pose = relative @ pose
    return pose


def test_chains_compose_to_the_simulations_poses():
    world = World()
    world.run(0.05)
    snapshot = world.snapshot()
    assert np.allclose(_in_world(snapshot, "panda_link8"), snapshot.transform_ee_to_base, atol=1e-9)
    assert np.allclose(_in_world(snapshot, "box")[:3, 3], snapshot.box_position, atol=1e-9)
    assert np.allclose(_in_world(snapshot, "palm")[:3, :3], snapshot.palm_rotation, atol=1e-9)
    from sim import camera

    assert np.allclose(_in_world(snapshot, "camera_optical"), camera.transform_optical_to_base(), atol=1e-9)
    plate = _in_world(snapshot, "plate")
    assert np.allclose(plate[:3, 3], snapshot.transform_ee_to_base[:3, 3] + 0.02 * snapshot.transform_ee_to_base[:3, 2])


def test_tf_static_is_the_same_message_at_any_q():
    world = World()
    first = tf.tf_static(world.snapshot())
    world.arm.q = world.arm.q + 0.1  # another configuration
    assert tf.tf_static(world.snapshot()) == first
    assert tf.tf(world.snapshot()) != tf.tf(World().snapshot())
