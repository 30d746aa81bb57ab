"""subscribe / unsubscribe: throttle_rate (ms) and queue_length; one stream per topic and client, at
the lowest throttle and longest queue of its subscriptions, as rosbridge does. The lab's topics
are sampled from its snapshot (newest first; what a slow client cannot take is dropped, the
simulation never waits); node topics are relayed from their publishers; /rosout carries each
log line as it comes, as rcl_interfaces/Log or (asked for) rosgraph_msgs/Log. The lab's extension
`connection_header: true` (rospy's subscribers) asks that a node topic's messages come with their
publisher's connection header (capabilities/advertise.py); a lab topic's never do.

A subscription of a node topic gets first what its latched publishers kept (rosbridge_suite's ROS 2
subscriber takes TRANSIENT_LOCAL when its publishers are; ROS 1's latched topics), each message
addressed to it by its id; the lab's extension `durability: "volatile"` (an rclpy subscription
of that durability) asks for none of it, as a DDS volatile reader gets none."""

from __future__ import annotations

import asyncio
from collections.abc import Iterable
from contextlib import ExitStack
from functools import partial
from typing import Any

from sim.messages import F_EXT, Topic, wrench_stamped_at
from sim.sampling import due

from app.ros import rosout
from app.ros.node_services import normalise_type
from app.rosbridge.capabilities.advertise import Advertise
from app.rosbridge.capabilities.capability import Capability, Op, Ops
from app.rosbridge.internal.node_frames import TF_TOPICS, TF_TYPES
from app.rosbridge.internal.streams import Stream
from app.rosbridge.ports import Id, SessionLike
from app.rosbridge.protocol import BadFrame, field, name_field
from app.runtime.camera_process import IMAGE, image_message

MAX_QUEUE = 1000  # queue_length cap
MAX_TOPICS = 32  # topics one client may be subscribed to at once
IMAGE_QUEUE = 2  # /image_raw: at most this many images wait for a slow client (the newest)


class Subscribe(Capability):
    """The topics this client subscribes to: one stream each (app/rosbridge/internal/streams.py)."""

    DETAILS = "subscribing"

    def __init__(self, session: SessionLike) -> None:
        super().__init__(session)
        self.streams: dict[str, Stream] = {}  # topic -> its stream

    def names(self) -> list[str]:
        return list(self.streams)

    async def subscribe(self, message: dict, id_: Id) -> None:
        bridge = self.bridge
        topic = name_field(message, "topic")
        type_name = field(message, "type", str, None)
        throttle = field(message, "throttle_rate", int, 0)
        queue_length = field(message, "queue_length", int, 0)
        if throttle < 0 or queue_length < 0:
            raise BadFrame("subscribe: 'throttle_rate' and 'queue_length' must be >= 0")
        wants_header = field(message, "connection_header", bool, False)  # the lab's extension (rospy's)
        volatile = durability_field(message) == "volatile"
        compression = field(message, "compression", str, "none")
        if compression not in ("none", ""):
            raise BadFrame(f"subscribe: compression '{compression[:20]}' is not supported (only none)")
        known = bridge.topics.types().get(topic)
        if known is None and not type_name:
            raise BadFrame(f"subscribe: topic {topic} does not exist (give its 'type' to wait for a publisher)")
        if topic == rosout.TOPIC and type_name and normalise_type(type_name) in rosout.TYPES:
            known = normalise_type(type_name)  # a ROS 1 client reads /rosout as rosgraph_msgs/Log
        if topic in TF_TOPICS and normalise_type(type_name) in TF_TYPES:
            known = normalise_type(type_name)  # a ROS 1 tf client reads /tf as tf/tfMessage (node_frames.py)
        if known is not None and type_name and normalise_type(type_name) != known:
            raise BadFrame(f"subscribe: topic {topic} is of type {known}, not {type_name}")
        stream = self.streams.get(topic)
        if stream is None and len(self.streams) >= MAX_TOPICS:
            raise BadFrame(f"subscribe: at most {MAX_TOPICS} topics per client (unsubscribe from one first)")
        if stream is None and topic != rosout.TOPIC:
            bridge.topics.room_for_topic(topic, "subscribe")
        if stream is not None:
            stream.connection_header |= wants_header
            stream.options[id_] = (throttle, min(queue_length, MAX_QUEUE))
            stream.configure()
            self._latched(stream, id_, volatile)
            return
        stream = self.streams[topic] = self._open(topic, id_, throttle, queue_length)
        stream.connection_header = wants_header
        lab, lab_topic = bridge.lab, bridge.topics.lab_topic(topic)
        if topic == rosout.TOPIC:  # every line from now on, in the subscriber's type
            loop, kind = asyncio.get_running_loop(), known or rosout.TYPE

            def relay(line: rosout.LogLine) -> None:
                loop.call_soon_threadsafe(stream.offer, line.message(kind))

            stream.on_stop.append(lab.rosout.listen(relay))
        elif topic == F_EXT and lab_topic is not None:  # every step's sample, not only the newest when we look
            stream.tasks.append(asyncio.ensure_future(sample_every_step(lab, stream)))
        elif topic == IMAGE and lab_topic is not None:  # the camera's images, rendered while somebody subscribes
            stream.tasks.append(asyncio.ensure_future(sample_images(lab, stream)))
        elif lab_topic is not None:
            min_period_s = bridge.topics.min_period(topic)
            stream.tasks.append(
                asyncio.ensure_future(sample(lab, stream, lab_topic, min_period_s, bridge.topics.latched))
            )
        else:
            bridge.topics.subscribe(topic, normalise_type(type_name or known or ""), stream)
            self._latched(stream, id_, volatile)

    def _latched(self, stream: Stream, id_: Id, volatile: bool) -> None:
        """What the node topic's latched publishers kept (capabilities/advertise.py), for subscription
        `id_` (none for a volatile one; a lab topic has no entry: its latched ones are sampled)."""
        for publisher in [] if volatile else self.bridge.topics.publishers(stream.topic):
            for message, header in publisher.capability(Advertise).kept(stream.topic):
                stream.offer(message, header, id_)

    def _open(self, topic: str, id_: Id, throttle: int, queue_length: int) -> Stream:
        """A new stream of `topic` for this client, sending from now on."""
        stream = Stream(self.session, topic, paced=not self.bridge.topics.sampled(topic))
        if topic == IMAGE:
            stream.max_queue = IMAGE_QUEUE  # the camera's or a played bag's
        stream.options[id_] = (throttle, min(queue_length, MAX_QUEUE))
        stream.configure()
        stream.tasks.append(asyncio.ensure_future(stream.deliver()))
        return stream

    async def unsubscribe(self, message: dict, id_: Id) -> None:
        topic = name_field(message, "topic")
        stream = self.streams.get(topic)
        if stream is None:
            await self.session.report("warning", f"unsubscribe: not subscribed to {topic}", id_)
            return
        if id_ is not None and id_ in stream.options and len(stream.options) > 1:
            del stream.options[id_]
            stream.configure()
            return
        del self.streams[topic]
        self._close(stream)

    def _close(self, stream: Stream) -> None:
        stream.stop()
        self.bridge.topics.unsubscribe(stream.topic, stream)

    def finish(self) -> None:
        for stream in self.streams.values():
            self._close(stream)
        self.streams.clear()


def durability_field(message: dict) -> str:
    """The lab's extension `durability` (an rclpy subscription's): transient_local (the default, as
    rosbridge_suite matches its publishers) or volatile."""
    durability = field(message, "durability", str, "transient_local")
    if durability not in ("transient_local", "volatile"):
        raise BadFrame(f"subscribe: 'durability' must be transient_local or volatile, not {durability[:20]!r}")
    return durability


async def sample(
    lab: Any, stream: Stream, topic: Topic, min_period_s: float = 0.0, latched: Iterable[str] = ()
) -> None:
    """A lab topic from the snapshot: at most one message per throttle_rate of simulation time
    (rosbridge's minimum gap; the topic's own min_period_s when longer), paced by the wall clock;
    behind, it skips, it never queues up. A latched topic is sent again only when it changed."""
    loop = asyncio.get_running_loop()
    wake, last, sent = loop.time(), None, None
    with Need(lab) as need:
        while True:
            snapshot = lab.snapshot()
            period = max(stream.period, min_period_s)
            need.every(period)
            if due(last, snapshot.time, period):
                last = snapshot.time
                shared = stream.session.bridge.topics.shared  # built once for every client's stream of the topic
                key = (shared.trial(snapshot.time), snapshot.time)
                message = shared.built(topic.name, key, partial(topic.build, snapshot))
                if topic.name not in latched or message != sent:
                    stream.offer(message)
                sent = message
                wake = max(wake + period, loop.time())
            else:  # early (the wall clock ran ahead of the simulation): wait for the rest
                wake = loop.time() + period - (snapshot.time - last)
            await asyncio.sleep(wake - loop.time())


POLL_S = 0.001  # s, the control period: a stream this eager reads each sample as its step writes it
# event-loop turns a full queue's sender gets, in all, over one look's samples before the next sample
# replaces its newest: enough for the one or two samples of a look that keeps up, never enough to
# send a client that is behind old samples in order (a lifting node fed those went unstable)
HANDOFF_TURNS = 4


async def sample_every_step(lab: Any, stream: Stream) -> None:
    """F_ext from the ring of every step's sample (app/runtime/sample_ring.py): each sample at least
    throttle_rate of simulation time after the last one sent (0: every step), in order, however
    late this thread got the CPU; what a slow client cannot take is dropped by its queue. At 1 kHz
    the ring wakes this look as each step writes its sample, so samples go out one at a time, as
    the steps came; at a lower rate it looks on a schedule. A sample read with others in one look
    (this thread was late) waits for the stream's sender to take the one before (HANDOFF_TURNS for
    the whole look): a short queue (queue_length 1, rospy's queue_size=1) loses samples to a client
    that is slow, not to the look's batching, and a client that is behind gets the newest."""
    _, seen, _ = lab.wrench_samples(0)  # from now on
    last = None
    loop = asyncio.get_running_loop()
    look = loop.time()
    with Need(lab, snapshots=False) as need, lab.new_wrench_samples() as new_samples:
        while True:
            period = stream.period
            need.every(period)
            rows, seen, _ = lab.wrench_samples(seen)
            turns = HANDOFF_TURNS
            for index, row in enumerate(rows, seen - len(rows)):  # index: the sample's number in the ring
                if due(last, row[0], period):
                    last = row[0]
                    time_s = float(row[0])
                    while turns and stream.queue.maxlen is not None and len(stream.queue) >= stream.queue.maxlen:
                        turns -= 1
                        await asyncio.sleep(0)  # the sender's turn: it takes the one before
                    shared = stream.session.bridge.topics.shared  # each step's sample built once for every client
                    stream.offer(shared.built(F_EXT, index, partial(wrench_stamped_at, time_s, row[1:])))
            if period <= POLL_S:  # every step's: the next as it is written
                await new_samples.next()
            else:  # no oftener than it may send (its share of the lab's rate), on a schedule
                look = max(look + period, loop.time() - period)
                await asyncio.sleep(look - loop.time())


async def sample_images(lab: Any, stream: Stream) -> None:
    """/image_raw: each new image of the camera (app/runtime/camera_process.py), at least
    throttle_rate of simulation time after the last one sent; the camera renders while this runs."""
    camera = lab.camera
    seen, last = camera.number, None
    with ExitStack() as held:
        period = None
        while True:
            if stream.period != period:  # the camera renders as often as its most eager subscriber
                period = stream.period
                held.close()
                held.enter_context(camera.wants(period))
            if camera.number != seen:
                frame = camera.latest()
                if frame is not None and due(last, frame.time, period):
                    seen, last = frame.number, frame.time
                    stream.offer(image_message(frame))
            await asyncio.sleep(IMAGE_POLL_S)


IMAGE_POLL_S = 0.005  # s between two looks for a new image


class Need:
    """How often this subscription needs a step and (`snapshots`) a fresh snapshot (Lab.needs),
    kept to its current period."""

    def __init__(self, lab: Any, snapshots: bool = True) -> None:
        self.period: float | None = None
        self.lab, self._held, self.snapshots = lab, ExitStack(), snapshots

    def every(self, period: float) -> None:
        if period != self.period:
            self._held.close()
            self._held = ExitStack()
            self._held.enter_context(self.lab.needs(max(period, 0.001), self.snapshots))
            self.period = period

    def __enter__(self) -> Need:
        return self

    def __exit__(self, *exc: Any) -> None:
        self._held.close()


OPS: Ops = {
    "subscribe": Op(Subscribe, Subscribe.subscribe),
    "unsubscribe": Op(Subscribe, Subscribe.unsubscribe),
}
