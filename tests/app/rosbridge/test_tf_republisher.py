"""tf2_web_republisher's pieces, against hand-computed transforms: the tree from /tf and /tf_static,
a pair of frames in one tree, a goal's thresholds (upstream's TFPair), a request's fields; its action
on a real bridge in memory: feedback, cancel, a client's going, a rejected goal."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from sim.messages import Topic

from app.ros import tf_messages as tf
from app.rosbridge.internal.node_frames import NodeFrames
from app.rosbridge.tf_republisher import Pair, _request, relative, tree_poses
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def stamped(parent: str, child: str, xyz=(0.0, 0.0, 0.0), yaw_rad: float = 0.0) -> dict:
    return {
        "header": {"frame_id": parent},
        "child_frame_id": child,
        "transform": {
            "translation": dict(zip("xyz", xyz)),
            "rotation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw_rad / 2), "w": math.cos(yaw_rad / 2)},
        },
    }


def bridge_with(moving: list[dict], fixed: list[dict]):
    topics = {
        "/tf": Topic("/tf", "tf2_msgs/TFMessage", lambda s: {"transforms": moving}),
        "/tf_static": Topic("/tf_static", "tf2_msgs/TFMessage", lambda s: {"transforms": fixed}),
    }
    return SimpleNamespace(topics=topics, frames=NodeFrames())


def test_a_chain_is_composed_from_its_root_and_a_pair_is_relative():
    # world -> base 1 m along x, turned 90 deg; base -> tool 0.5 m along the base's x (world's y)
    bridge = bridge_with(
        [stamped("base", "/tool", (0.5, 0.0, 0.0))], [stamped("/world", "base", (1.0, 0.0, 0.0), math.pi / 2)]
    )
    poses = tree_poses(bridge.topics, bridge.frames, None)
    assert set(poses) == {"world", "base", "tool"}
    assert {root for _, root in poses.values()} == {"world"}
    assert np.allclose(poses["tool"][0].matrix[:3, 3], [1.0, 0.5, 0.0])
    tool_in_world = relative(poses, "world", "tool").matrix
    world_in_tool = relative(poses, "tool", "world").matrix
    assert np.allclose(tool_in_world[:3, 3], [1.0, 0.5, 0.0])
    assert np.allclose(world_in_tool @ tool_in_world, np.eye(4))


def test_a_rotation_is_composed_as_tf2_composes_it_its_sign_kept():
    # odom -> base_footprint after a long turn (yaw -2.3 rad, broadcast as turtlebot3_node does: w >= 0),
    # base_footprint -> base_scan a quarter turn: tf2 multiplies the broadcast quaternions
    yaw, quarter = -2.3, math.pi / 2
    bridge = bridge_with(
        [stamped("odom", "base_footprint", (1.0, 0.0, 0.0), yaw)],
        [stamped("base_footprint", "base_scan", yaw_rad=quarter)],
    )
    poses = tree_poses(bridge.topics, bridge.frames, None)
    footprint = relative(poses, "odom", "base_footprint").rotation_xyzw
    assert np.allclose(footprint, [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)])  # as broadcast, not negated
    scan = relative(poses, "odom", "base_scan").rotation_xyzw
    assert np.allclose(scan, [0.0, 0.0, math.sin((yaw + quarter) / 2), math.cos((yaw + quarter) / 2)])
    # the path through a common frame: the target's conjugate times the source's
    scan_in_footprint = relative(poses, "base_footprint", "base_scan").rotation_xyzw
    assert np.allclose(scan_in_footprint, [0.0, 0.0, math.sin(quarter / 2), math.cos(quarter / 2)])
    at = SimpleNamespace(time=1.0)
    message = tf.relative_stamped(at, "odom", "base_footprint", *relative(poses, "odom", "base_footprint"))
    assert message["transform"]["rotation"]["z"] == pytest.approx(math.sin(yaw / 2))


def test_frames_of_two_trees_or_below_a_loop_do_not_resolve():
    bridge = bridge_with(
        [stamped("a", "b"), stamped("b", "a"), stamped("a", "c"), stamped("odom", "base_footprint")],
        [stamped("world", "base")],
    )
    poses = tree_poses(bridge.topics, bridge.frames, None)
    assert {"a", "b", "c"}.isdisjoint(poses)  # a loop, and what hangs below it
    assert relative(poses, "world", "base_footprint") is None  # two trees: odom's and world's
    assert relative(poses, "odom", "base_footprint") is not None
    assert relative(poses, "world", "nowhere") is None


def test_programs_frames_serve_when_the_lab_publishes_no_tf():
    bridge = SimpleNamespace(topics={}, frames=NodeFrames())  # a lab started to replay bags
    session = SimpleNamespace(name="/talker")
    assert bridge.frames.offer(session, {"transforms": [stamped("map", "robot", (2.0, 0.0, 0.0))]}, static=False) == []
    assert np.allclose(
        relative(tree_poses(bridge.topics, bridge.frames, None), "map", "robot").matrix[:3, 3], [2.0, 0.0, 0.0]
    )


def pose(x_m: float = 0.0, yaw_rad: float = 0.0) -> np.ndarray:
    matrix = np.eye(4)
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    matrix[:2, :2] = [[c, -s], [s, c]]
    matrix[0, 3] = x_m
    return matrix


def test_a_pair_sends_when_it_moved_or_turned_beyond_its_thresholds():
    pair = Pair("tool")
    assert pair.moved(pose(), 0.01, 0.01)  # never sent: always
    pair.sent = pose()
    assert not pair.moved(pose(x_m=0.009), 0.01, 0.01)
    assert pair.moved(pose(x_m=0.011), 0.01, 0.01)
    assert not pair.moved(pose(yaw_rad=0.019), 0.01, 0.01)  # tf's Quaternion::angle: half of it, 0.0095
    assert pair.moved(pose(yaw_rad=0.021), 0.01, 0.01)
    assert pair.moved(pose(), 0.0, 0.01)
    assert pair.moved(pose(), 0.01, 0.0)


@pytest.mark.parametrize(
    ("args", "says"),
    [
        ({"source_frames": "plate"}, "'source_frames' must be a list"),
        ({"source_frames": ["plate", 3]}, "'source_frames' must be a frame name"),
        ({"source_frames": ["a"] * 101}, "at most 100"),
        ({"target_frame": "/"}, "'target_frame' must be a frame name"),
        ({"rate": 0}, "'rate' must be a positive number"),
        ({"rate": float("nan")}, "'rate' must be a positive number"),
        ({"rate": True}, "'rate' must be a positive number"),
    ],
)
def test_a_bad_request_is_refused_naming_its_field(args, says):
    with pytest.raises(ValueError, match=says):
        _request(args)


def test_a_request_strips_slashes_and_caps_the_rate():
    assert _request({"source_frames": ["/plate"], "target_frame": "/world", "rate": 1000.0}) == (
        ["plate"],
        "world",
        100.0,
    )


# --- the action, on a real bridge in memory (tests/app/rosbridge/clients.py) -------------------------
GOAL, CANCEL = "/tf2_web_republisher/goal", "/tf2_web_republisher/cancel"
FEEDBACK, RESULT = "/tf2_web_republisher/feedback", "/tf2_web_republisher/result"


async def action_client(lab):
    """A client of the action as roslibjs' ActionClient makes one: goal and cancel advertised,
    feedback and result subscribed."""
    session = await connect(lab)
    await op(session, op="advertise", topic=GOAL, type="tf2_web_republisher/TFSubscriptionActionGoal")
    await op(session, op="advertise", topic=CANCEL, type="actionlib_msgs/GoalID")
    await op(session, op="subscribe", topic=FEEDBACK, type="tf2_web_republisher/TFSubscriptionActionFeedback")
    await op(session, op="subscribe", topic=RESULT, type="tf2_web_republisher/TFSubscriptionActionResult")
    return session


def goal(id_: str, **fields) -> dict:
    body = {"source_frames": ["plate"], "target_frame": "panda_link8", "rate": 50.0, **fields}
    return {"goal_id": {"stamp": {"secs": 0, "nsecs": 0}, "id": id_}, "goal": body}


def on(session, topic: str) -> list[dict]:
    return [m["msg"] for m in sent(session, "publish") if m["topic"] == topic]


def test_a_goal_gets_its_frames_as_feedback_and_a_cancel_ends_it_preempted():
    async def check() -> None:
        lab = parts()
        client = await action_client(lab)
        await op(client, op="publish", topic=GOAL, msg=goal("g1"))
        feedback = await until(lambda: on(client, FEEDBACK), "feedback")
        (transform,) = feedback[0]["feedback"]["transforms"]
        assert feedback[0]["status"]["goal_id"]["id"] == "g1"
        assert feedback[0]["status"]["status"] == 1
        assert transform["header"]["frame_id"] == "panda_link8"
        assert transform["child_frame_id"] == "plate"
        offset = lab.lab.snapshot().lifting.plate_offset  # the plate hangs on the flange's z (app/lab/tf.py)
        assert math.isclose(transform["transform"]["translation"]["z"], offset, abs_tol=1e-9)
        await op(client, op="publish", topic=CANCEL, msg={"id": "g1"})
        (result,) = await until(lambda: on(client, RESULT), "result")
        assert result["status"] == {"goal_id": goal("g1")["goal_id"], "status": 2, "text": "cancelled"}  # PREEMPTED
        assert lab.bridge.tf.republisher.subscriptions() == 0

    run(check())


def test_a_goal_ends_with_its_client_and_a_bad_goal_is_rejected_naming_its_field():
    async def check() -> None:
        lab = parts()
        watcher, client = await action_client(lab), await action_client(lab)
        await op(client, op="publish", topic=GOAL, msg=goal("g2"))
        assert lab.bridge.tf.republisher.subscriptions() == 1
        await client.close()
        (result,) = await until(lambda: on(watcher, RESULT), "result")
        assert result["status"]["status"] == 2
        assert result["status"]["text"] == "its client disconnected"
        refused = await op(watcher, op="publish", topic=GOAL, msg=goal("g3", rate=0))
        assert "goal rejected: 'rate' must be a positive number" in refused[0]["msg"]
        rejected = await until(lambda: on(watcher, RESULT)[1:], "the rejected goal's result")
        assert rejected[0]["status"]["status"] == 5  # REJECTED
        assert lab.bridge.tf.republisher.subscriptions() == 0

    run(check())
