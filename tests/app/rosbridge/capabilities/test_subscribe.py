"""subscribe / unsubscribe (app/rosbridge/capabilities/subscribe.py): one stream per topic and
client, at the lowest throttle and the longest queue of its subscriptions; the stream goes with
the last of them, or with the client."""

from app.rosbridge.capabilities.subscribe import MAX_QUEUE, MAX_TOPICS, Subscribe
from tests.app.rosbridge.clients import connect, op, parts, run, sent, until


def test_a_node_topic_reaches_its_subscriber_through_its_stream():
    async def check() -> None:
        lab = parts(replay=True)
        listener, talker = await connect(lab), await connect(lab)
        await op(listener, op="subscribe", topic="/chatter", type="std_msgs/String")
        await op(talker, op="advertise", topic="/chatter", type="std_msgs/String")
        await op(talker, op="publish", topic="/chatter", msg={"data": "hello"})
        delivered = await until(lambda: sent(listener, "publish"), "the message at its subscriber")
        assert delivered == [{"op": "publish", "topic": "/chatter", "msg": {"data": "hello"}}]

    run(check())


def test_subscriptions_of_one_topic_share_a_stream_at_the_lowest_throttle_and_longest_queue():
    async def check() -> None:
        session = await connect(parts(replay=True))
        await op(session, op="subscribe", id="slow", topic="/chatter", type="std_msgs/String", throttle_rate=500)
        await op(session, op="subscribe", id="fast", topic="/chatter", throttle_rate=100, queue_length=5000)
        stream = session.capability(Subscribe).streams["/chatter"]
        assert stream.options == {"slow": (500, 0), "fast": (100, MAX_QUEUE)}
        assert stream.period == 0.1
        assert stream.queue.maxlen == MAX_QUEUE
        await op(session, op="unsubscribe", id="fast", topic="/chatter")  # the other one holds the stream
        assert stream.period == 0.5
        assert not stream.stopped
        await op(session, op="unsubscribe", id="slow", topic="/chatter")
        assert stream.stopped
        assert "/chatter" not in session.bridge.node_topics

    run(check())


def test_refusals_name_the_field():
    async def check() -> None:
        session = await connect(parts(replay=True))
        assert "topic /nowhere does not exist" in (await op(session, op="subscribe", topic="/nowhere"))[0]["msg"]
        negative = await op(session, op="subscribe", topic="/chatter", type="std_msgs/String", throttle_rate=-1)
        assert "'throttle_rate' and 'queue_length' must be >= 0" in negative[0]["msg"]
        await op(session, op="advertise", topic="/chatter", type="std_msgs/String")
        wrong = await op(session, op="subscribe", topic="/chatter", type="std_msgs/Int32")
        assert "is of type std_msgs/String, not std_msgs/Int32" in wrong[0]["msg"]
        for n in range(MAX_TOPICS):
            await op(session, op="subscribe", topic=f"/t{n}", type="std_msgs/String")
        assert f"at most {MAX_TOPICS} topics" in (await op(session, op="subscribe", topic="/x", type="a/B"))[0]["msg"]

    run(check())


def test_finish_stops_every_stream_and_gives_back_its_share_of_the_rate():
    async def check() -> None:
        lab = parts(replay=True)
        session = await connect(lab)
        await op(session, op="subscribe", topic="/a", type="std_msgs/String")
        await op(session, op="subscribe", topic="/b", type="std_msgs/String")
        streams = list(session.capability(Subscribe).streams.values())
        assert lab.bridge.streams == 2
        session.capability(Subscribe).finish()
        assert all(s.stopped for s in streams)
        assert lab.bridge.streams == 0
        assert all(t.lab for t in lab.bridge.node_topics.values())  # left: the lab's own node's (tf2_web_republisher's)

    run(check())
