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
"""

from __future__ import annotations

from app.ros import rosout
from app.ros.node_services import normalise_type
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.internal.node_frames import TF_TOPICS
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import MAX_CLIENT_TOPICS, BadFrame, field, headers_field, name_field
from interfaces.packages import field_count
from interfaces.parser import MAX_DEFINITION_FIELDS

MAX_DEFINITION = 64_000  # characters of a carried message definition kept for recorders


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
        known = bridge.topic_types().get(topic)
        if topic == rosout.TOPIC:  # every node logs here, in ROS 2's type or ROS 1's
            if type_name not in rosout.TYPES:
                raise BadFrame(
                    f"advertise: topic {topic} is of type {rosout.TYPE} (or {rosout.ROS1_TYPE}), not {type_name}"
                )
            self.rosout_type = type_name
            self._hold(topic, id_)
            return
        if topic in bridge.topics and topic != bridge.command_topic and topic not in TF_TOPICS:
            raise BadFrame(f"advertise: topic {topic} is published by the lab")
        if known is not None and known != type_name:
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
        if topic not in TF_TOPICS and (topic != bridge.command_topic or topic not in bridge.topics):
            bridge.room_for_topic(topic, "advertise")
            entry = bridge.node_topic(topic, type_name)
            entry.publishers.add(self.session)
            if isinstance(definition, str) and not entry.definition and len(definition) <= MAX_DEFINITION:
                entry.definition = definition
        if headers is not None:
            self.headers[topic] = headers
            self._connection_headers.pop(topic, None)
        self._hold(topic, id_)

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
        self.headers.pop(topic, None)
        self._connection_headers.pop(topic, None)
        self.bridge.leave(topic, publisher=self.session)

    def finish(self) -> None:
        for topic in self.ids:
            self.bridge.leave(topic, publisher=self.session)
        self.ids.clear()


OPS: Ops = {
    "advertise": Op(Advertise, Advertise.advertise, mutating=True),
    "unadvertise": Op(Advertise, Advertise.unadvertise),
}
