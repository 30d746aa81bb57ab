"""advertise / unadvertise: a client announces the topics it publishes (the lab's own topics are the
lab's; the command topic, /rosout, /tf and /tf_static may be published by any client).

As rosbridge_suite's advertise capability, a client's publisher of a topic counts the ids of the
advertise ops that made it (an op without an id counts as one id of its own): an unadvertise
withdraws its id (one without an id withdraws them all), and the publisher ends when its last id
is withdrawn.
"""

from __future__ import annotations

from typing import Any

from app.ros import rosout
from app.rosbridge.capabilities.op import Op
from app.rosbridge.internal.node_frames import TF_TOPICS
from app.rosbridge.internal.node_services import normalise_type
from app.rosbridge.internal.state import NodeTopic
from app.rosbridge.protocol import BadFrame, field, name_field

MAX_DEFINITION = 64_000  # characters of a carried message definition kept for recorders


def advertise_ids(session: Any, topic: str) -> set[Any]:
    """The ids of the advertise ops this client's publisher of `topic` holds."""
    ids: dict[str, set[Any]] = session.state.setdefault("advertise_ids", {})
    return ids.setdefault(topic, set())


async def advertise(session: Any, message: dict, id_: Any) -> None:
    bridge = session.bridge
    topic = name_field(message, "topic")
    type_name = normalise_type(field(message, "type", str))
    known = bridge.topic_types().get(topic)
    if topic == rosout.TOPIC:  # every node logs here, in ROS 2's type or ROS 1's
        if type_name not in rosout.TYPES:
            raise BadFrame(
                f"advertise: topic {topic} is of type {rosout.TYPE} (or {rosout.ROS1_TYPE}), not {type_name}"
            )
        session.state["rosout_type"] = type_name
        session.publishing.add(topic)
        advertise_ids(session, topic).add(id_)
        return
    if topic in bridge.topics and topic != bridge.command_topic and topic not in TF_TOPICS:
        raise BadFrame(f"advertise: topic {topic} is published by the lab")
    if known is not None and known != type_name:
        raise BadFrame(f"advertise: topic {topic} is of type {known}, not {type_name}")
    if topic in TF_TOPICS:  # shared with the lab: a program's frames join its tree (internal/node_frames.py)
        session.publishing.add(topic)
        advertise_ids(session, topic).add(id_)
        return
    if topic != bridge.command_topic:
        entry = bridge.node_topics.setdefault(topic, NodeTopic(type_name))
        entry.publishers.add(session)
        definition = message.get("definition")  # hri-lab's programs carry their type's full text
        if isinstance(definition, str) and not entry.definition and len(definition) <= MAX_DEFINITION:
            entry.definition = definition
    session.publishing.add(topic)
    advertise_ids(session, topic).add(id_)


async def unadvertise(session: Any, message: dict, id_: Any) -> None:
    topic = name_field(message, "topic")
    if topic not in session.publishing:
        await session.report("warning", f"unadvertise: {topic} is not advertised by this client", id_)
        return
    ids = advertise_ids(session, topic)
    if id_ is None:
        ids.clear()
    elif id_ not in ids:
        await session.report("warning", f"unadvertise: {topic} was not advertised with id {id_!r} by this client", id_)
        return
    ids.discard(id_)
    if ids:  # another of its advertise ops still holds the publisher
        return
    session.publishing.discard(topic)
    session.bridge.leave(topic, publisher=session)


OPS = {"advertise": Op(advertise, mutating=True), "unadvertise": Op(unadvertise)}
