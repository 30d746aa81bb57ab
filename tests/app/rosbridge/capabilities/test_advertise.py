"""advertise / unadvertise (app/rosbridge/capabilities/advertise.py): a client's publisher of a topic
lasts while one of the advertise ids that made it is not withdrawn, as rosbridge_suite counts them."""

import pytest
from fastapi.testclient import TestClient

from app.rosbridge.capabilities.advertise import Advertise
from app.serving.compose import create_app
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until
from tests.waiting import within


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app()) as c:
        yield c


def answered(ws, call_id: str) -> list[dict]:
    """What came before the answer of a call made now (a connection's ops are handled in order)."""
    ws.send_json({"op": "call_service", "id": call_id, "service": "/rosapi/get_time", "args": {}})
    before = []
    while (message := within(ws.receive_json, 30, f"the answer to {call_id}"))["op"] != "service_response":
        before.append(message)
    return before


def test_the_publisher_ends_with_its_last_advertise_id(client):
    with client.websocket_connect("/") as listener, client.websocket_connect("/") as talker:
        listener.send_json({"op": "subscribe", "topic": "/two_ids", "type": "std_msgs/String"})
        answered(listener, "subscribed")
        for advertise_id in ("first", "second"):
            talker.send_json({"op": "advertise", "id": advertise_id, "topic": "/two_ids", "type": "std_msgs/String"})
        talker.send_json({"op": "unadvertise", "id": "first", "topic": "/two_ids"})
        talker.send_json({"op": "publish", "topic": "/two_ids", "msg": {"data": "still published"}})
        assert answered(talker, "after first") == []  # no refusal: "second" holds the publisher
        message = within(listener.receive_json, 30, "the message published after the first unadvertise")
        assert message["msg"] == {"data": "still published"}
        talker.send_json({"op": "unadvertise", "id": "second", "topic": "/two_ids"})
        talker.send_json({"op": "publish", "id": "late", "topic": "/two_ids", "msg": {"data": "refused"}})
        refused = answered(talker, "after second")
        assert [m["msg"] for m in refused] == ["publish: advertise /two_ids first (op advertise with its type)"]


def test_an_unadvertise_without_an_id_withdraws_them_all(client):
    with client.websocket_connect("/") as talker:
        for advertise_id in ("a", "b"):
            talker.send_json({"op": "advertise", "id": advertise_id, "topic": "/all_ids", "type": "std_msgs/String"})
        talker.send_json({"op": "unadvertise", "topic": "/all_ids"})
        talker.send_json({"op": "publish", "topic": "/all_ids", "msg": {"data": "refused"}})
        assert [m["msg"] for m in answered(talker, "after")] == [
            "publish: advertise /all_ids first (op advertise with its type)"
        ]


def test_the_lab_s_topics_and_a_wrong_type_are_refused_and_finish_leaves_the_topics():
    async def check() -> None:
        lab = parts()
        session = await connect(lab)
        lab_topic = await op(session, op="advertise", topic="/joint_states", type="sensor_msgs/JointState")
        assert lab_topic[0]["msg"] == "advertise: topic /joint_states is published by the lab"
        wrong = await op(session, op="advertise", topic="/rosout", type="std_msgs/String")
        assert "topic /rosout is of type rcl_interfaces/Log" in wrong[0]["msg"]
        await op(session, op="advertise", topic="/chatter", type="std_msgs/msg/String")  # ROS 2's spelling
        assert lab.bridge.topics.find("/chatter").type == "std_msgs/String"
        assert await op(session, op="advertise", topic="/tf", type="tf2_msgs/TFMessage") == []  # shared with the lab
        assert session.capability(Advertise).publishing == {"/chatter", "/tf"}
        session.capability(Advertise).finish()
        assert lab.bridge.topics.find("/chatter") is None
        assert session.capability(Advertise).names() == []

    run(check())


def test_a_subscriber_that_asks_gets_each_message_with_its_publishers_connection_header():
    async def check() -> None:
        lab = parts(replay=True)
        talker, asking, plain = await connect(lab), await connect(lab), await connect(lab)
        await op(talker, op="node", name="/talker")
        for session, asks in ((asking, True), (plain, False)):
            frame = {"op": "subscribe", "topic": "/chatter", "type": "std_msgs/String", "connection_header": asks}
            assert await op(session, **frame) == []
        advertise = {"op": "advertise", "topic": "/chatter", "type": "std_msgs/String", "headers": {"cookies": "oreo"}}
        assert await op(talker, **advertise) == []
        await op(talker, op="publish", topic="/chatter", msg={"data": "hello"})
        heard = (await until(lambda: sent(asking, "publish"), "the message at the asking subscriber"))[0]
        assert heard["msg"] == {"data": "hello"}
        assert heard["connection_header"] == {"callerid": "/talker", "cookies": "oreo"}
        other = (await until(lambda: sent(plain, "publish"), "the message at the other subscriber"))[0]
        assert other == {"op": "publish", "topic": "/chatter", "msg": {"data": "hello"}}  # rosbridge's frame
        # a later advertise's headers replace the earlier ones
        await op(talker, op="advertise", topic="/chatter", type="std_msgs/String", headers={"callerid": "/own"})
        await op(talker, op="publish", topic="/chatter", msg={"data": "again"})
        again = (await until(lambda: sent(asking, "publish")[1:], "the second message"))[0]
        assert again["connection_header"] == {"callerid": "/own"}  # a publisher's own field replaces it, as in rospy

    run(check())


@pytest.mark.parametrize(
    ("headers", "reason"),
    [
        ("oreo", "field 'headers' must be an object"),
        ({f"k{i}": "v" for i in range(33)}, "field 'headers' holds at most 32 fields, got 33"),
        ({"": "v"}, "field 'headers': a name of 1 to 64 characters without '='"),
        ({"k" * 65: "v"}, "field 'headers': a name of 1 to 64 characters without '='"),
        ({"a=b": "v"}, "field 'headers': a name of 1 to 64 characters without '='"),
        ({"cookies": 3}, "field 'headers.cookies' must be a string of at most 1024 characters, got 3"),
        ({"cookies": "x" * 1025}, "field 'headers.cookies' must be a string of at most 1024 characters"),
    ],
)
def test_headers_out_of_bounds_are_refused_naming_the_field(headers, reason):
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        for frame in (
            {"op": "advertise", "topic": "/bounded", "type": "std_msgs/String", "headers": headers},
            {"op": "call_service", "service": "/rosapi/get_time", "headers": headers},
        ):
            refused = await op(session, **frame)
            assert [m["op"] for m in refused] == ["status"], frame["op"]
            assert refused[0]["level"] == "error"
            assert refused[0]["msg"].startswith(f"{frame['op']}: {reason}")
            assert len(refused[0]["msg"]) < 300  # what the client sent is cut, never echoed whole
        assert "/bounded" not in session.capability(Advertise).ids

    run(check())


def test_a_latched_publishers_last_messages_reach_a_late_subscription_as_deep_as_it_asked():
    """rosbridge's `latch` and `queue_size`: a TRANSIENT_LOCAL publisher of depth 10 (rclpy's), its
    10 messages kept for a subscription made after them, addressed to its id; a volatile one
    (the lab's extension) gets none; a publisher that is gone leaves nothing behind."""

    async def check() -> None:
        lab = parts(replay=True)
        talker, plain, late, volatile, again = [await connect(lab) for _ in range(5)]
        await op(talker, op="advertise", topic="/plain", type="std_msgs/String")  # not latched
        assert await op(talker, op="advertise", topic="/kept", type="std_msgs/String", latch=True, queue_size=10) == []
        for i in range(12):
            for topic in ("/plain", "/kept"):
                await op(talker, op="publish", topic=topic, msg={"data": str(i)})
        await op(plain, op="subscribe", id="p", topic="/plain", type="std_msgs/String")
        await op(late, op="subscribe", id="late:1", topic="/kept", type="std_msgs/String")
        await op(volatile, op="subscribe", id="v", topic="/kept", type="std_msgs/String", durability="volatile")
        heard = await until(lambda: sent(late, "publish")[9:] and sent(late, "publish"), "the kept messages")
        assert [m["msg"]["data"] for m in heard] == [str(i) for i in range(2, 12)]  # the last 10, oldest first
        assert {m["id"] for m in heard} == {"late:1"}
        await op(talker, op="publish", topic="/kept", msg={"data": "live"})  # marks the end of what each got
        for session in (late, volatile):
            await until(lambda s=session: any(m["msg"]["data"] == "live" for m in sent(s, "publish")), "the live one")
        assert [m["msg"]["data"] for m in sent(volatile, "publish")] == ["live"]
        assert sent(plain, "publish") == []  # a volatile publisher keeps nothing
        bad = await op(talker, op="advertise", topic="/x", type="std_msgs/String", latch=True, queue_size=-1)
        assert bad[0]["msg"] == "advertise: 'queue_size' must be >= 0"
        await op(talker, op="unadvertise", topic="/kept")
        await op(again, op="subscribe", id="a", topic="/kept", type="std_msgs/String")
        assert sent(again, "publish") == []

    run(check())


def test_a_kept_message_older_than_its_lifespan_does_not_reach_a_late_subscription():
    """The lab's `lifespan` (rclpy's QoS lifespan, the lifespan demo): a TRANSIENT_LOCAL publisher's
    kept messages reach a late subscription while they live; past their lifespan, none does. A
    lifespan that is not a positive number is refused by name."""
    import time

    async def check() -> None:
        lab = parts(replay=True)
        talker, late = [await connect(lab) for _ in range(2)]
        for topic, lifespan in (("/short", 0.05), ("/long", 3600)):
            advertise = {"op": "advertise", "topic": topic, "type": "std_msgs/String", "latch": True, "queue_size": 10}
            assert await op(talker, **advertise, lifespan=lifespan) == []
        for i in range(3):
            for topic in ("/short", "/long"):
                await op(talker, op="publish", topic=topic, msg={"data": str(i)})
        published = time.monotonic()
        await until(lambda: time.monotonic() > published + 0.05 and [True], "the short lifespan to pass")
        await op(late, op="subscribe", id="s", topic="/short", type="std_msgs/String")
        await op(late, op="subscribe", id="l", topic="/long", type="std_msgs/String")
        await op(talker, op="publish", topic="/short", msg={"data": "live"})  # marks the end of what it got
        await until(lambda: any(m["msg"]["data"] == "live" for m in sent(late, "publish")), "the live one")
        heard = await until(lambda: sent(late, "publish")[3:] and sent(late, "publish"), "the long-lived ones")
        assert sorted((m["topic"], m["msg"]["data"]) for m in heard) == [
            ("/long", "0"),
            ("/long", "1"),
            ("/long", "2"),
            ("/short", "live"),
        ]
        bad = await op(talker, op="advertise", topic="/x", type="std_msgs/String", latch=True, lifespan=-1)
        assert bad[0]["msg"] == "advertise: 'lifespan' must be a number of seconds > 0"

    run(check())
