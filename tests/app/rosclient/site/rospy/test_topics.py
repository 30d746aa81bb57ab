"""rospy.topics' Subscriber (app/rosclient/site/rospy/topics.py): its queue_size is the callback's
queue, as in rospy: a message is dropped only while the callback is busy, never because the
connection's reader thread offered the next one before the callback thread had its turn."""

from __future__ import annotations

import threading

import pytest

from app.rosclient import process
from tests.app.rosclient.site.conftest import RecordingConnection
from tests.waiting import wait_for

TOPIC = "/franka_state_controller/F_ext"


@pytest.fixture()
def lab(site):
    connection = RecordingConnection()
    process._connection.append(connection)
    return connection


def wrench(k: int) -> dict:
    return {"header": {"seq": k, "stamp": {"secs": 0, "nsecs": k}, "frame_id": ""}}


def test_a_callback_that_keeps_up_gets_every_message_offered_back_to_back(lab, monkeypatch):
    import rospy
    from geometry_msgs.msg import WrenchStamped
    from rospy import topics

    monkeypatch.setattr(topics, "HANDOFF_S", 60.0)  # a bound for a starved machine, not a speed figure
    handled: list[int] = []
    subscriber = rospy.Subscriber(TOPIC, WrenchStamped, lambda msg: handled.append(msg.header.seq), queue_size=1)
    try:
        lab.publish(TOPIC, wrench(0))
        wait_for(lambda: handled == [0], timeout=30)
        for k in range(1, 201):  # with no pause between them: the reader holds the interpreter
            lab.publish(TOPIC, wrench(k))
        wait_for(lambda: len(handled) == 201, timeout=60)
        assert handled == list(range(201))
    finally:
        subscriber.unregister()


def test_a_busy_callback_loses_the_oldest_and_the_reader_never_waits_for_it(lab):
    import rospy
    from geometry_msgs.msg import WrenchStamped

    release, handled = threading.Event(), []

    def callback(msg):
        handled.append(msg.header.seq)
        assert release.wait(60)

    subscriber = rospy.Subscriber(TOPIC, WrenchStamped, callback, queue_size=1)
    try:
        lab.publish(TOPIC, wrench(1))
        wait_for(lambda: handled == [1], timeout=30)  # busy from now on
        for k in range(2, 102):  # offered while it is busy: returns at once (a wait would hang here)
            lab.publish(TOPIC, wrench(k))
        assert [message["header"]["seq"] for message, _ in subscriber.queue] == [101]  # the newest is kept
        release.set()
        wait_for(lambda: handled == [1, 101], timeout=30)
        assert subscriber.received == 101
    finally:
        release.set()
        subscriber.unregister()
