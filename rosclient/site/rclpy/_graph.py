"""How many publishers and subscriptions a topic has in the graph, as rclpy's counts give them
(`Node.count_publishers`, `count_subscribers`), and the other clients on a topic (the matched counts
of rclpy/_endpoints.py: `Publisher.get_subscription_count`, `Subscription.get_publisher_count`, the
matched events).

rosapi lists clients, not their entities: the count is this program's own entities on the topic
(every node's, each one) and every other client on it, each counted once however many it holds —
the lab's own node as one when it publishes the topic."""

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


def add_publisher(topic: str, type_name: str, msg_class: object, latch: int = 0, lifespan_s: float = 0.0) -> None:
    process.add_publisher(topic, type_name, msg_class, latch=latch, lifespan_s=lifespan_s)
    CHANGED.set()


def remove_publisher(topic: str) -> None:
    process.remove_publisher(topic)
    CHANGED.set()


def other_clients(topic: str, publishers: bool) -> list[str]:
    """The clients other than this program that rosapi lists publishing (or subscribing to) `topic`,
    by the names the lab gives them (their first node's)."""
    service, field = ("/rosapi/publishers", "publishers") if publishers else ("/rosapi/subscribers", "subscribers")
    names = process.connection().call_service(service, {"topic": topic}, timeout=10).get(field, [])
    own = set(process.node_names[:1])  # rosapi names a client by its first node
    return [name for name in names if name not in own]


def count_subscriptions(topic: str) -> int:
    with _lock:
        own = _subscriptions.get(topic, 0)
    return own + len(other_clients(topic, publishers=False))


def count_publishers(topic: str) -> int:
    return process.publishers_of(topic) + len(other_clients(topic, publishers=True))


# --- the graph's names (Node.get_topic_names_and_types and its kin), from the lab's rosapi -------------
def ros2_type(type_name: str, kind: str) -> str:
    """`pkg/Name` as ROS 2 names it: `pkg/msg/Name` (or srv, action); a ROS 2 name stays."""
    parts = type_name.split("/")
    return f"{parts[0]}/{kind}/{parts[1]}" if len(parts) == 2 else type_name


def topic_names_and_types() -> list[tuple[str, list[str]]]:
    answer = process.connection().call_service("/rosapi/topics", {}, timeout=10)
    pairs = zip(answer.get("topics", []), answer.get("types", []), strict=False)
    return sorted((name, [ros2_type(kind, "msg")]) for name, kind in pairs)


def service_names_and_types() -> list[tuple[str, list[str]]]:
    out = []
    for name in sorted(process.service_names()):
        kind = process.connection().call_service("/rosapi/service_type", {"service": name}, timeout=10).get("type", "")
        out.append((name, [ros2_type(kind, "srv")] if kind else []))
    return out


def node_names() -> list[str]:
    names = process.connection().call_service("/rosapi/nodes", {}, timeout=10).get("nodes", [])
    return sorted("/" + n.strip("/") for n in names)


def split_node(name: str) -> tuple[str, str]:
    namespace, _, base = name.rpartition("/")
    return base, namespace or "/"


def by_node(node_name: str, node_namespace: str, field: str) -> list[tuple[str, list[str]]]:
    full = "/" + "/".join(p for p in (node_namespace.strip("/"), node_name.strip("/")) if p)
    details = process.connection().call_service("/rosapi/node_details", {"node": full}, timeout=10)
    names = sorted(details.get(field, []))
    if field == "services":
        return [(n, t) for n, t in service_names_and_types() if n in names]
    types = dict(topic_names_and_types())
    return [(n, types.get(n, [])) for n in names]
