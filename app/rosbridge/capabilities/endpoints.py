"""endpoints (the lab's extension): a client tells the graph its entities of one kind on one name,
as a DDS participant announces its readers and writers, e.g.
`{"op": "endpoints", "kind": "publisher", "name": "/chatter", "entities": [{"node": "/talker",
"qos": {"reliability": "RELIABLE", "durability": "VOLATILE", ...}}]}` (an empty list: none left).
`hri-lab run`'s rclpy sends them for its publishers, subscriptions, service and action clients;
rosapi's extension `/rosapi/endpoints` lists them (app/rosbridge/rosapi.py), for `topic info -v`
(each endpoint's node and QoS), `service info` and `action info` (their clients). rosbridge_suite
has no such op: a client that sends none is listed by the topics it advertises and subscribes.

The lab tells them back, as DDS discovery tells a participant the remote readers and writers: a
client that told publishers (subscriptions) on a topic is sent, with the same op, the other
clients' subscriptions (publishers) on it, each entity with its `client` (the name the lab gives
that client: its first node's, the `callerid` of its messages' connection headers), e.g.
`{"op": "endpoints", "kind": "subscription", "name": "/chatter", "entities": [{"node": "/listener",
"qos": {...}, "client": "/listener"}]}` — in answer to each of its own `endpoints` frames of a topic
(when some other client has entities of the opposite kind there), and whenever the others' entities
of that kind there change, a client that leaves included (its entities gone). The program pairs
them with its own (rclpy's incompatible-QoS, liveliness and matched events, rclpy/_endpoints.py);
the lab only relays: it never reads the QoS. Service and action clients are listed, never paired."""

from __future__ import annotations

import math

from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import ENDPOINT_KINDS, MAX_CLIENT_TOPICS, BadFrame, field, name_field

MAX_ENTITIES = 64  # of one kind on one name, per client
MAX_QOS_FIELDS = 16
MAX_TEXT = 256  # characters of a node name or a QoS value
PAIRED = {"publisher": "subscription", "subscription": "publisher"}  # the kind a kind's entities are told of


class Endpoints(Capability):
    """The client's entities: (kind, name) -> [{"node": str, "qos": {str: str | number}}]."""

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.entities: dict[tuple[str, str], list[dict]] = {}

    async def endpoints(self, message: dict, id_: Id) -> None:
        kind = field(message, "kind", str)
        if kind not in ENDPOINT_KINDS:
            raise BadFrame(f"endpoints: field 'kind' must be one of {', '.join(ENDPOINT_KINDS)}, got {kind[:40]!r}")
        name = name_field(message, "name")
        entities = field(message, "entities", list)
        if len(entities) > MAX_ENTITIES:
            raise BadFrame(f"endpoints: at most {MAX_ENTITIES} entities of a kind on a name")
        checked = [_entity(entity) for entity in entities]
        if not checked:
            self.entities.pop((kind, name), None)
        else:
            if (kind, name) not in self.entities and len(self.entities) >= 3 * MAX_CLIENT_TOPICS:
                raise BadFrame(f"endpoints: at most {3 * MAX_CLIENT_TOPICS} names per client")
            self.entities[(kind, name)] = checked
        if kind in PAIRED:
            if checked:
                await self._answer(PAIRED[kind], name)
            self._tell_others(kind, name)

    def of(self, kind: str, name: str) -> list[dict]:
        return self.entities.get((kind, name), [])

    def others(self, kind: str, name: str) -> list[dict]:
        """The other clients' entities of `kind` on `name`, each with its client's name."""
        return [
            {**entity, "client": session.name}
            for session in self.bridge.sessions.all()
            if session is not self.session
            for entity in session.endpoints(kind, name)
        ]

    async def _answer(self, kind: str, name: str) -> None:
        """This client told entities on `name`: the others' of `kind` there (none: nothing sent)."""
        entities = self.others(kind, name)
        if entities:
            await self.session.send({"op": "endpoints", "kind": kind, "name": name, "entities": entities})

    def _tell_others(self, kind: str, name: str) -> None:
        """This client's entities of `kind` on `name` changed: every other client with entities of the
        paired kind there is sent the entities of `kind` it now sees (in a task of its own: a slow
        client holds up nobody)."""
        for session in self.bridge.sessions.all():
            if session is self.session or not session.endpoints(PAIRED[kind], name):
                continue
            told = session.capability(Endpoints).others(kind, name)
            session.spawn(session.send({"op": "endpoints", "kind": kind, "name": name, "entities": told}))

    def finish(self) -> None:
        """The client left (no longer among the sessions): the others are told its entities are gone."""
        held, self.entities = list(self.entities), {}
        for kind, name in held:
            if kind in PAIRED:
                self._tell_others(kind, name)


def _entity(entity: object) -> dict:
    """One entity as told: its node's name and its QoS (names, or numbers of nanoseconds)."""
    if not isinstance(entity, dict):
        raise BadFrame("endpoints: each entity must be an object with 'node' and 'qos'")
    node = entity.get("node")
    qos = entity.get("qos", {})
    if not isinstance(node, str) or not node.startswith("/") or len(node) > MAX_TEXT:
        raise BadFrame("endpoints: an entity's 'node' must be a node's full name, e.g. /talker")
    if not isinstance(qos, dict) or len(qos) > MAX_QOS_FIELDS:
        raise BadFrame(f"endpoints: an entity's 'qos' must be an object of at most {MAX_QOS_FIELDS} fields")
    for key, value in qos.items():
        text_ok = isinstance(value, str) and len(value) <= MAX_TEXT
        number_ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        if len(key) > MAX_TEXT or not (text_ok or number_ok):
            raise BadFrame(f"endpoints: qos field {key[:40]!r} must be a name or a finite number")
    return {"node": node, "qos": dict(qos)}


OPS: Ops = {"endpoints": Op(Endpoints, Endpoints.endpoints)}
