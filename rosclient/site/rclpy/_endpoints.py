"""This program's publishers and subscriptions by topic, with their QoS and the times the QoS events
of rclpy/event_handler.py are computed from (time.monotonic): a publisher's last message and
last assertion of liveliness, a subscription's last message, when either was destroyed.

Over rosbridge the lab does not tell a program the QoS of other programs' endpoints: the events
that compare a subscription with its publishers (incompatible QoS, liveliness changed) see this
program's own, as the QoS demos of ROS 2 (quality_of_service_demo_py) hold both in one process.

The lab is told each topic's publishers and subscriptions, and each service's clients, with their
nodes and QoS (the lab's `endpoints` op), as a DDS participant announces its readers and writers:
`hri-lab topic info -v` shows them and `service info` counts the clients."""

from __future__ import annotations

import threading
import time
from typing import Any

from rosclient import process
from rclpy.qos import LivelinessPolicy, QoSPolicyKind, QoSProfile, incompatible_policies

_lock = threading.Lock()
_publishers: dict[str, list[Endpoint]] = {}  # topic -> this program's publishers of it (the destroyed kept a lease)
_subscriptions: dict[str, list[Endpoint]] = {}
_clients: dict[str, list[str]] = {}  # service -> the nodes of this program's clients of it
generation = [0]  # counts the program's endpoints made and destroyed (a subscription's `deaf` is kept until it moves)


class Endpoint:
    """A publisher's or a subscription's part in the events: its QoS and its times."""

    def __init__(self, topic: str, qos: QoSProfile, publisher: bool, node: str) -> None:
        self.topic, self.qos, self.publisher, self.node = topic, qos, publisher, node
        self.created = time.monotonic()
        self.last_message: float | None = None  # published (a publisher) or received (a subscription)
        self.last_assertion = self.created  # a publisher asserts its liveliness by being made and by each message
        self.destroyed: float | None = None
        self.handlers: list[Any] = []  # its event handlers (rclpy/event_handler.py)

    def message(self) -> None:
        self.last_message = self.last_assertion = time.monotonic()

    def assert_liveliness(self) -> None:
        self.last_assertion = time.monotonic()

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


def add(endpoint: Endpoint) -> list[tuple[Endpoint, Endpoint, QoSPolicyKind]]:
    """Register a new endpoint; the (publisher, subscription, last incompatible policy) pairs it
    makes with the program's endpoints of the other kind on its topic."""
    table, others = (_publishers, _subscriptions) if endpoint.publisher else (_subscriptions, _publishers)
    pairs = []
    with _lock:
        table.setdefault(endpoint.topic, []).append(endpoint)
        generation[0] += 1
        for other in others.get(endpoint.topic, []):
            if other.destroyed is not None:
                continue
            publisher, subscription = (endpoint, other) if endpoint.publisher else (other, endpoint)
            policies = incompatible_policies(publisher.qos, subscription.qos)
            if policies:
                pairs.append((publisher, subscription, policies[-1]))
    _tell(endpoint)
    return pairs


def remove(endpoint: Endpoint) -> None:
    """A destroyed endpoint: a publisher stays listed while a subscription may still count it alive."""
    endpoint.destroyed = time.monotonic()
    generation[0] += 1
    if not endpoint.publisher:
        with _lock:
            _forget(_subscriptions, endpoint)
    _tell(endpoint)


def _tell(endpoint: Endpoint) -> None:
    """The lab told this program's live endpoints of the endpoint's kind on its topic."""
    table = _publishers if endpoint.publisher else _subscriptions
    with _lock:
        live = [e for e in table.get(endpoint.topic, []) if e.destroyed is None]
    entities = [{"node": e.node, "qos": qos_fields(e.qos)} for e in live]
    kind = "publisher" if endpoint.publisher else "subscription"
    process.connection().send({"op": "endpoints", "kind": kind, "name": endpoint.topic, "entities": entities})


def qos_fields(qos: QoSProfile) -> dict[str, str | int]:
    """A profile as the lab keeps it: the policies' names, the durations in nanoseconds (0: infinite)."""
    liveliness = LivelinessPolicy.AUTOMATIC if qos.liveliness == LivelinessPolicy.SYSTEM_DEFAULT else qos.liveliness
    return {"reliability": qos.reliability.name, "durability": qos.durability.name,
            "lifespan": qos.lifespan.nanoseconds, "deadline": qos.deadline.nanoseconds,
            "liveliness": liveliness.name, "liveliness_lease_duration": qos.liveliness_lease_duration.nanoseconds}


def add_client(service: str, node: str) -> None:
    """A service client made: the lab told the program's clients of `service`."""
    with _lock:
        _clients.setdefault(service, []).append(node)
    _tell_clients(service)


def remove_client(service: str, node: str) -> None:
    with _lock:
        nodes = _clients.get(service, [])
        if node in nodes:
            nodes.remove(node)
        if not nodes:
            _clients.pop(service, None)
    _tell_clients(service)


def _tell_clients(service: str) -> None:
    with _lock:
        entities = [{"node": node, "qos": {}} for node in _clients.get(service, [])]
    process.connection().send({"op": "endpoints", "kind": "client", "name": service, "entities": entities})


def publishers(topic: str) -> list[Endpoint]:
    """The program's publishers of `topic` a subscription may count (the destroyed ones past their
    lease dropped)."""
    now = time.monotonic()
    with _lock:
        for gone in [p for p in _publishers.get(topic, []) if p.destroyed is not None and p.alive_until() <= now]:
            _forget(_publishers, gone)
        return list(_publishers.get(topic, []))


def incompatible(publisher: Endpoint, subscription: Endpoint) -> bool:
    return bool(incompatible_policies(publisher.qos, subscription.qos))


def deaf(subscription: Endpoint) -> bool:
    """Whether the subscription hears none of this program's publishers of its topic (each one
    incompatible with it)."""
    own = [p for p in publishers(subscription.topic) if p.destroyed is None]
    return bool(own) and all(incompatible(p, subscription) for p in own)


def _forget(table: dict[str, list[Endpoint]], endpoint: Endpoint) -> None:
    listed = table.get(endpoint.topic, [])
    if endpoint in listed:
        listed.remove(endpoint)
    if not listed:
        table.pop(endpoint.topic, None)
