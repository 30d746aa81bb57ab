"""app/cli/bag_ros.py's own rules: which topics `bag record` takes (names, -a, -e, -x) and when
`bag play` publishes each message (the recorded gaps divided by -r, from -s seconds in)."""

import argparse

import pytest

from app.cli.bag_ros import chosen, timeline
from app.recording import bags

TOPICS = {
    "/joint_states": "sensor_msgs/JointState",
    "/tf": "tf2_msgs/TFMessage",
    "/tf_static": "tf2_msgs/TFMessage",
    "/image_raw": "sensor_msgs/Image",
    "/student_info": "student_pkg/StudentInfo",
}


def args(*topics: str, all: bool = False, regex: str | None = None, exclude: str | None = None):
    return argparse.Namespace(topics=list(topics), all=all, regex=regex, exclude=exclude)


def test_named_topics_are_taken_with_or_without_their_slash():
    assert chosen(TOPICS, args("student_info", "/image_raw", "/not_there")) == ["/image_raw", "/student_info"]


def test_all_less_an_exclusion():
    assert chosen(TOPICS, args(all=True, exclude="^/tf")) == ["/joint_states", "/image_raw", "/student_info"]


def test_a_regular_expression_picks_by_name():
    assert chosen(TOPICS, args(regex="tf")) == ["/tf", "/tf_static"]


def message(t: int) -> bags.BagMessage:
    return bags.BagMessage("/x", "std_msgs/msg/Int32", t, {"data": t})


TIMES = [1_000_000_000, 1_100_000_000, 1_400_000_000, 2_000_000_000]


def test_the_player_keeps_the_recorded_gaps_divided_by_the_rate():
    offsets = [o for o, _ in timeline(iter(map(message, TIMES)), TIMES[0], 2.0, 0.0)]
    assert offsets == pytest.approx([0, 0.05, 0.2, 0.5])


def test_the_player_starts_start_seconds_into_the_bag():
    started = list(timeline(iter(map(message, TIMES)), TIMES[0], 1.0, 0.3))  # -s 0.3: from 0.4 s in
    assert [(o, m.log_time) for o, m in started] == [(0.0, TIMES[2]), (pytest.approx(0.6), TIMES[3])]
