"""Topics (app/rosbridge/managers/topics.py): the lab's sampled topics and the nodes' topics, a
node topic relayed from its publishers to its subscriptions and gone when nobody is on it, the cap
on node topics (all clients together; the lab's own node's not counted) and the lab's outgoing rate
shared by every stream."""

from types import SimpleNamespace

import pytest

from sim.messages import Topic

from app.lab.world import LIFTING
from app.ros import rosout
from app.rosbridge.internal.streams import Stream
from app.rosbridge.managers.topics import COMMAND_TYPE, MAX_OUTGOING_RATE, TopicManager
from app.rosbridge.protocol import BadFrame
from tests.app.rosbridge.clients import connect, parts, run


class Received:
    """A subscription's stream as the manager sees it: the messages offered to it, in order."""

    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.offered: list[tuple[dict, dict | None]] = []

    def offer(self, message: dict, header: dict | None = None) -> None:
        self.offered.append((message, header))


def test_the_lab_topics_their_rates_and_the_graph():
    topics = parts().bridge.topics
    assert topics.sampled("/tf_static") and not topics.sampled("/chatter")
    assert topics.min_period("/tf_static") == 0.1 and topics.min_period("/joint_states") == 0.0
    assert "/tf_static" in topics.latched
    types = topics.types()
    assert types[rosout.TOPIC] == rosout.TYPE
    assert types[topics.command_topic] == COMMAND_TYPE
    assert topics.lab_publishes("/joint_states") and topics.lab_publishes(rosout.TOPIC)
    assert topics.lab_publishes("/tf2_web_republisher/status")  # its own node's, relayed
    assert not topics.lab_publishes("/chatter")
    extra = Topic("/extra", "std_msgs/String", lambda snapshot: {"data": "x"})
    topics.add_topic(extra, min_period_s=0.5)
    assert topics.lab_topic("/extra") is extra and topics.min_period("/extra") == 0.5
    topics.remove_topic("/extra")
    assert topics.lab_topic("/extra") is None and "/extra" not in topics.types()


def test_a_node_topic_goes_from_its_publishers_to_its_subscriptions_and_goes_when_nobody_is_on_it():
    async def check() -> None:
        lab = parts(replay=True)
        talker, other = await connect(lab), await connect(lab)
        topics = lab.bridge.topics
        listener = Received("/chatter")
        topics.subscribe("/chatter", "std_msgs/String", listener)
        topics.advertise("/chatter", "std_msgs/String", talker, "string data")
        topics.advertise("/chatter", "std_msgs/String", other, "string other")
        entry = topics.find("/chatter")
        assert entry is not None and entry.type == "std_msgs/String"
        assert entry.definition == "string data"  # the first publisher's text
        assert topics.definitions()["/chatter"] == "string data"
        assert topics.publishes("/chatter", talker) and set(topics.publishers("/chatter")) == {talker, other}
        assert topics.types()["/chatter"] == "std_msgs/String"
        topics.deliver("/chatter", {"data": "hi"}, {"callerid": "/talker"})
        assert listener.offered == [({"data": "hi"}, {"callerid": "/talker"})]
        topics.unadvertise("/chatter", talker)
        topics.unadvertise("/chatter", other)
        assert topics.find("/chatter") is not None  # its subscription holds it
        assert topics.subscribed("/chatter")
        topics.unsubscribe("/chatter", listener)
        assert topics.find("/chatter") is None and "/chatter" not in topics.node_topic_names()
        topics.deliver("/chatter", {"data": "to nobody"})  # no topic: nothing to do
        assert len(listener.offered) == 1

    run(check())


def test_the_labs_own_node_topics_stay_when_nobody_is_on_them():
    topics = TopicManager(LIFTING, replay=True)
    topics.add_lab_node_topic("/status", "actionlib_msgs/GoalStatusArray")
    listener = Received("/status")
    topics.subscribe("/status", "actionlib_msgs/GoalStatusArray", listener)
    topics.unsubscribe("/status", listener)
    entry = topics.find("/status")
    assert entry is not None and entry.lab
    assert topics.lab_publishes("/status")


def test_the_cap_counts_the_nodes_topics_of_all_clients_not_the_labs(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr("app.rosbridge.managers.topics.MAX_TOPICS", 2)
    topics = TopicManager(LIFTING, replay=True)
    topics.add_lab_node_topic("/lab_own", "std_msgs/String")
    topics.subscribe("/a", "std_msgs/String", Received("/a"))
    topics.subscribe("/b", "std_msgs/String", Received("/b"))
    topics.room_for_topic("/a", "subscribe")  # one that exists: room
    with pytest.raises(BadFrame, match="advertise: at most 2 topics exist already"):
        topics.advertise("/c", "std_msgs/String", SimpleNamespace(name="/talker"))  # type: ignore[arg-type]
    assert topics.find("/c") is None


def test_the_streams_share_the_labs_outgoing_rate_in_powers_of_two_of_milliseconds():
    topics = TopicManager(LIFTING, replay=True)
    assert topics.fair_period() == 0.0
    for _ in range(6):  # 6 streams at 5000 messages/s: each at most 1.2 ms apart -> 2 ms
        topics.stream_opened()
    assert topics.fair_period() == 0.002
    assert 6 / topics.fair_period() <= MAX_OUTGOING_RATE
    session = SimpleNamespace(bridge=SimpleNamespace(topics=topics))
    stream = Stream(session, "/joint_states")  # type: ignore[arg-type]  # a stream counts itself
    assert topics.streams == 7
    stream.stop()
    for _ in range(6):
        topics.stream_closed()
    assert topics.streams == 0 and topics.fair_period() == 0.0
