"""This program's publishers and subscriptions by topic, with their QoS and the times the QoS events
of rclpy/event_handler.py are computed from (time.monotonic): a publisher's last message and
last assertion of liveliness, a subscription's last message, when either was destroyed; and the
other programs' publishers and subscriptions on the same topics, as the lab tells them.

The lab is told each topic's publishers and subscriptions, and each service's clients, with their
nodes and QoS (the lab's `endpoints` op), as a DDS participant announces its readers and writers:
`hri-lab topic info -v` shows them and `service info` counts the clients. The lab tells them back as
DDS discovery does (app/rosbridge/capabilities/endpoints.py): the other programs' subscriptions on
the topics this program publishes, their publishers on those it subscribes to, each with its
client's name (`client`: the `callerid` of that program's messages). `told` keeps them (Remote) and
pairs the new ones with this program's endpoints: the incompatible pairs are rclpy's
incompatible-QoS events, a remote publisher counts in a subscription's liveliness (alive while
listed) and the matched counts (`matched`) hold the compatible peers only.

A subscription hears no message of an incompatible publisher (`muted`). The program decides, not the
lab: rmw's rule is rclpy's (rclpy/qos.py), one source, and the lab relays one stream of a topic to a
program however many subscriptions of it the program has. A message is attributed to its program by
its connection header's `callerid` (the lab's relay: rosbridge's publish frame names no publisher);
what the program cannot tell apart is heard: a message of a program whose publishers of the topic
are some compatible and some not (one advertised topic: its messages do not say which publisher
sent them), of a client that told no QoS (rospy, roslibpy, the lab's node), or of two programs
whose first nodes have one name."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

from rosclient import process
from rclpy import _graph
from rclpy.duration import Duration
from rclpy.qos import (
    DurabilityPolicy,
    LivelinessPolicy,
    QoSPolicyKind,
    QoSProfile,
    ReliabilityPolicy,
    incompatible_policies,
)

_lock = threading.Lock()
_publishers: dict[str, list[Endpoint]] = {}  # topic -> this program's publishers of it (the destroyed kept a lease)
_subscriptions: dict[str, list[Endpoint]] = {}
_remote: dict[tuple[bool, str], list[Remote]] = {}  # (publishers?, topic) -> the other programs' there, as told
_clients: dict[tuple[str, str], list[str]] = {}  # (kind, name) -> the nodes of this program's clients of it
generation = [0]  # counts the endpoints made, destroyed and told (a subscription's `muted` is kept until it moves)
Pairs = list[tuple["Endpoint", "Endpoint", QoSPolicyKind]]
# who hears of the pairs the lab's news makes (rclpy/event_handler.py: the incompatible-QoS events)
discovered: list[Callable[[Pairs], None]] = []


class Endpoint:
    """A publisher's or a subscription's part in the events: its QoS and its times."""

    known = True  # its QoS is known (another program's may not be: Remote)

    def __init__(self, topic: str, qos: QoSProfile, publisher: bool, node: str) -> None:
        self.topic, self.qos, self.publisher, self.node = topic, qos, publisher, node
        self.created = time.monotonic()
        self.last_message: float | None = None  # published (a publisher) or received (a subscription)
        self.last_assertion = self.created  # a publisher asserts its liveliness by being made and by each message
        self.revivals = 0  # assertions that came once its lease had passed: alive again after a lapse
        self.destroyed: float | None = None
        self.handlers: list[Any] = []  # its event handlers (rclpy/event_handler.py)
        # the lab's pairs with it that came before its handlers were made (None once they are: `ready`)
        self.early: Pairs | None = []

    def message(self) -> None:
        self.assert_liveliness()
        self.last_message = self.last_assertion

    def assert_liveliness(self) -> None:
        now = time.monotonic()
        if now >= self.alive_until():
            self.revivals += 1  # a subscription sees it not alive, then alive again, however soon it looks
        self.last_assertion = now

    # --- liveliness as a subscription sees this publisher ------------------------------------------
    def lease_s(self) -> float:
        return self.qos.liveliness_lease_duration.nanoseconds / 1e9

    def alive_until(self) -> float:
        """Until when (time.monotonic) this publisher is alive: an AUTOMATIC one while it exists (its
        lease after it was destroyed), a MANUAL_BY_TOPIC one its lease after its last assertion;
        inf for a lease of 0 (infinite) while it exists."""
        lease = self.lease_s()
        manual = self.qos.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC
        if self.destroyed is not None:
            return self.destroyed + (lease if lease > 0 and not manual else 0.0)
        if lease <= 0 or not manual:
            return float("inf")
        return self.last_assertion + lease


class Remote(Endpoint):
    """Another program's publisher or subscription, as the lab told it: alive while it is listed (its
    program's assertions are not relayed: a MANUAL_BY_TOPIC one counts as alive until it goes)."""

    def __init__(self, topic: str, qos: QoSProfile | None, publisher: bool, node: str, client: str,
                 key: tuple) -> None:
        super().__init__(topic, qos or QoSProfile(depth=1), publisher, node)
        self.known = qos is not None  # a QoS the program could read (else: never incompatible)
        self.client, self.key = client, key

    def alive_until(self) -> float:
        return float("inf")


def compatible(publisher: Endpoint, subscription: Endpoint) -> bool:
    return not incompatible(publisher, subscription)


def incompatible(publisher: Endpoint, subscription: Endpoint) -> bool:
    return bool(_policies(publisher, subscription))


def _policies(publisher: Endpoint, subscription: Endpoint) -> list[QoSPolicyKind]:
    if not (publisher.known and subscription.known):
        return []
    return incompatible_policies(publisher.qos, subscription.qos)


def _pair(publisher: Endpoint, subscription: Endpoint, pairs: Pairs) -> None:
    policies = _policies(publisher, subscription)
    if policies:
        pairs.append((publisher, subscription, policies[-1]))


def add(endpoint: Endpoint) -> Pairs:
    """Register a new endpoint; the (publisher, subscription, last incompatible policy) pairs it
    makes with the endpoints of the other kind on its topic: this program's and the others' it knows."""
    table, others = (_publishers, _subscriptions) if endpoint.publisher else (_subscriptions, _publishers)
    pairs: Pairs = []
    _listen()
    with _lock:
        table.setdefault(endpoint.topic, []).append(endpoint)
        generation[0] += 1
        peers = [o for o in others.get(endpoint.topic, []) if o.destroyed is None]
        peers += _remote.get((not endpoint.publisher, endpoint.topic), [])
        for other in peers:
            publisher, subscription = (endpoint, other) if endpoint.publisher else (other, endpoint)
            _pair(publisher, subscription, pairs)
    _tell(endpoint)
    return pairs


def remove(endpoint: Endpoint) -> None:
    """A destroyed endpoint: a publisher stays listed while a subscription may still count it alive;
    the other programs' endpoints of the other kind are forgotten with this program's last one there
    (the lab tells them again with its next)."""
    endpoint.destroyed = time.monotonic()
    with _lock:
        generation[0] += 1
        if not endpoint.publisher:
            _forget(_subscriptions, endpoint)
        if not _live(endpoint.publisher, endpoint.topic):
            _remote.pop((not endpoint.publisher, endpoint.topic), None)
    _tell(endpoint)


def _live(publishers: bool, topic: str) -> list[Endpoint]:
    table = _publishers if publishers else _subscriptions
    return [e for e in table.get(topic, []) if e.destroyed is None]


def _tell(endpoint: Endpoint) -> None:
    """The lab told this program's live endpoints of the endpoint's kind on its topic."""
    with _lock:
        live = _live(endpoint.publisher, endpoint.topic)
    entities = [{"node": e.node, "qos": qos_fields(e.qos)} for e in live]
    kind = "publisher" if endpoint.publisher else "subscription"
    process.connection().send({"op": "endpoints", "kind": kind, "name": endpoint.topic, "entities": entities})


def qos_fields(qos: QoSProfile) -> dict[str, str | int]:
    """A profile as the lab keeps it: the policies' names, the durations in nanoseconds (0: infinite)."""
    liveliness = LivelinessPolicy.AUTOMATIC if qos.liveliness == LivelinessPolicy.SYSTEM_DEFAULT else qos.liveliness
    return {"reliability": qos.reliability.name, "durability": qos.durability.name,
            "lifespan": qos.lifespan.nanoseconds, "deadline": qos.deadline.nanoseconds,
            "liveliness": liveliness.name, "liveliness_lease_duration": qos.liveliness_lease_duration.nanoseconds}


def qos_of(fields: object) -> QoSProfile | None:
    """A profile from what the lab relayed of another program (qos_fields' form); None when it cannot
    be read (a client's own making: its QoS unknown, never incompatible)."""
    if not isinstance(fields, dict):
        return None

    def duration(key: str) -> Duration:
        return Duration(nanoseconds=_nanoseconds(fields.get(key, 0)))

    try:
        return QoSProfile(depth=1, reliability=ReliabilityPolicy[str(fields.get("reliability", "RELIABLE"))],
                          durability=DurabilityPolicy[str(fields.get("durability", "VOLATILE"))],
                          liveliness=LivelinessPolicy[str(fields.get("liveliness", "AUTOMATIC"))],
                          lifespan=duration("lifespan"), deadline=duration("deadline"),
                          liveliness_lease_duration=duration("liveliness_lease_duration"))
    except (KeyError, ValueError, TypeError):
        return None


def _nanoseconds(value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value < 2**63:
        raise ValueError(f"not a duration in nanoseconds: {value!r}")
    return int(value)


# --- the other programs' endpoints, as the lab tells them --------------------------------------------
def _listen() -> None:
    connection = process.connection()
    if getattr(connection, "endpoints_handler", None) is not told:
        connection.endpoints_handler = told


def told(message: dict) -> None:
    """The lab's `endpoints` frame (the connection's reader): the other programs' entities of a kind on
    a topic this program has endpoints of the other kind on. The new ones are paired with this
    program's live endpoints (`discovered` hears the incompatible pairs); the gone ones are forgotten."""
    kind, topic, entities = message.get("kind"), message.get("name"), message.get("entities")
    if kind not in ("publisher", "subscription") or not isinstance(topic, str) or not isinstance(entities, list):
        return
    publishers = kind == "publisher"
    pairs: Pairs = []
    with _lock:
        own = _live(not publishers, topic)
        if not own:  # told before this program's last one there went: nothing to pair with
            return
        unmatched = list(_remote.get((publishers, topic), []))
        kept: list[Remote] = []
        for entity in entities:
            if not isinstance(entity, dict):
                continue
            qos = entity.get("qos")
            key = (str(entity.get("client")), str(entity.get("node")), repr(sorted(qos.items())) if isinstance(qos, dict) else "")
            old = next((r for r in unmatched if r.key == key), None)
            if old is not None:
                unmatched.remove(old)
                kept.append(old)
                continue
            remote = Remote(topic, qos_of(qos), publishers, key[1], key[0], key)
            kept.append(remote)
            for endpoint in own:
                found: Pairs = []
                publisher, subscription = (remote, endpoint) if publishers else (endpoint, remote)
                _pair(publisher, subscription, found)
                if endpoint.early is not None:  # its handlers are not made yet: told when they are
                    endpoint.early += found
                else:
                    pairs += found
        if kept:
            _remote[(publishers, topic)] = kept
        else:
            _remote.pop((publishers, topic), None)
        generation[0] += 1
    _graph.CHANGED.set()  # the matched counts (rclpy/event_handler.py's watcher)
    for hear in discovered:
        hear(pairs)


def ready(endpoint: Endpoint) -> Pairs:
    """The endpoint's handlers are made: the pairs the lab's news made with it before (told now)."""
    with _lock:
        early, endpoint.early = endpoint.early or [], None
    return early


def remotes(publishers: bool, topic: str) -> list[Remote]:
    """The other programs' publishers (or subscriptions) of `topic` this program knows of."""
    with _lock:
        return list(_remote.get((publishers, topic), []))


def muted(subscription: Endpoint) -> set[str]:
    """The programs (`callerid`s: this program's first node for its own) whose messages the
    subscription does not hear: every publisher of its topic in that program is incompatible with it."""
    senders: dict[str, list[Endpoint]] = {}
    own = [p for p in publishers(subscription.topic) if p.destroyed is None]
    if own and process.node_names:
        senders[process.node_names[0]] = list(own)
    for remote in remotes(True, subscription.topic):
        senders.setdefault(remote.client, []).append(remote)
    return {name for name, theirs in senders.items() if all(incompatible(p, subscription) for p in theirs)}


def matched(endpoint: Endpoint) -> int:
    """rmw's matched count of an endpoint: the endpoints of the other kind on its topic it is paired
    with — this program's and the other programs' told ones, each compatible with it — and every other
    client on the topic that told none (rospy, roslibpy, the lab's own node) once (rclpy/_graph.py).
    The topic's listing is read between two looks at the told entities: a program makes its entities
    known before it subscribes and unsubscribes before it unmakes them (rclpy/subscription.py), so one
    the listing names is told in the look after it (arriving) or in the look before it (leaving: its
    untelling may come here before the listing's answer), never a client that told none."""
    topic, mine = endpoint.topic, endpoint.publisher
    with _lock:
        told_before = {r.client for r in _remote.get((not mine, topic), [])}
    clients = _graph.other_clients(topic, publishers=not mine)
    with _lock:
        own = _live(not mine, topic)
        theirs = list(_remote.get((not mine, topic), []))
    ordered = (lambda other: (endpoint, other)) if mine else (lambda other: (other, endpoint))
    count = sum(1 for other in own + theirs if compatible(*ordered(other)))
    told_clients = told_before | {r.client for r in theirs}
    return count + sum(1 for client in clients if client not in told_clients)


# --- service and action clients ----------------------------------------------------------------------
def add_client(name: str, node: str, kind: str = "client") -> None:
    """A service client (`kind` "client") or an action client ("action_client") made: the lab told
    the program's clients of `name` (`service info`, `action info` count them)."""
    with _lock:
        _clients.setdefault((kind, name), []).append(node)
    _tell_clients(kind, name)


def remove_client(name: str, node: str, kind: str = "client") -> None:
    with _lock:
        nodes = _clients.get((kind, name), [])
        if node in nodes:
            nodes.remove(node)
        if not nodes:
            _clients.pop((kind, name), None)
    _tell_clients(kind, name)


def _tell_clients(kind: str, name: str) -> None:
    with _lock:
        entities = [{"node": node, "qos": {}} for node in _clients.get((kind, name), [])]
    process.connection().send({"op": "endpoints", "kind": kind, "name": name, "entities": entities})


def publishers(topic: str) -> list[Endpoint]:
    """The program's publishers of `topic` a subscription may count (the destroyed ones past their
    lease dropped)."""
    now = time.monotonic()
    with _lock:
        for gone in [p for p in _publishers.get(topic, []) if p.destroyed is not None and p.alive_until() <= now]:
            _forget(_publishers, gone)
        return list(_publishers.get(topic, []))


def _forget(table: dict[str, list[Endpoint]], endpoint: Endpoint) -> None:
    listed = table.get(endpoint.topic, [])
    if endpoint in listed:
        listed.remove(endpoint)
    if not listed:
        table.pop(endpoint.topic, None)
