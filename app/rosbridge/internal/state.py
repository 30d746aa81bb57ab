"""The bridge's shared state: the lab, its registries, the services and topics nodes provide,
the connected sessions. Every session (app/rosbridge/session.py) reads and changes it; it imports
no session."""

from __future__ import annotations

import threading
from typing import Any

from app.lab.topics import MIN_PERIOD_S, TOPICS, franka_state
from app.ros import rosout
from app.rosbridge.internal.node_actions import NodeActions
from app.rosbridge.internal.node_params import NodeParameters
from app.rosbridge.internal.node_services import NodeServices

COMMAND_TOPIC = "/cartesian_velocity_controller/command"


class NodeTopic:
    """A topic that nodes publish (not one of the lab's): its type and who is on it."""

    def __init__(self, type_name: str) -> None:
        self.type = type_name
        self.definition = ""  # the full text its first publisher carried (hri-lab bag record reads it)
        self.publishers: set[Any] = set()  # sessions
        self.subscriptions: set[Any] = set()  # app.rosbridge.internal.streams.Stream


class Bridge:
    """What every session shares: the lab, its registries, the node-provided services and topics."""

    def __init__(
        self, lab: Any, nodes: NodeServices, actions: Any, token: str | None = None, replay: bool = False
    ) -> None:
        self.lab, self.nodes, self.actions, self.token = lab, nodes, actions, token
        self.node_actions = NodeActions(actions)  # actions nodes provide, in the same ActionServer
        lab.params.remote = NodeParameters(nodes)  # parameters nodes declare, in the same parameter server
        # the lab's topics, sampled from its snapshot; none in a lab started to replay bags (`serve
        # --replay`): a player publishes them as a node would
        self.topics = {} if replay else {t.name: t for t in TOPICS}
        self.min_period_s = dict(MIN_PERIOD_S)  # a topic's own longest rate (app/lab/topics.py)
        self.node_topics: dict[str, NodeTopic] = {}
        self.windows: dict[str, dict] = {}  # a program's cv2.imshow window (topic) -> its newest image
        self.sessions: list[Any] = []
        self._counter = 0
        # load franka_states' robot model now, not on the event loop when a node first subscribes
        threading.Thread(target=franka_state, args=(lab.snapshot(),), name="rosbridge-warm-up", daemon=True).start()

    @property
    def services(self):
        return self.nodes.registry

    def next_name(self) -> str:
        self._counter += 1
        return f"/rosbridge_client_{self._counter}"

    def add_topic(self, topic, min_period_s: float = 0.0) -> None:
        """A topic sampled from the snapshot, added while the lab runs (e.g. /republish_tfs')."""
        self.topics[topic.name] = topic
        self.min_period_s[topic.name] = min_period_s

    def remove_topic(self, name: str) -> None:
        self.topics.pop(name, None)
        self.min_period_s.pop(name, None)

    def topic_types(self) -> dict[str, str]:
        types = {t.name: t.type for t in self.topics.values()}
        types[rosout.TOPIC] = rosout.TYPE
        types.update({name: t.type for name, t in self.node_topics.items() if name not in types})
        return types

    def leave(self, topic: str, publisher: Any = None, subscription: Any = None) -> None:
        """A publisher (a session) or a subscription (a session's Stream) is off a node topic; the
        topic goes away when nobody publishes or subscribes to it any more (a lab topic: nothing to do)."""
        entry = self.node_topics.get(topic)
        if entry is None:
            return
        entry.publishers.discard(publisher)
        entry.subscriptions.discard(subscription)
        if not entry.publishers:
            self.windows.pop(topic, None)  # the program that showed it is gone
        if not entry.publishers and not entry.subscriptions:
            del self.node_topics[topic]
