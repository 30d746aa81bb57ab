"""QoS events as rclpy reports them (rosclient/site/rclpy/event_handler.py over rclpy/_endpoints.py),
in this process over the recording connection: incompatible QoS on both sides with rmw's policy kind
(and rclpy's default warning), deadlines missed, liveliness lost and changed. The times are the
profiles' periods, waited for by spinning until the event came (never a guessed sleep)."""

from __future__ import annotations

import time

from rosclient import process
from tests.waiting import wait_for


def spin_until(executor, predicate, timeout: float = 30.0):
    """Spin `executor` one callback at a time until `predicate()` holds (a bound for a hung test)."""

    def step():
        executor.spin_once(timeout_sec=0.1)
        return predicate()

    return wait_for(step, timeout)


def test_an_incompatible_publisher_and_subscription_are_each_told_and_nothing_is_heard(rclpy, capsys):
    """A RELIABLE subscription of a BEST_EFFORT publisher (the incompatible_qos demo's `reliability`):
    rmw's QoSRequestedIncompatibleQoSInfo / QoSOfferedIncompatibleQoSInfo with the last policy kind;
    the subscription hears none of the publisher's messages; without a callback of its own, rclpy's
    default one warns in the entity's logger."""
    from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSPolicyKind, QoSProfile, ReliabilityPolicy, qos_policy_name_from_kind
    from std_msgs.msg import String

    talker = rclpy.create_node("talker", start_parameter_services=False)
    listener = rclpy.create_node("listener", start_parameter_services=False)
    offered: list = []
    requested: list = []
    heard: list = []
    publisher = talker.create_publisher(
        String,
        "chatter",
        QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT),
        event_callbacks=PublisherEventCallbacks(incompatible_qos=offered.append),
    )
    listener.create_subscription(
        String,
        "chatter",
        heard.append,
        QoSProfile(depth=10),
        event_callbacks=SubscriptionEventCallbacks(incompatible_qos=requested.append),
    )
    executor = SingleThreadedExecutor()
    executor.add_node(talker)
    executor.add_node(listener)
    publisher.publish(String(data="lost"))
    rclpy.connection.publish("/chatter", {"data": "lost"}, sender=process.node_names[0])  # as the lab relays it back
    spin_until(executor, lambda: offered and requested)
    assert (offered[0].total_count, offered[0].total_count_change) == (1, 1)
    assert (requested[0].total_count, requested[0].total_count_change) == (1, 1)
    assert qos_policy_name_from_kind(requested[0].last_policy_kind) == "RELIABILITY"
    assert f"{offered[0].last_policy_kind}" == "rmw_qos_policy_kind_t.RMW_QOS_POLICY_RELIABILITY"
    executor.spin_once(timeout_sec=0)
    assert heard == []

    # durability: a TRANSIENT_LOCAL subscription of a VOLATILE publisher, rclpy's default callbacks
    talker.create_publisher(String, "durable", QoSProfile(depth=10))
    listener.create_subscription(
        String, "durable", heard.append, QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    )
    warned: list[str] = []
    spin_until(
        executor,
        lambda: (
            warned.extend(capsys.readouterr().err.splitlines())
            or len([line for line in warned if "incompatible QoS" in line]) == 2
        ),
    )
    assert any(
        line.startswith("[WARN]")
        and line.endswith(
            "[listener]: New publisher discovered on topic 'durable', offering incompatible QoS. No messages will be "
            "received from it. Last incompatible policy: DURABILITY"
        )
        for line in warned
    )
    assert any(
        line.endswith(
            "[talker]: New subscription discovered on topic 'durable', requesting incompatible QoS. No messages will be "
            "sent to it. Last incompatible policy: DURABILITY"
        )
        for line in warned
    )
    assert QoSPolicyKind.DURABILITY.name == "DURABILITY"


def test_compatible_profiles_raise_no_event_and_are_heard(rclpy, capsys):
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSCompatibility, QoSProfile, ReliabilityPolicy, qos_check_compatible
    from std_msgs.msg import String

    node = rclpy.create_node("both", start_parameter_services=False)
    heard: list = []
    node.create_publisher(String, "ok", QoSProfile(depth=10))
    node.create_subscription(
        String, "ok", heard.append, QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
    )
    rclpy.connection.publish("/ok", {"data": "heard"})
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spin_until(executor, lambda: heard)
    assert "incompatible" not in capsys.readouterr().err
    assert qos_check_compatible(QoSProfile(depth=1), QoSProfile(depth=1))[0] == QoSCompatibility.OK
    best_effort = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
    assert qos_check_compatible(best_effort, QoSProfile(depth=1))[0] == QoSCompatibility.ERROR


def test_deadlines_missed_are_counted_on_both_sides_from_the_last_message(rclpy):
    """The deadline demo: a publisher that stops publishing misses its offered deadline, the
    subscription its requested one, one miss a period, with rmw's total count and its change."""
    from rclpy.duration import Duration
    from rclpy.event_handler import (
        PublisherEventCallbacks,
        QoSOfferedDeadlineMissedInfo,
        QoSRequestedDeadlineMissedInfo,
        SubscriptionEventCallbacks,
    )
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile
    from std_msgs.msg import String

    node = rclpy.create_node("deadline", start_parameter_services=False)
    qos = QoSProfile(depth=10, deadline=Duration(seconds=0.05))
    offered: list = []
    requested: list = []
    publisher = node.create_publisher(
        String, "qos_deadline_chatter", qos, event_callbacks=PublisherEventCallbacks(deadline=offered.append)
    )
    node.create_subscription(
        String,
        "qos_deadline_chatter",
        lambda m: None,
        qos,
        event_callbacks=SubscriptionEventCallbacks(deadline=requested.append),
    )
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    executor.spin_once(timeout_sec=0.2)
    assert offered == [] and requested == []  # no deadline before the first message
    publisher.publish(String(data="once"))
    rclpy.connection.publish("/qos_deadline_chatter", {"data": "once"})
    spin_until(executor, lambda: len(offered) >= 2 and len(requested) >= 2)
    assert isinstance(offered[0], QoSOfferedDeadlineMissedInfo)
    assert isinstance(requested[0], QoSRequestedDeadlineMissedInfo)
    for events in (offered, requested):
        assert all(e.total_count_change >= 1 for e in events)
        assert [e.total_count for e in events] == [
            sum(e.total_count_change for e in events[: i + 1]) for i in range(len(events))
        ]


def liveliness_listener(rclpy, changed: list):
    """A node "liveliness" whose subscription to qos_liveliness_chatter asks for a MANUAL_BY_TOPIC
    liveliness with a 50 ms lease, its liveliness changes appended to `changed`: (node, its QoS)."""
    from rclpy.duration import Duration
    from rclpy.event_handler import SubscriptionEventCallbacks
    from rclpy.qos import LivelinessPolicy, QoSProfile
    from std_msgs.msg import String

    node = rclpy.create_node("liveliness", start_parameter_services=False)
    qos = QoSProfile(
        depth=10, liveliness=LivelinessPolicy.MANUAL_BY_TOPIC, liveliness_lease_duration=Duration(seconds=0.05)
    )
    node.create_subscription(
        String,
        "qos_liveliness_chatter",
        lambda m: None,
        qos,
        event_callbacks=SubscriptionEventCallbacks(liveliness=changed.append),
    )
    return node, qos


def test_a_manual_publisher_loses_its_liveliness_and_the_subscription_sees_it_change(rclpy):
    """The liveliness demo with MANUAL_BY_TOPIC: the publisher alive while it asserts itself (a
    message, assert_liveliness), lost once its lease passed (QoSLivelinessLostInfo); the subscription's
    QoSLivelinessChangedInfo counts it alive, then not alive, then alive again."""
    from rclpy.event_handler import PublisherEventCallbacks
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    lost: list = []
    changed: list = []
    node, qos = liveliness_listener(rclpy, changed)
    publisher = node.create_publisher(
        String, "qos_liveliness_chatter", qos, event_callbacks=PublisherEventCallbacks(liveliness=lost.append)
    )
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spin_until(executor, lambda: lost and changed and changed[-1].not_alive_count == 1)
    assert (lost[0].total_count, lost[0].total_count_change) == (1, 1)
    counts = [(e.alive_count, e.not_alive_count, e.alive_count_change, e.not_alive_count_change) for e in changed]
    # alive, then lost; or, on a machine slower than the 50 ms lease, both before the executor
    # looked: the changes summed in one event (rmw's, as the next test makes it)
    assert counts in ([(1, 0, 1, 0), (0, 1, -1, 1)], [(0, 1, 0, 1)])
    seen = len(changed)
    publisher.assert_liveliness()
    spin_until(executor, lambda: len(changed) > seen)
    again = changed[seen]
    assert (again.alive_count, again.not_alive_count, again.alive_count_change, again.not_alive_count_change) in (
        (1, 0, 1, -1),  # alive again
        (0, 1, 0, 0),  # alive and lost again before the executor looked
    )
    spin_until(executor, lambda: len(lost) >= 2)  # the lease passed again: lost once more
    assert lost[1].total_count == 2


def test_an_assertion_whose_lease_passed_before_the_executor_looked_is_still_an_event(rclpy):
    """Alive again and lost again between two spins: DDS told the subscription both changes, and
    rmw_fastrtps sums the changes into the next event (its counts as they are, the changes 0): an
    event all the same, never none."""
    from rclpy.executors import SingleThreadedExecutor
    from std_msgs.msg import String

    changed: list = []
    node, qos = liveliness_listener(rclpy, changed)
    publisher = node.create_publisher(String, "qos_liveliness_chatter", qos)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spin_until(executor, lambda: changed and changed[-1].not_alive_count == 1)  # alive, then lost
    seen = len(changed)
    publisher.assert_liveliness()
    time.sleep(0.1)  # the program does other work for two leases: no spin sees it alive
    spin_until(executor, lambda: len(changed) > seen)
    last = changed[seen]
    assert (last.alive_count, last.not_alive_count, last.alive_count_change, last.not_alive_count_change) == (
        0,
        1,
        0,
        0,
    )


def test_an_automatic_publisher_stays_alive_until_its_lease_after_it_is_destroyed(rclpy):
    """The liveliness demo's AUTOMATIC talker: alive while its node lives (no liveliness lost), and the
    subscription hears it gone a lease after `destroy_node`."""
    from rclpy.duration import Duration
    from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import LivelinessPolicy, QoSProfile
    from std_msgs.msg import String

    qos = QoSProfile(depth=10, liveliness=LivelinessPolicy.AUTOMATIC, liveliness_lease_duration=Duration(seconds=0.05))
    listener = rclpy.create_node("listener", start_parameter_services=False)
    talker = rclpy.create_node("talker", start_parameter_services=False)
    changed: list = []
    lost: list = []
    listener.create_subscription(
        String, "alive", lambda m: None, qos, event_callbacks=SubscriptionEventCallbacks(liveliness=changed.append)
    )
    talker.create_publisher(String, "alive", qos, event_callbacks=PublisherEventCallbacks(liveliness=lost.append))
    executor = SingleThreadedExecutor()
    executor.add_node(listener)
    executor.add_node(talker)
    spin_until(executor, lambda: changed)
    start = time.monotonic()
    spin_until(executor, lambda: time.monotonic() > start + 0.1)  # two leases: an AUTOMATIC one is not lost
    assert lost == [] and len(changed) == 1
    executor.remove_node(talker)
    talker.destroy_node()
    spin_until(executor, lambda: len(changed) >= 2)
    assert (changed[1].alive_count, changed[1].not_alive_count, changed[1].alive_count_change) == (0, 0, -1)


def test_a_transient_local_publishers_lifespan_goes_to_the_lab_with_its_history(rclpy):
    """The lifespan demo's publisher: the lab keeps its last `depth` messages for a late subscription
    (advertise's latch and queue_size) and drops those older than its lifespan (the lab's `lifespan`)."""
    from rclpy.duration import Duration
    from rclpy.qos import DurabilityPolicy, QoSProfile
    from std_msgs.msg import String

    node = rclpy.create_node("talker", start_parameter_services=False)
    qos = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL, lifespan=Duration(seconds=1.5))
    node.create_publisher(String, "qos_lifespan_chatter", qos)
    node.create_publisher(String, "forever", QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    advertised = {m["topic"]: m for m in rclpy.connection.sent if m["op"] == "advertise"}
    kept = advertised["/qos_lifespan_chatter"]
    assert (kept["latch"], kept["queue_size"], kept["lifespan"]) == (True, 10, 1.5)
    assert "lifespan" not in advertised["/forever"]


def test_the_program_tells_the_lab_its_endpoints_with_their_nodes_and_qos(rclpy):
    """What `topic info -v`, `service info` and `action info` show of an rclpy program (the lab's
    `endpoints` op): each publisher and subscription with its node and QoS, each service and action
    client; none left once destroyed."""
    from example_interfaces.action import Fibonacci
    from example_interfaces.srv import AddTwoInts
    from rclpy.action import ActionClient
    from rclpy.duration import Duration
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    node = rclpy.create_node("talker", namespace="demo", start_parameter_services=False)
    qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT, deadline=Duration(seconds=0.5))
    publisher = node.create_publisher(String, "chatter", qos)
    client = node.create_client(AddTwoInts, "/add_two_ints")
    action_client = ActionClient(node, Fibonacci, "fibonacci")

    def told(kind: str, name: str) -> list:
        frames = [m for m in rclpy.connection.sent if m["op"] == "endpoints" and (m["kind"], m["name"]) == (kind, name)]
        return frames[-1]["entities"]

    assert told("publisher", "/demo/chatter") == [
        {
            "node": "/demo/talker",
            "qos": {
                "reliability": "BEST_EFFORT",
                "durability": "VOLATILE",
                "lifespan": 0,
                "deadline": 500_000_000,
                "liveliness": "AUTOMATIC",
                "liveliness_lease_duration": 0,
            },
        }
    ]
    assert told("client", "/add_two_ints") == [{"node": "/demo/talker", "qos": {}}]
    assert told("action_client", "/demo/fibonacci") == [{"node": "/demo/talker", "qos": {}}]
    action_client.destroy()
    assert told("action_client", "/demo/fibonacci") == []
    subscription = node.create_subscription(String, "chatter", lambda msg: None, qos)
    node.destroy_publisher(publisher)
    node.destroy_subscription(subscription)
    node.destroy_client(client)
    assert told("publisher", "/demo/chatter") == [] and told("client", "/add_two_ints") == []
    # gone in the reverse order of their making: the lab's topic first, then the endpoint told of it, so
    # no other program sees this one on the topic with its QoS untold (which counts as matched)
    gone = [(m["op"], m.get("kind")) for m in rclpy.connection.sent if m.get("topic", m.get("name")) == "/demo/chatter"]
    assert gone[-4:] == [
        ("unadvertise", None),
        ("endpoints", "publisher"),
        ("unsubscribe", None),
        ("endpoints", "subscription"),
    ]


def test_other_programs_endpoints_the_lab_tells_are_paired_heard_and_counted(rclpy, capsys):
    """DDS discovery over the lab (rclpy/_endpoints.py `told`): the other programs' publishers and
    subscriptions on this program's topics, as the lab's `endpoints` frames tell them. An incompatible
    one is an event on this program's side (once per peer: told again, nothing new), rclpy's default
    warning without a callback; its program's messages are not heard while a compatible program's
    are; a compatible publisher counts in the subscription's liveliness while it is listed."""
    from rclpy.event_handler import SubscriptionEventCallbacks
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile
    from std_msgs.msg import String

    node = rclpy.create_node("listener", start_parameter_services=False)
    requested: list = []
    changed: list = []
    heard: list = []
    node.create_subscription(
        String,
        "chatter",
        lambda m: heard.append(m.data),
        QoSProfile(depth=10),
        event_callbacks=SubscriptionEventCallbacks(incompatible_qos=requested.append, liveliness=changed.append),
    )
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    lab = rclpy.connection.endpoints_handler  # the program listens once it has an endpoint
    best_effort = {
        "reliability": "BEST_EFFORT",
        "durability": "VOLATILE",
        "deadline": 0,
        "liveliness": "AUTOMATIC",
        "liveliness_lease_duration": 0,
        "lifespan": 0,
    }
    reliable = {**best_effort, "reliability": "RELIABLE"}
    fast = {"node": "/fast_talker", "qos": best_effort, "client": "/fast_talker"}
    good = {"node": "/good_talker", "qos": reliable, "client": "/good_talker"}
    lab({"op": "endpoints", "kind": "publisher", "name": "/chatter", "entities": [fast, good]})
    spin_until(executor, lambda: requested and changed)
    assert (requested[0].total_count, requested[0].total_count_change) == (1, 1)
    assert f"{requested[0].last_policy_kind}" == "rmw_qos_policy_kind_t.RMW_QOS_POLICY_RELIABILITY"
    assert (changed[0].alive_count, changed[0].alive_count_change) == (1, 1)  # the compatible one only
    rclpy.connection.publish("/chatter", {"data": "best effort"}, sender="/fast_talker")
    rclpy.connection.publish("/chatter", {"data": "reliable"}, sender="/good_talker")
    rclpy.connection.publish("/chatter", {"data": "unknown"})  # a client that tells no QoS (the lab's node)
    spin_until(executor, lambda: len(heard) == 2)
    lab({"op": "endpoints", "kind": "publisher", "name": "/chatter", "entities": [good, fast]})  # nothing new
    lab({"op": "endpoints", "kind": "publisher", "name": "/chatter", "entities": [fast]})  # the good one left
    spin_until(executor, lambda: len(changed) >= 2)
    assert (changed[1].alive_count, changed[1].not_alive_count, changed[1].alive_count_change) == (0, 0, -1)
    assert len(requested) == 1 and heard == ["reliable", "unknown"]

    # a publisher without callbacks: rclpy's default warning for a transient-local subscription elsewhere;
    # a QoS the program cannot read, or an entity of no QoS, is never incompatible
    node.create_publisher(String, "durable", QoSProfile(depth=10))
    durable = {**reliable, "durability": "TRANSIENT_LOCAL"}
    lab(
        {
            "op": "endpoints",
            "kind": "subscription",
            "name": "/durable",
            "entities": [
                {"node": "/late", "qos": durable, "client": "/late"},
                {"node": "/odd", "qos": {"reliability": "SOMETIMES"}, "client": "/odd"},
                {"node": "/rospy", "client": "/x"},
            ],
        }
    )
    warned: list[str] = []
    spin_until(
        executor,
        lambda: (
            warned.extend(capsys.readouterr().err.splitlines()) or any("incompatible QoS" in line for line in warned)
        ),
    )
    assert [line.split("]: ", 1)[1] for line in warned if "incompatible QoS" in line] == [
        "New subscription discovered on topic 'durable', requesting incompatible QoS. No messages will be sent to "
        "it. Last incompatible policy: DURABILITY"
    ]


def test_a_program_on_its_way_out_is_never_counted_matched(rclpy, monkeypatch):
    """A leaving program unsubscribes, then untells its entities: a listing of the topic's subscribers
    the lab answered before the first, read here after the second was told, still names it. It was
    told (and incompatible): not a client that told none, so the matched count never rises on its way
    out (a best-effort talker printed `matched current=1`, then 0, as a reliable listener ended). A
    client listed that never told, rospy's, counts once."""
    from rclpy import _endpoints, _graph
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    node = rclpy.create_node("fast_talker", start_parameter_services=False)
    publisher = node.create_publisher(
        String, "chatter", QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
    )
    lab = rclpy.connection.endpoints_handler
    reliable = {
        "reliability": "RELIABLE",
        "durability": "VOLATILE",
        "deadline": 0,
        "liveliness": "AUTOMATIC",
        "liveliness_lease_duration": 0,
        "lifespan": 0,
    }
    lab(
        {
            "op": "endpoints",
            "kind": "subscription",
            "name": "/chatter",
            "entities": [{"node": "/listener", "qos": reliable, "client": "/listener"}],
        }
    )

    def listed_before_it_left(topic, publishers):
        lab({"op": "endpoints", "kind": "subscription", "name": "/chatter", "entities": []})  # told meanwhile
        return ["/listener"]

    monkeypatch.setattr(_graph, "other_clients", listed_before_it_left)
    assert _endpoints.matched(publisher._endpoint) == 0
    monkeypatch.setattr(_graph, "other_clients", lambda topic, publishers: ["/rospy_listener"])
    assert _endpoints.matched(publisher._endpoint) == 1
