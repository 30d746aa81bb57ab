"""Topics (rosbridge_suite's PublisherManager and SubscriberManager together): the lab's topics,
sampled from its snapshot (their rates, the latched ones, the command topic the lab follows), the
topics nodes publish (relayed from their publishers to their subscriptions), the messages every
subscriber's stream of a topic shares, and the lab's outgoing rate shared by all streams. Caps:
MAX_TOPICS node topics, all clients together (one client's are its capabilities')."""

from __future__ import annotations

import math
from collections.abc import Iterable

from sim.messages import Topic

from app.ros import rosout
from app.rosbridge.internal import message_conversion
from app.rosbridge.internal.shared import SharedMessages
from app.rosbridge.managers.windows import Windows
from app.rosbridge.ports import NodeTopicLike, SessionLike, SharedMessagesLike, StreamLike
from app.rosbridge.protocol import MAX_TOPICS, BadFrame
from app.worlds.contract import Command, World

COMMAND_TYPE = "geometry_msgs/Twist"  # what the lab follows on its command topic (either world's)
MAX_OUTGOING_RATE = 5000.0  # messages/s the lab publishes to all its rosbridge clients together (fair_period)


class NodeTopic:
    """A topic that nodes publish (not one of the lab's): its type and who is on it."""

    def __init__(self, type_name: str, lab: bool = False) -> None:
        self.type = type_name
        self.lab = lab  # a topic of the lab's own node (the tf2_web_republisher action's): kept while the lab runs
        self.definition = ""  # the full text its first publisher carried (hri-lab bag record reads it)
        self.publishers: set[SessionLike] = set()
        self.subscriptions: set[StreamLike] = set()  # the subscribers' streams (app/rosbridge/internal/streams.py)


class TopicManager:
    def __init__(
        self, world: World, graded: bool = False, replay: bool = False, windows: Windows | None = None
    ) -> None:
        # the lab's topics, sampled from its snapshot (its world's, those a graded trial's program may see), and
        # the one a node's Twists drive its robot on; none in a lab started to replay bags (`serve --replay`): a
        # player publishes them as a node would
        self.world_topics: list[Topic] = list(world.served_topics(graded))
        self._sampled: dict[str, Topic] = {} if replay else {t.name: t for t in self.world_topics}
        self.min_period_s = dict(world.min_period_s)  # a topic's own longest rate
        self.command_topic: str = world.command_topic
        self.command: Command = world.command  # what the lab runs with each Twist on command_topic
        self.latched: Iterable[str] = world.latched  # sent again only when the message changed
        self._nodes: dict[str, NodeTopic] = {}
        self.windows = windows if windows is not None else Windows()  # a window goes with its topic's publishers
        self.shared: SharedMessagesLike = (
            SharedMessages()
        )  # a topic's message built and encoded once for all its streams
        self.streams = 0  # the topic streams of every client (app/rosbridge/internal/streams.py)

    # --- the lab's topics, sampled from its snapshot ---
    def sampled(self, name: str) -> bool:
        """`name` is one of the lab's topics, sampled from its snapshot."""
        return name in self._sampled

    def lab_topic(self, name: str) -> Topic | None:
        return self._sampled.get(name)

    def sampled_names(self) -> list[str]:
        return list(self._sampled)

    def min_period(self, name: str) -> float:
        """s, the lab topic's own longest rate (0: none)."""
        return self.min_period_s.get(name, 0.0)

    def add_topic(self, topic: Topic, min_period_s: float = 0.0) -> None:
        """A topic sampled from the snapshot, added while the lab runs (e.g. /republish_tfs')."""
        self._sampled[topic.name] = topic
        self.min_period_s[topic.name] = min_period_s

    def replace(self, topic: Topic) -> None:
        """A lab topic built another way (its rate kept): /tf with the programs' frames."""
        self._sampled[topic.name] = topic

    def remove_topic(self, name: str) -> None:
        self._sampled.pop(name, None)
        self.min_period_s.pop(name, None)
        self.shared.forget(name)

    # --- the graph ---
    def types(self) -> dict[str, str]:
        """Every topic's type: the lab's, /rosout, the command topic the lab follows, the nodes'."""
        types = {t.name: t.type for t in self._sampled.values()}
        types[rosout.TOPIC] = rosout.TYPE
        types.setdefault(
            self.command_topic, COMMAND_TYPE
        )  # the lab subscribes to it: in the graph, as a base's /cmd_vel is
        types.update({name: t.type for name, t in self._nodes.items() if name not in types})
        return types

    def lab_publishes(self, topic: str) -> bool:
        """The lab's node publishes `topic`: a topic of its own, /rosout, or one of its node topics."""
        entry = self._nodes.get(topic)
        return topic in self._sampled or topic == rosout.TOPIC or (entry is not None and entry.lab)

    def definitions(self) -> dict[str, str]:
        """node topic -> the full text its publisher carried (those that carried one)."""
        return {name: t.definition for name, t in self._nodes.items() if t.definition}

    # --- the nodes' topics ---
    def add_lab_node_topic(self, name: str, type_name: str) -> None:
        """A topic the lab's own node publishes or subscribes as a program's node would (relayed, not
        sampled from the snapshot): kept while the lab runs."""
        self._nodes[name] = NodeTopic(type_name, lab=True)

    def find(self, topic: str) -> NodeTopicLike | None:
        """The node topic `topic`, if somebody is on it."""
        return self._nodes.get(topic)

    def node_topic_names(self) -> list[str]:
        return list(self._nodes)

    def room_for_topic(self, topic: str, op: str) -> None:
        """BadFrame naming the cap when a new node topic `topic` would be one too many (MAX_TOPICS)."""
        if topic in self._nodes or topic in self._sampled:
            return
        if sum(1 for entry in self._nodes.values() if not entry.lab) >= MAX_TOPICS:
            raise BadFrame(f"{op}: at most {MAX_TOPICS} topics exist already (the lab's limit, all clients together)")

    def _node_topic(self, topic: str, type_name: str) -> NodeTopic:
        """The node topic `topic`, made (of `type_name`) when nobody is on it yet."""
        return self._nodes.setdefault(topic, NodeTopic(type_name))

    def advertise(self, topic: str, type_name: str, publisher: SessionLike, definition: str | None = None) -> None:
        """`publisher` publishes `topic` (BadFrame at the cap); `definition`, its type's full text,
        is kept when the topic has none yet."""
        self.room_for_topic(topic, "advertise")
        entry = self._node_topic(topic, type_name)
        entry.publishers.add(publisher)
        if definition is not None and not entry.definition:
            entry.definition = definition

    def publishes(self, topic: str, session: SessionLike) -> bool:
        entry = self._nodes.get(topic)
        return entry is not None and session in entry.publishers

    def publishers(self, topic: str) -> list[SessionLike]:
        """The clients that publish the node topic `topic` now."""
        entry = self._nodes.get(topic)
        return list(entry.publishers) if entry is not None else []

    def subscribe(self, topic: str, type_name: str, subscription: StreamLike) -> None:
        """A client's stream of the node topic `topic` (made of `type_name` when nobody is on it)."""
        self._node_topic(topic, type_name).subscriptions.add(subscription)

    def subscribed(self, topic: str) -> bool:
        entry = self._nodes.get(topic)
        return entry is not None and bool(entry.subscriptions)

    def deliver(self, topic: str, message: dict, header: dict | None = None) -> None:
        """A message on the node topic `topic` to each of its subscriptions (`header`: its publisher's
        connection header, for the streams that asked)."""
        entry = self._nodes.get(topic)
        for stream in list(entry.subscriptions) if entry is not None else ():
            stream.offer(message, header)

    def unadvertise(self, topic: str, publisher: SessionLike) -> None:
        self._leave(topic, publisher=publisher)

    def unsubscribe(self, topic: str, subscription: StreamLike) -> None:
        self._leave(topic, subscription=subscription)

    def _leave(self, topic: str, publisher: SessionLike | None = None, subscription: StreamLike | None = None) -> None:
        """A publisher (a session) or a subscription (a session's Stream) is off a node topic; the
        topic goes away when nobody publishes or subscribes to it any more (a lab topic: nothing to do)."""
        entry = self._nodes.get(topic)
        if entry is None:
            return
        entry.publishers.discard(publisher)  # None: not one of them
        entry.subscriptions.discard(subscription)
        if not entry.publishers:
            self.windows.close(topic)  # the program that showed it is gone
        if not entry.publishers and not entry.subscriptions and not entry.lab:
            del self._nodes[topic]
            self.shared.forget(topic)
            message_conversion.forget(entry.type, entry.definition)  # what its publisher's definition made

    # --- the lab's outgoing rate, shared by every client's streams ---
    def stream_opened(self) -> None:
        self.streams += 1

    def stream_closed(self) -> None:
        self.streams -= 1

    def fair_period(self) -> float:
        """s between two messages of one stream so that all of them together send at most
        MAX_OUTGOING_RATE messages a second: the event loop keeps most of its time for HTTP and
        the other ops however many clients subscribe at throttle_rate 0. In steps of a power of two
        of milliseconds (1, 2, 4, ... ms), so a stream's period changes only when the count of
        streams crosses one (each change re-paces every stream)."""
        share = self.streams / MAX_OUTGOING_RATE
        return 0.0 if share <= 0.001 else 0.001 * 2.0 ** math.ceil(math.log2(share / 0.001))
