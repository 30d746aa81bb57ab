"""advertise / unadvertise: a client announces the topics it publishes (the lab's own topics are the
lab's; the command topic, /rosout, /tf and /tf_static may be published by any client).

As rosbridge_suite's advertise capability, a client's publisher of a topic counts the ids of the
advertise ops that made it (an op without an id counts as one id of its own): an unadvertise
withdraws its id (one without an id withdraws them all), and the publisher ends when its last id
is withdrawn.

The lab's extension `headers` ({str: str}, bounded: protocol.headers_field) is a ROS 1 publisher's
connection header's extra fields (rospy's `Publisher(headers=...)`): the relay hands them, with the
publisher's node name as `callerid`, to the subscribers that ask for connection headers
(capabilities/subscribe.py). An advertise that carries them replaces the topic's earlier ones.

rosbridge's `latch` (with `queue_size`, the history depth, 100 when absent as in rosbridge_suite)
makes the publisher a ROS 2 TRANSIENT_LOCAL one (ROS 1's latched: depth 1): the relay keeps its last
`queue_size` messages (at most MAX_LATCHED) while it publishes the topic, and a later subscription
gets them first (capabilities/subscribe.py). An advertise with `latch` may deepen the history,
never undo it (a program's publishers of a topic share one advertise). The lab's extension
`lifespan` (s, > 0: rclpy's QoS lifespan) drops a kept message that old from what a later
subscription gets.
"""

from __future__ import annotations

import math
import time
from collections import deque

from app.ros import rosout
from app.ros.node_services import normalise_type
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.internal.node_frames import TF_TOPICS, TF_TYPES
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import MAX_CLIENT_TOPICS, BadFrame, field, headers_field, name_field
from interfaces.packages import field_count
from interfaces.parser import MAX_DEFINITION_FIELDS

MAX_DEFINITION = 64_000  # characters of a carried message definition kept for recorders
MAX_LATCHED = 100  # messages a latched publisher's history keeps per topic at most (an image's is a few MB)
DEFAULT_QUEUE_SIZE = 100  # rosbridge_suite's advertise default


class Advertise(Capability):
    """The topics this client publishes, each with the ids of the advertise ops that hold it, and
    the type it logs to /rosout in (ROS 2's or ROS 1's)."""

    DETAILS = "publishing"

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.ids: dict[str, set[Id]] = {}  # topic -> the ids of the advertise ops that hold its publisher
        self.rosout_type = rosout.TYPE
        self.headers: dict[str, dict[str, str]] = {}  # topic -> the connection header's extra fields
        self._connection_headers: dict[str, tuple[str, dict[str, str]]] = {}  # topic -> (node name, header)
        self.latched: dict[str, deque[tuple[dict, dict, float]]] = {}  # topic -> its last (message, header, expiry)s
        self.lifespan_s: dict[str, float] = {}  # topic -> how long a kept message lives (none: for ever)

    @property
    def publishing(self) -> set[str]:
        return set(self.ids)

    def names(self) -> list[str]:
        return list(self.ids)

    def _hold(self, topic: str, id_: Id) -> None:
        self.ids.setdefault(topic, set()).add(id_)

    def connection_header(self, topic: str) -> dict[str, str]:
        """What a subscriber of `topic` is told of this publisher: `callerid` (its node's name) and
        the extra fields it advertised, which may replace it (as rospy's may). One dict while the
        name and the fields stay (built once, not per message)."""
        name = self.session.name
        kept = self._connection_headers.get(topic)
        if kept is None or kept[0] != name:
            kept = self._connection_headers[topic] = (name, {"callerid": name, **self.headers.get(topic, {})})
        return kept[1]

    async def advertise(self, message: dict, id_: Id) -> None:
        bridge = self.bridge
        topic = name_field(message, "topic")
        type_name = normalise_type(field(message, "type", str))
        headers = headers_field(message)
        latch = field(message, "latch", bool, False)
        queue_size = field(message, "queue_size", int, DEFAULT_QUEUE_SIZE)
        if queue_size < 0:
            raise BadFrame("advertise: 'queue_size' must be >= 0")
        lifespan_s = field(message, "lifespan", (int, float), None, allow_none=True)
        if lifespan_s is not None and not (math.isfinite(lifespan_s) and lifespan_s > 0):
            raise BadFrame("advertise: 'lifespan' must be a number of seconds > 0")
        known = bridge.topics.types().get(topic)
        if topic == rosout.TOPIC:  # every node logs here, in ROS 2's type or ROS 1's
            if type_name not in rosout.TYPES:
                raise BadFrame(
                    f"advertise: topic {topic} is of type {rosout.TYPE} (or {rosout.ROS1_TYPE}), not {type_name}"
                )
            self.rosout_type = type_name
            self._hold(topic, id_)
            return
        if bridge.topics.sampled(topic) and topic != bridge.topics.command_topic and topic not in TF_TOPICS:
            raise BadFrame(f"advertise: topic {topic} is published by the lab")
        if known is not None and known != type_name and not (topic in TF_TOPICS and type_name in TF_TYPES):
            raise BadFrame(f"advertise: topic {topic} is of type {known}, not {type_name}")
        if topic not in self.ids and len(self.ids) >= MAX_CLIENT_TOPICS:
            raise BadFrame(f"advertise: at most {MAX_CLIENT_TOPICS} topics per client (unadvertise one first)")
        definition = message.get("definition")  # hri-lab's programs carry their type's full text
        if isinstance(definition, str) and field_count(definition) > MAX_DEFINITION_FIELDS:
            raise BadFrame(
                f"advertise: the definition of {type_name} has {field_count(definition)} fields, over the cap of "
                f"{MAX_DEFINITION_FIELDS} (its types' fields counted once each)"
            )
        # tf: shared with the lab (node_frames.py); a command topic the lab publishes too (the lifting
        # world's) is the lab's, one it only follows (the mobile world's /cmd_vel) is the nodes'
        if topic not in TF_TOPICS and (topic != bridge.topics.command_topic or not bridge.topics.sampled(topic)):
            kept = definition if isinstance(definition, str) and len(definition) <= MAX_DEFINITION else None
            bridge.topics.advertise(topic, type_name, self.session, kept)
        if headers is not None:
            self.headers[topic] = headers
            self._connection_headers.pop(topic, None)
        if latch and topic not in TF_TOPICS:
            self._latch(topic, min(max(queue_size, 1), MAX_LATCHED))
        if lifespan_s is not None:
            self.lifespan_s[topic] = float(lifespan_s)
        self._hold(topic, id_)

    def _latch(self, topic: str, depth: int) -> None:
        kept = self.latched.get(topic)
        if kept is None or (kept.maxlen or 0) < depth:
            self.latched[topic] = deque(kept or (), maxlen=depth)

    def keep(self, topic: str, message: dict, header: dict) -> None:
        """A message this client published on `topic`: kept if its publisher is latched."""
        kept = self.latched.get(topic)
        if kept is not None:
            kept.append((message, header, time.monotonic() + self.lifespan_s.get(topic, math.inf)))

    def kept(self, topic: str) -> list[tuple[dict, dict]]:
        """What this client's latched publisher of `topic` kept and still lives (its lifespan)."""
        now = time.monotonic()
        return [(message, header) for message, header, expiry in list(self.latched.get(topic, ())) if expiry > now]

    async def unadvertise(self, message: dict, id_: Id) -> None:
        topic = name_field(message, "topic")
        ids = self.ids.get(topic)
        if ids is None:
            await self.session.report("warning", f"unadvertise: {topic} is not advertised by this client", id_)
            return
        if id_ is None:
            ids.clear()
        elif id_ not in ids:
            await self.session.report(
                "warning", f"unadvertise: {topic} was not advertised with id {id_!r} by this client", id_
            )
            return
        ids.discard(id_)
        if ids:  # another of its advertise ops still holds the publisher
            return
        del self.ids[topic]
        self.latched.pop(topic, None)
        self.lifespan_s.pop(topic, None)
        self.headers.pop(topic, None)
        self._connection_headers.pop(topic, None)
        self.bridge.topics.unadvertise(topic, self.session)

    def finish(self) -> None:
        for topic in self.ids:
            self.bridge.topics.unadvertise(topic, self.session)
        self.ids.clear()
        self.latched.clear()


OPS: Ops = {
    "advertise": Op(Advertise, Advertise.advertise, mutating=True),
    "unadvertise": Op(Advertise, Advertise.unadvertise),
}
