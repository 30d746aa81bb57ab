"""The bridge's shared state: the lab, its world's settings (its topics, their rates, the command
topic: app/worlds/contract.py), its registries (handed in by the composition root,
app/serving/compose.py), the service table, the topics nodes provide, the connected sessions. Every
session (app/rosbridge/session.py) reads and changes it; it imports no session (app/rosbridge/ports.py
has the shapes both see)."""

from __future__ import annotations

import math
import threading
from collections.abc import Iterable
from typing import Any

from sim.messages import Topic

from app.ros import rosout
from app.ros.actions import ActionServer
from app.ros.node_actions import NodeActions
from app.ros.node_services import NodeServices
from app.ros.services import ServiceRegistry
from app.rosbridge.internal import message_conversion
from app.rosbridge.internal.node_frames import TF_TOPICS, NodeFrames
from app.rosbridge.internal.shared import SharedMessages
from app.rosbridge.ports import (
    FramesLike,
    NodeTopicLike,
    ServiceTableLike,
    SessionLike,
    SharedMessagesLike,
    StreamLike,
    TFRepublisherLike,
)
from app.rosbridge.protocol import MAX_TOPICS, BadFrame
from app.rosbridge.services import ServiceTable
from app.rosbridge.tf_republisher import TFSubscriptionServer
from app.tokens import Throttle
from app.worlds.contract import Command, World
from app.worlds.port import LabPort

COMMAND_TYPE = "geometry_msgs/Twist"  # what the lab follows on its command topic (either world's)


class NodeTopic:
    """A topic that nodes publish (not one of the lab's): its type and who is on it."""

    def __init__(self, type_name: str, lab: bool = False) -> None:
        self.type = type_name
        self.lab = lab  # a topic of the lab's own node (the tf2_web_republisher action's): kept while the lab runs
        self.definition = ""  # the full text its first publisher carried (hri-lab bag record reads it)
        self.publishers: set[SessionLike] = set()
        self.subscriptions: set[StreamLike] = set()  # the subscribers' streams (app/rosbridge/internal/streams.py)


MAX_OUTGOING_RATE = 5000.0  # messages/s the lab publishes to all its rosbridge clients together (fair_period)


def _with_programs_frames(topic: Topic, frames: NodeFrames, static: bool) -> Topic:
    """The lab's /tf or /tf_static with the programs' transforms of that kind after its own."""

    def build(snapshot: Any) -> dict:
        return {"transforms": [*topic.build(snapshot)["transforms"], *frames.transforms(static)]}

    return Topic(topic.name, topic.type, build)


def _frames_of(topics: list[Topic], snapshot: Any) -> set[str]:
    """Every frame the lab's own /tf and /tf_static name (parents and children)."""
    frames = set()
    for topic in topics:
        for t in topic.build(snapshot)["transforms"]:
            frames |= {t["header"]["frame_id"].strip("/"), t["child_frame_id"].strip("/")}
    return frames


class Bridge:
    """What every session shares: the lab, its registries, the node-provided services and topics."""

    def __init__(
        self,
        world: World,
        lab: LabPort[Any],
        nodes: NodeServices,
        actions: ActionServer,
        node_actions: NodeActions,
        token: str | None = None,
        replay: bool = False,
    ) -> None:
        self.lab, self.nodes, self.actions, self.token = lab, nodes, actions, token
        # a graded trial's lab (app/grading/wall_trial.py): a client without the token is the graded program, a node
        # as on a robot (it publishes, advertises, provides and calls its nodes' services); the lab's own services
        # stay the token's (app/rosbridge/session.py, capabilities/call_service.py)
        self.graded = lab.graded
        self.node_actions = node_actions  # actions nodes provide, in the same ActionServer
        self.service_table: ServiceTableLike = ServiceTable(nodes)  # every service a client may call
        # the lab's topics, sampled from its snapshot (its world's, those a graded trial's program may see), and
        # the one a node's Twists drive its robot on; none in a lab started to replay bags (`serve --replay`): a
        # player publishes them as a node would
        self.world_topics = world.served_topics(lab.graded)
        self.topics = {} if replay else {t.name: t for t in self.world_topics}
        own_tf = [t for t in self.world_topics if t.name in TF_TOPICS]
        # the frames programs publish: /tf and /tf_static carry them with the lab's, whose own frames
        # (the served world's) no program may publish
        self.frames: FramesLike = NodeFrames(lambda: _frames_of(own_tf, lab.snapshot())) if own_tf else NodeFrames()
        for name, static in TF_TOPICS.items():
            if name in self.topics:
                self.topics[name] = _with_programs_frames(self.topics[name], self.frames, static)
        self.min_period_s = dict(world.min_period_s)  # a topic's own longest rate
        self.command_topic = world.command_topic
        self.command: Command = world.command  # what the lab runs with each Twist on command_topic
        self.latched: Iterable[str] = world.latched  # sent again only when the message changed
        self.node_topics: dict[str, NodeTopicLike] = {}
        self.shared: SharedMessagesLike = (
            SharedMessages()
        )  # a topic's message built and encoded once for all its streams
        self.tf_republisher: TFRepublisherLike = TFSubscriptionServer(
            self
        )  # its action's topics are node topics of the lab's
        self.windows: dict[str, dict] = {}  # a program's cv2.imshow window (topic) -> its newest image
        self.sessions: list[SessionLike] = []
        self.auth_throttle = Throttle()  # wrong tokens of the auth op, per client address (HTTP's rule)
        self.streams = 0  # the topic streams of every client (app/rosbridge/internal/streams.py)
        self._counter = 0
        if self.topics and world.warm_up is not None:
            # what its topics need loaded now, not on the event loop when a node first subscribes
            threading.Thread(target=world.warm_up, args=(lab,), name="rosbridge-warm-up", daemon=True).start()

    def fair_period(self) -> float:
        """s between two messages of one stream so that all of them together send at most
        MAX_OUTGOING_RATE messages a second: the event loop keeps most of its time for HTTP and
        the other ops however many clients subscribe at throttle_rate 0. In steps of a power of two
        of milliseconds (1, 2, 4, ... ms), so a stream's period changes only when the count of
        streams crosses one (each change re-paces every stream)."""
        share = self.streams / MAX_OUTGOING_RATE
        return 0.0 if share <= 0.001 else 0.001 * 2.0 ** math.ceil(math.log2(share / 0.001))

    @property
    def services(self) -> ServiceRegistry:
        """The lab's service registry: its own services and the nodes'."""
        return self.nodes.registry

    def next_name(self) -> str:
        self._counter += 1
        return f"/rosbridge_client_{self._counter}"

    def add_topic(self, topic: Topic, min_period_s: float = 0.0) -> None:
        """A topic sampled from the snapshot, added while the lab runs (e.g. /republish_tfs')."""
        self.topics[topic.name] = topic
        self.min_period_s[topic.name] = min_period_s

    def remove_topic(self, name: str) -> None:
        self.topics.pop(name, None)
        self.min_period_s.pop(name, None)
        self.shared.forget(name)

    def add_lab_node_topic(self, name: str, type_name: str) -> None:
        """A topic the lab's own node publishes or subscribes as a program's node would (relayed, not
        sampled from the snapshot): kept while the lab runs."""
        self.node_topics[name] = NodeTopic(type_name, lab=True)

    def lab_publishes(self, topic: str) -> bool:
        """The lab's node publishes `topic`: a topic of its own, /rosout, or one of its node topics."""
        entry = self.node_topics.get(topic)
        return topic in self.topics or topic == rosout.TOPIC or (entry is not None and entry.lab)

    def topic_types(self) -> dict[str, str]:
        types = {t.name: t.type for t in self.topics.values()}
        types[rosout.TOPIC] = rosout.TYPE
        types.setdefault(
            self.command_topic, COMMAND_TYPE
        )  # the lab subscribes to it: in the graph, as a base's /cmd_vel is
        types.update({name: t.type for name, t in self.node_topics.items() if name not in types})
        return types

    def room_for_topic(self, topic: str, op: str) -> None:
        """BadFrame naming the cap when a new node topic `topic` would be one too many (MAX_TOPICS)."""
        if topic in self.node_topics or topic in self.topics:
            return
        if sum(1 for entry in self.node_topics.values() if not entry.lab) >= MAX_TOPICS:
            raise BadFrame(f"{op}: at most {MAX_TOPICS} topics exist already (the lab's limit, all clients together)")

    def node_topic(self, topic: str, type_name: str) -> NodeTopicLike:
        """The node topic `topic`, made (of `type_name`) when nobody is on it yet."""
        return self.node_topics.setdefault(topic, NodeTopic(type_name))

    def leave(self, topic: str, publisher: SessionLike | None = None, subscription: StreamLike | None = None) -> None:
        """A publisher (a session) or a subscription (a session's Stream) is off a node topic; the
        topic goes away when nobody publishes or subscribes to it any more (a lab topic: nothing to do)."""
        entry = self.node_topics.get(topic)
        if entry is None:
            return
        entry.publishers.discard(publisher)
        entry.subscriptions.discard(subscription)
        if not entry.publishers:
            self.windows.pop(topic, None)  # the program that showed it is gone
        if not entry.publishers and not entry.subscriptions and not entry.lab:
            del self.node_topics[topic]
            self.shared.forget(topic)
            message_conversion.forget(entry.type, entry.definition)  # what its publisher's definition made
