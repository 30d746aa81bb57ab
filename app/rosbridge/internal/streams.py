"""A topic as one client receives it (rosbridge_suite's subscribers' queue)."""

from __future__ import annotations

import asyncio
import math
from collections import deque
from collections.abc import Callable

from app.rosbridge.ports import Id, SessionLike, TopicsLike


class Stream:
    """A topic as one client receives it: newest messages in a bounded queue, sent in order.

    A lab topic is paced where it is sampled (capabilities/subscribe.py, simulation time). A node
    topic is paced here, on the sending side, as rosbridge's queue does: every message is queued
    (full: the oldest is dropped) and the sender waits out the throttle period (wall clock) before
    the next, so the newest message of a burst is always sent, at most one throttle period late."""

    def __init__(self, session: SessionLike, topic: str, paced: bool = False) -> None:
        self.session, self.topic, self.paced = session, topic, paced  # session: has `async send(dict)`
        self.options: dict[Id, tuple[int, int]] = {}  # subscription id -> (throttle_rate ms, queue_length)
        # (message, its connection header, the subscription it is addressed to: a latched one's history)
        self.queue: deque[tuple[dict, dict | None, Id]] = deque(maxlen=1)
        self.connection_header = False  # asked for: a node topic's messages carry their publisher's header
        self.ready = asyncio.Event()
        self.last_sent = -math.inf  # s, loop time of the last message sent (paced streams)
        self.tasks: list[asyncio.Task] = []
        self.on_stop: list[Callable[[], None]] = []  # e.g. leave the lab's /rosout listeners
        self.max_queue: int | None = None  # a cap on the queue whatever was asked (images: a few MB each)
        # the topics it shares the lab's outgoing rate with (TopicManager.fair_period)
        self.topics: TopicsLike | None = getattr(getattr(session, "bridge", None), "topics", None)
        self.stopped = False
        if self.topics is not None:
            self.topics.stream_opened()

    @property
    def period(self) -> float:
        """s between messages: the lowest throttle_rate of the subscriptions (at most 1 kHz), and at
        least this stream's fair share of the lab's outgoing rate (TopicManager.fair_period)."""
        fair = self.topics.fair_period() if self.topics is not None else 0.0
        return max(min(t for t, _ in self.options.values()) / 1000.0, 0.001, fair)

    PASS_THROUGH = 1000  # messages kept for a throttle_rate 0, queue_length 0 subscription

    def configure(self) -> None:
        """The queue's length: the longest asked for; none asked and no throttle is rosbridge_suite's
        pass-through handler (every message sent, here bounded by PASS_THROUGH), else the newest only."""
        length = max(q for _, q in self.options.values())
        if length == 0:
            length = self.PASS_THROUGH if min(t for t, _ in self.options.values()) == 0 else 1
        if self.max_queue is not None:
            length = min(length, self.max_queue)
        if length != self.queue.maxlen:
            self.queue = deque(self.queue, maxlen=length)

    def offer(self, message: dict, header: dict | None = None, to: Id = None) -> None:
        """Queue a message for the sender (full: the oldest is dropped); never refused. `header`:
        its publisher's connection header (a node topic's), sent if this stream asked for it. `to`:
        the id of the one subscription it is for (a latched publisher's history, which a client's
        other subscriptions of the topic had already: the frame carries that id)."""
        self.queue.append((message, header if self.connection_header else None, to))
        self.ready.set()

    async def deliver(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            await self.ready.wait()
            self.ready.clear()
            while self.queue:
                if self.paced:
                    wait = self.last_sent + self.period - loop.time()
                    if wait > 0:  # newer messages may come meanwhile: the queue is read after the wait
                        await asyncio.sleep(wait)
                        continue
                    self.last_sent = loop.time()
                message, header, to = self.queue.popleft()
                if to is not None:  # addressed: its own frame, never shared
                    frame = {"op": "publish", "id": to, "topic": self.topic, "msg": message}
                    if header is not None:
                        frame["connection_header"] = header
                    await self.session.send(frame)
                elif self.topics is not None:  # encoded once for every client's stream of the topic
                    await self.session.send_text(self.topics.shared.frame(self.topic, message, header))
                else:
                    frame = {"op": "publish", "topic": self.topic, "msg": message}
                    if header is not None:
                        frame["connection_header"] = header
                    await self.session.send(frame)
                await asyncio.sleep(0)  # one message, then the others' turn: HTTP waits behind no queue

    def stop(self) -> None:
        if self.topics is not None and not self.stopped:
            self.topics.stream_closed()
        self.stopped = True
        for task in self.tasks:
            task.cancel()
        for stop in self.on_stop:
            stop()
        self.on_stop.clear()
