"""How many publishers and subscriptions a topic has in the graph, as rclpy's counts give them
(`Node.count_publishers`, `count_subscribers`, `Publisher.get_subscription_count`,
`Subscription.get_publisher_count`, the matched events of rclpy/event_handler.py).

Over rosbridge the lab knows clients, not their entities: the count is this program's own entities on
the topic (every node's, each one) and, from the lab's rosapi, every other client on it, each
counted once however many it holds — the lab's own node as one when it publishes the topic."""

from __future__ import annotations

import threading

from rosclient import process

_lock = threading.Lock()
_subscriptions: dict[str, int] = {}  # topic -> this program's subscriptions of it
CHANGED = threading.Event()  # set when this program made or destroyed a publisher or a subscription


def add_subscription(topic: str) -> None:
    with _lock:
        _subscriptions[topic] = _subscriptions.get(topic, 0) + 1
    CHANGED.set()


def remove_subscription(topic: str) -> None:
    with _lock:
        left = _subscriptions.get(topic, 0) - 1
        if left > 0:
            _subscriptions[topic] = left
        else:
            _subscriptions.pop(topic, None)
    CHANGED.set()


def add_publisher(topic: str, type_name: str, msg_class: object) -> None:
    process.add_publisher(topic, type_name, msg_class)
    CHANGED.set()


def remove_publisher(topic: str) -> None:
    process.remove_publisher(topic)
    CHANGED.set()


def _others(service: str, field: str, topic: str) -> int:
    """The clients other than this program that rosapi lists on `topic`."""
    names = process.connection().call_service(service, {"topic": topic}, timeout=10).get(field, [])
    own = set(process.node_names[:1])  # rosapi names a client by its first node
    return sum(1 for name in names if name not in own)


def count_subscriptions(topic: str) -> int:
    with _lock:
        own = _subscriptions.get(topic, 0)
    return own + _others("/rosapi/subscribers", "subscribers", topic)


def count_publishers(topic: str) -> int:
    return process.publishers_of(topic) + _others("/rosapi/publishers", "publishers", topic)
