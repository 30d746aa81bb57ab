"""subscribe / unsubscribe (app/rosbridge/capabilities/subscribe.py): one stream per topic and
client, at the lowest throttle and the longest queue of its subscriptions; the stream goes with
the last of them, or with the client."""

import asyncio
from contextlib import contextmanager

import numpy as np

from sim.messages import F_EXT

from app.rosbridge.capabilities.subscribe import HANDOFF_TURNS, MAX_QUEUE, MAX_TOPICS, Subscribe, sample_every_step
from app.rosbridge.internal.streams import Stream
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
        assert session.bridge.topics.find("/chatter") is None

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
        assert lab.bridge.topics.streams == 2
        session.capability(Subscribe).finish()
        assert all(s.stopped for s in streams)
        assert lab.bridge.topics.streams == 0
        assert all(
            lab.bridge.topics.find(n).lab for n in lab.bridge.topics.node_topic_names()
        )  # left: the lab's own node's (tf2_web_republisher's)

    run(check())


class _Ring:
    """A lab whose F_ext ring gives one look's rows at a time (app/runtime/sample_ring.py's shape)."""

    def __init__(self, looks: list[int]) -> None:
        self.looks, self.step, self.opened = list(looks), 0, False
        self.needed: list[tuple[float, bool]] = []  # (period s, of snapshots) asked of the loop

    def wrench_samples(self, seen: int):
        if not self.opened:  # the subscription's first look: from now on
            self.opened = True
            return [], 0, 0
        if not self.looks:
            return [], seen, 0
        rows = [np.array([(self.step + k + 1) * 0.001, 0, 0, 5.0, 0, 0, 0]) for k in range(self.looks.pop(0))]
        self.step += len(rows)
        return rows, seen + len(rows), 0

    @contextmanager
    def needs(self, period: float, snapshots: bool = True):
        self.needed.append((period, snapshots))
        yield

    @contextmanager
    def new_wrench_samples(self):
        yield self

    async def next(self) -> None:  # the next look at once: the looks' rows stand for the steps
        await asyncio.sleep(0)


async def _f_ext_through_a_queue_of_one(looks: list[int], ring: _Ring | None = None) -> list[float]:
    """sample_every_step into a stream of queue_length 1 whose sender takes a message each turn of
    the event loop: the samples' times (s) the sender took, in order."""
    session = await connect(parts(replay=True))
    stream = Stream(session, F_EXT)
    stream.options["rospy"] = (0, 1)
    stream.configure()
    taken: list[float] = []

    async def sender() -> None:
        while True:
            while stream.queue:
                message, _, _ = stream.queue.popleft()
                stamp = message["header"]["stamp"]
                taken.append(round(stamp["sec"] + stamp["nanosec"] * 1e-9, 3))
            await asyncio.sleep(0)

    ring = ring or _Ring(looks)
    tasks = [asyncio.ensure_future(sample_every_step(ring, stream)), asyncio.ensure_future(sender())]
    await until(lambda: not ring.looks and not stream.queue and ring.step, "every look read and taken")
    for _ in range(10):
        await asyncio.sleep(0)
    for task in tasks:
        task.cancel()
    stream.stop()
    return taken


def test_f_ext_samples_read_together_reach_a_queue_of_one_in_order():
    """A look that keeps up (one or two samples) loses none to the queue of one (rospy's
    queue_size=1): each waits for the sender to take the one before."""
    taken = run(_f_ext_through_a_queue_of_one([1, 2, 2, 1, 2]))
    assert taken == [round(0.001 * k, 3) for k in range(1, 9)]


def test_an_f_ext_stream_needs_the_loop_to_step_each_ms_not_to_publish_each_snapshot():
    """Every step's F_ext comes from the ring: the stream keeps the loop at 1 ms steps, and the
    snapshot is published only as often as its own readers need (app/runtime/loop.py)."""
    ring = _Ring([1, 1])
    run(_f_ext_through_a_queue_of_one(ring.looks, ring))
    assert ring.needed == [(0.001, False)]


def test_f_ext_samples_of_a_look_that_is_behind_give_the_newest_not_a_backlog():
    """A look that is behind (the sender gets HANDOFF_TURNS turns in all over its samples) ends with
    its newest sample: a slow client is not sent old samples in order."""
    taken = run(_f_ext_through_a_queue_of_one([40]))
    assert taken[-1] == 0.04
    assert len(taken) <= HANDOFF_TURNS + 2  # the turns' samples, the first and the newest
