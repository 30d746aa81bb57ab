"""rospy.topics' Subscriber (rosclient/site/rospy/topics.py): its queue_size is the callback's
queue, in the program, as in rospy (and the most the lab holds for it): a callback that keeps up
gets every message offered, even back to back (never lost because the connection's reader thread
offered the next before the callback thread had its turn), and one slower than its messages gets
the newest, the reader never waiting for it."""

from __future__ import annotations

import threading
import time

import pytest

from rosclient import delivery, process
from tests.rosclient.site.conftest import RecordingConnection
from tests.waiting import wait_for

TOPIC = "/franka_state_controller/F_ext"


@pytest.fixture
def lab(site):
    connection = RecordingConnection()
    process._connection.append(connection)
    return connection


def wrench(k: int) -> dict:
    return {"header": {"seq": k, "stamp": {"secs": 0, "nsecs": k}, "frame_id": ""}}


def test_a_callback_that_keeps_up_gets_every_message_offered_back_to_back(lab, monkeypatch):
    import rospy
    from geometry_msgs.msg import WrenchStamped

    monkeypatch.setattr(delivery, "HANDOFF_S", 60.0)  # a bound for a starved machine, not a speed figure
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


def test_the_lab_holds_at_most_queue_size_messages_for_a_subscriber(lab):
    import rospy
    from geometry_msgs.msg import WrenchStamped

    subscriber = rospy.Subscriber(TOPIC, WrenchStamped, lambda msg: None, queue_size=1)
    unbounded = rospy.Subscriber("/other", WrenchStamped, lambda msg: None)
    try:
        assert lab.queue_lengths[TOPIC] == 1  # a program behind on a 1 kHz topic gets the newest
        assert lab.queue_lengths["/other"] == 0  # no queue_size: every message (rosbridge's 0)
    finally:
        subscriber.unregister()
        unbounded.unregister()


def test_a_callback_quicker_than_its_messages_gets_a_burst_in_order_though_it_is_running(lab, monkeypatch):
    import rospy
    from geometry_msgs.msg import WrenchStamped

    monkeypatch.setattr(delivery, "HANDOFF_S", 60.0)  # a bound for a starved machine, not a speed figure
    handled: list[int] = []

    def callback(msg):  # some work: the next message of a burst comes while it runs
        handled.append(msg.header.seq)
        time.sleep(0.001)

    subscriber = rospy.Subscriber(TOPIC, WrenchStamped, callback, queue_size=1)
    try:
        k = 0
        for k in range(10):  # paced, 50 ms apart: its running mean well under their interval
            lab.publish(TOPIC, wrench(k))
            time.sleep(0.05)
        k = 10
        wait_for(lambda: len(handled) == k, timeout=30)
        for j in range(k, k + 100):  # a burst, back to back, while each callback is running
            lab.publish(TOPIC, wrench(j))
        wait_for(lambda: len(handled) == k + 100, timeout=60)
        assert handled == list(range(k + 100))
    finally:
        subscriber.unregister()


def test_a_callback_slower_than_its_messages_gets_the_newest_and_the_reader_goes_on(lab, monkeypatch):
    import rospy
    from geometry_msgs.msg import WrenchStamped

    monkeypatch.setattr(delivery, "HANDOFF_S", 60.0)  # a wait for this callback would hang the reader here
    release, handled = threading.Event(), []
    blocking = threading.Event()

    def callback(msg):  # 50 ms a message, against 2 ms between them; then it blocks
        handled.append(msg.header.seq)
        time.sleep(0.05)
        if blocking.is_set():
            assert release.wait(60)

    subscriber = rospy.Subscriber(TOPIC, WrenchStamped, callback, queue_size=1)
    reader = None
    try:
        k = 0
        while len(handled) < 10:  # its running mean is now well over the messages' interval
            lab.publish(TOPIC, wrench(k))
            k += 1
            time.sleep(0.002)
            assert k < 100_000
        blocking.set()
        last = k + 99

        def burst() -> None:
            for j in range(k, last + 1):
                lab.publish(TOPIC, wrench(j))

        reader = threading.Thread(target=burst)
        reader.start()
        reader.join(timeout=30)
        assert not reader.is_alive(), "the reader waited for a callback slower than its messages"
        assert [message["header"]["seq"] for message, _ in subscriber.queue] == [last]  # the newest kept
        release.set()
        wait_for(lambda: handled[-1] == last, timeout=30)
    finally:
        release.set()
        if reader is not None:
            reader.join(timeout=60)
        subscriber.unregister()
