"""advertise / unadvertise: a client announces the topics it publishes (the lab's own topics are the
lab's; the command topic, /rosout, /tf and /tf_static may be published by any client).

As rosbridge_suite's advertise capability, a client's publisher of a topic counts the ids of the
advertise ops that made it (an op without an id counts as one id of its own): an unadvertise
withdraws its id (one without an id withdraws them all), and the publisher ends when its last id
is withdrawn.
"""

from __future__ import annotations

from app.ros import rosout
from app.ros.node_services import normalise_type
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.internal.node_frames import TF_TOPICS
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import BadFrame, field, name_field

MAX_DEFINITION = 64_000  # characters of a carried message definition kept for recorders


class Advertise(Capability):
    """The topics this client publishes, each with the ids of the advertise ops that hold it, and
    the type it logs to /rosout in (ROS 2's or ROS 1's)."""

    DETAILS = "publishing"

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.ids: dict[str, set[Id]] = {}  # topic -> the ids of the advertise ops that hold its publisher
        self.rosout_type = rosout.TYPE

    @property
    def publishing(self) -> set[str]:
        return set(self.ids)

    def names(self) -> list[str]:
        return list(self.ids)

    def _hold(self, topic: str, id_: Id) -> None:
        self.ids.setdefault(topic, set()).add(id_)

    async def advertise(self, message: dict, id_: Id) -> None:
        bridge = self.bridge
        topic = name_field(message, "topic")
        type_name = normalise_type(field(message, "type", str))
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
        if topic not in TF_TOPICS and topic != bridge.command_topic:  # tf: shared with the lab (node_frames.py)
            entry = bridge.node_topic(topic, type_name)
            entry.publishers.add(self.session)
            definition = message.get("definition")  # hri-lab's programs carry their type's full text
            if isinstance(definition, str) and not entry.definition and len(definition) <= MAX_DEFINITION:
                entry.definition = definition
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
        self.bridge.leave(topic, publisher=self.session)

    def finish(self) -> None:
        for topic in self.ids:
            self.bridge.leave(topic, publisher=self.session)
        self.ids.clear()


OPS: Ops = {
    "advertise": Op(Advertise, Advertise.advertise, mutating=True),
    "unadvertise": Op(Advertise, Advertise.unadvertise),
}
