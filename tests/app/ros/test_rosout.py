"""app/ros/rosout.py: a log line as rcl_interfaces/Log and rosgraph_msgs/Log (their level numbers
differ), a published message checked field by field, and the newest lines handed to listeners."""

import pytest

from app.ros.rosout import (
    LEVELS,
    ROS1_LEVELS,
    ROS1_TYPE,
    TYPE,
    BadLogMessage,
    LogLine,
    Rosout,
    from_message,
)


def test_a_line_as_either_message_type():
    line = LogLine(12.25, "WARN", "cooperative_lifting", "slipping")
    ros2 = line.message(TYPE)
    assert ros2["stamp"] == {"sec": 12, "nanosec": 250_000_000}
    assert ros2["level"] == LEVELS["WARN"] == 30
    ros1 = line.message(ROS1_TYPE)
    assert ros1["header"]["stamp"] == {"secs": 12, "nsecs": 250_000_000}
    assert ros1["level"] == ROS1_LEVELS["WARN"] == 4
    assert ros1["name"] == ros2["name"] == "cooperative_lifting"


def test_a_published_message_comes_back_the_same_from_either_type():
    line = LogLine(3.5, "ERROR", "/talker", "no", "a.py", "f", 7)
    for type_name in (TYPE, ROS1_TYPE):
        assert from_message(line.message(type_name), type_name, "/other") == line


def test_an_empty_name_is_the_publishing_node_s():
    assert from_message({"msg": "hi"}, TYPE, "/rosbridge_client_3").node == "/rosbridge_client_3"


@pytest.mark.parametrize(
    ("msg", "field"),
    [
        ({"level": 3}, "level"),
        ({"level": True}, "level"),
        ({"msg": 5}, "msg"),
        ({"line": "7"}, "line"),
        ({"stamp": {"sec": "x", "nanosec": 0}}, "stamp"),
        ({"stamp": {"sec": float("inf"), "nanosec": 0}}, "stamp"),
    ],
)
def test_a_wrong_field_is_named(msg, field):
    with pytest.raises(BadLogMessage, match=field):
        from_message(msg, TYPE, "/n")


def test_the_newest_lines_are_kept_numbered_and_handed_on():
    rosout = Rosout(max_lines=3)
    heard = []
    stop = rosout.listen(heard.append)
    rosout.listen(lambda line: 1 / 0)  # a listener that fails does not stop the others
    for n in range(5):
        rosout.log("lab", f"line {n}")
    assert [line.msg for line in rosout.recent()] == ["line 2", "line 3", "line 4"]
    assert [line.seq for line in heard] == [1, 2, 3, 4, 5]
    stop()
    rosout.log("lab", "after")
    assert len(heard) == 5
