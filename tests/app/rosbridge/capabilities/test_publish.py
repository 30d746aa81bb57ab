"""publish (app/rosbridge/capabilities/publish.py): a node topic to its subscribers (made whole once
for all of them), a log line to /rosout, transforms into the lab's tree, a Twist checked before it
reaches the simulation."""

import math

import pytest

from app.rosbridge.capabilities.publish import Publish, twist_values
from app.rosbridge.protocol import BadFrame
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_a_twist_is_six_finite_numbers_missing_ones_zero():
    assert twist_values({"linear": {"x": 0.1}, "angular": {"z": -2}}, "/cmd") == [0.1, 0, 0, 0, 0, -2.0]
    with pytest.raises(BadFrame, match=r"field 'msg.linear.y' must be a finite number"):
        twist_values({"linear": {"y": math.nan}}, "/cmd")
    with pytest.raises(BadFrame, match=r"field 'msg.angular.x' must be a finite number, got true"):
        twist_values({"angular": {"x": True}}, "/cmd")
    with pytest.raises(BadFrame, match="geometry_msgs/Twist has no field 'speed'"):
        twist_values({"speed": 1}, "/cmd")


def test_a_node_topic_needs_its_advertise_and_the_labs_topics_are_the_labs():
    async def check() -> None:
        session = await connect(parts())
        refused = await op(session, op="publish", topic="/chatter", msg={"data": "x"})
        assert "advertise /chatter first" in refused[0]["msg"]
        assert "published by the lab" in (await op(session, op="publish", topic="/joint_states", msg={}))[0]["msg"]
        await op(session, op="advertise", topic="/chatter", type="std_msgs/String")
        assert await op(session, op="publish", topic="/chatter", msg={"data": "x"}) == []

    run(check())


def test_a_node_topics_message_reaches_every_subscriber_whole_and_a_wrong_one_is_refused_by_name():
    async def check() -> None:
        lab = parts(replay=True)
        client, server, watcher = [await connect(lab) for _ in range(3)]
        for listener in (server, watcher):
            await op(listener, op="subscribe", topic="/test_action/cancel", type="actionlib_msgs/GoalID")
        await op(client, op="advertise", topic="/test_action/cancel", type="actionlib_msgs/GoalID")
        assert await op(client, op="publish", topic="/test_action/cancel", msg={"id": "goal_1"}) == []  # ROS 1's cancel
        for listener in (server, watcher):
            delivered = await until(lambda listener=listener: sent(listener, "publish"), "the cancel at its subscriber")
            stamp = {"sec": 0, "nanosec": 0, "secs": 0, "nsecs": 0}
            assert delivered[0]["msg"] == {"stamp": stamp, "id": "goal_1"}
        assert len(lab.bridge.topics.shared._frames["/test_action/cancel"]) == 1  # one message, encoded once for both
        refused = await op(client, op="publish", topic="/test_action/cancel", msg={"id": "goal_2", "stamp": 5})
        assert refused[0]["level"] == "error"
        assert (
            "publish /test_action/cancel: actionlib_msgs/GoalID message: field 'stamp' must be a time"
            in (refused[0]["msg"])
        )

    run(check())


def test_a_log_line_joins_the_labs_log_under_the_nodes_name():
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        await op(session, op="node", name="/talker")
        assert "advertise /rosout first" in (await op(session, op="publish", topic="/rosout", msg={}))[0]["msg"]
        await op(session, op="advertise", topic="/rosout", type="rosgraph_msgs/Log")
        await op(session, op="publish", topic="/rosout", msg={"level": 4, "msg": "too close"})  # ROS 1's WARN
        line = [entry for entry in lab.lab.rosout.recent() if entry.msg == "too close"][-1]
        assert line.node == "/talker"
        assert line.level == "WARN"

    run(check())


def test_a_refused_frame_is_told_once_and_finish_takes_the_clients_frames_away():
    frame = {
        "header": {"frame_id": "world"},
        "child_frame_id": "panda_link0",  # the lab's own frame
        "transform": {"translation": {"x": 0, "y": 0, "z": 0}, "rotation": {"x": 0, "y": 0, "z": 0, "w": 1}},
    }
    mine = dict(frame, child_frame_id="marker")

    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        await op(session, op="advertise", topic="/tf", type="tf2_msgs/TFMessage")
        refused = await op(session, op="publish", topic="/tf", msg={"transforms": [frame, mine]})
        assert "refused" in refused[0]["msg"]
        assert "panda_link0" in refused[0]["msg"]
        assert await op(session, op="publish", topic="/tf", msg={"transforms": [frame, mine]}) == []  # told once
        assert "marker" in lab.bridge.tf.frames.names()
        session.capability(Publish).finish()
        assert "marker" not in lab.bridge.tf.frames.names()

    run(check())


def test_ros1s_tf_tfmessage_on_tf_is_tf2s_message_and_its_frames_join_the_tree():
    """The ROS 1 tf tutorial's fixed_tf_broadcaster advertises /tf as tf/tfMessage (tf2_msgs/TFMessage's
    twin, the same md5sum: ROS 1 connects them); another type is still refused, and so is a
    subscriber of another type."""
    carrot = {
        "header": {"frame_id": "world"},
        "child_frame_id": "carrot1",
        "transform": {"translation": {"x": 0, "y": 2, "z": 0}, "rotation": {"x": 0, "y": 0, "z": 0, "w": 1}},
    }

    async def check() -> None:
        lab = parts()  # with the lab's topics: /tf is tf2_msgs/TFMessage
        session = await connect(lab)
        assert await op(session, op="advertise", topic="/tf", type="tf/tfMessage") == []
        assert await op(session, op="publish", topic="/tf", msg={"transforms": [carrot]}) == []
        assert "carrot1" in lab.bridge.tf.frames.names()
        wrong = await op(await connect(lab), op="advertise", topic="/tf", type="std_msgs/String")
        assert "is of type tf2_msgs/TFMessage, not std_msgs/String" in wrong[0]["msg"]
        listener = await connect(lab)
        assert await op(listener, op="subscribe", topic="/tf", type="tf/tfMessage") == []
        refused = await op(await connect(lab), op="subscribe", topic="/tf", type="std_msgs/String")
        assert "is of type tf2_msgs/TFMessage, not std_msgs/String" in refused[0]["msg"]

    run(check())
