"""tf2_ros' Buffer (rosclient/site/tf2_ros/buffer.py) and tf.transformations: lookups chained
through a common ancestor (hand-computed), tf2's exceptions for unknown and unconnected frames, a
timeout that waits for a frame, and ROS 1's Euler convention (tf's known values)."""

import math
import threading

import numpy as np
import pytest


def stamped(parent, child, xyz=(0.0, 0.0, 0.0), xyzw=(0.0, 0.0, 0.0, 1.0)):
    return {
        "header": {"frame_id": parent, "stamp": {"sec": 0, "nanosec": 0}},
        "child_frame_id": child,
        "transform": {"translation": dict(zip("xyz", xyz)), "rotation": dict(zip("xyzw", xyzw))},
    }


QUARTER_TURN_Z = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))


def test_lookup_chains_through_the_common_ancestor(site):
    from tf2_ros import Buffer

    buffer = Buffer()
    buffer._offer_message({"transforms": [stamped("world", "base", (1, 0, 0), QUARTER_TURN_Z)]})
    buffer._offer_message({"transforms": [stamped("base", "tool", (0, 0, 0.5)), stamped("world", "cam", (0, 2, 0))]})
    found = buffer.lookup_transform("cam", "tool", None)  # the tool's pose in the camera's frame
    t, r = found.transform.translation, found.transform.rotation
    assert (found.header.frame_id, found.child_frame_id) == ("cam", "tool")
    assert np.allclose([t.x, t.y, t.z], [1, -2, 0.5])  # tool at (1, 0, 0.5) in the world, cam at (0, 2, 0)
    assert np.allclose([r.x, r.y, r.z, r.w], QUARTER_TURN_Z)
    back = buffer.lookup_transform("tool", "world", None).transform.translation
    assert np.allclose([back.x, back.y, back.z], [0, 1, -0.5])  # the world's origin seen from the turned tool


def test_unknown_and_unconnected_frames_raise_tf2s_exceptions_and_a_timeout_waits(site):
    from tf2_ros import Buffer, ConnectivityException, LookupException

    buffer = Buffer()
    buffer._offer_message({"transforms": [stamped("world", "a"), stamped("island", "b")]})
    with pytest.raises(LookupException, match='"nowhere" passed to lookupTransform argument source_frame'):
        buffer.lookup_transform("world", "nowhere", None)
    with pytest.raises(ConnectivityException):
        buffer.lookup_transform("a", "b", None)
    assert buffer.can_transform("world", "a", None) and not buffer.can_transform("a", "b", None)
    threading.Timer(0.2, buffer._offer_message, args=({"transforms": [stamped("a", "late", (0, 0, 1))]},)).start()
    assert buffer.can_transform("world", "late", None, timeout=30.0)


def test_tf_transformations_euler_convention(site):
    from tf import transformations

    q = transformations.quaternion_from_euler(0.1, 0.2, 0.3)
    assert np.allclose(q, [0.0342708, 0.10602051, 0.14357218, 0.98334744])  # tf's own value (sxyz)
    assert np.allclose(transformations.euler_from_quaternion(q), (0.1, 0.2, 0.3))
    turn = transformations.quaternion_about_axis(math.pi / 2, (0, 0, 1))
    assert np.allclose(transformations.quaternion_multiply(turn, turn), [0, 0, 1, 0])  # half a turn
    assert np.allclose(transformations.quaternion_matrix(turn)[:3, :3] @ [1, 0, 0], [0, 1, 0])
    with pytest.raises(ValueError, match="sxyz, rzyx"):
        transformations.euler_matrix(0, 0, 0, axes="szyx")


def test_wait_for_transform_async_is_a_future_completed_when_the_chain_arrives(rclpy):
    """tf2_ros' wait_for_transform_async: done at once when the transform is there; else done (with the
    transform) by the thread that brings the missing frame, its done callbacks run then; the buffer
    forgets it."""
    from tf2_ros import Buffer

    buffer = Buffer()
    buffer._offer_message({"transforms": [stamped("base_link", "platform")]})
    assert buffer.wait_for_transform_async("base_link", "platform", None).result().child_frame_id == "platform"
    future = buffer.wait_for_transform_async("wheel", "platform", None)
    done: list[str] = []
    future.add_done_callback(lambda f: done.append(f.result().child_frame_id))
    buffer._offer_message({"transforms": [stamped("odom", "wheel")]})  # another tree: not yet
    assert not future.done() and done == []
    buffer._offer_message({"transforms": [stamped("base_link", "wheel", (0, 1, 0))]})
    assert future.done() and done == ["platform"]
    assert buffer._new_data_callbacks == []


def test_lookup_transform_async_suspends_a_coroutine_until_the_transform_comes(rclpy):
    """`await buffer.lookup_transform_async(...)` in a task: the executor keeps spinning (the task
    waits, not the executor) and the task ends with the transform once a thread brings it."""
    from rclpy.executors import SingleThreadedExecutor
    from tf2_ros import Buffer

    buffer = Buffer()

    async def look():
        return await buffer.lookup_transform_async("base_link", "sonar", None)

    executor = SingleThreadedExecutor()
    task = executor.create_task(look)
    executor.spin_once(timeout_sec=0)
    assert not task.done()
    threading.Timer(
        0.1, buffer._offer_message, args=({"transforms": [stamped("base_link", "sonar", (0.5, 0, 0))]},)
    ).start()
    executor.spin_until_future_complete(task, timeout_sec=30)
    found = task.result()
    assert (found.header.frame_id, found.child_frame_id) == ("base_link", "sonar")
    assert found.transform.translation.x == pytest.approx(0.5)
