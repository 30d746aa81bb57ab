"""rospy.topics: Publisher and Subscriber over the lab's rosbridge endpoint.

A publisher fills a message's `header.seq` (its count of messages, from 1) as rospy does. A
subscriber's `queue_size` is its own queue, in this process (and the most the lab holds for it
while the lab or the program is behind): the callback, on the subscriber's own thread, takes the
messages in order; a full queue drops its oldest, so a message is lost in the program only to a
callback that does not keep up, as in rospy (HANDOFF_S, KEEPUP_SHARE). Both may be made before init_node, as rospy allows; a message is
published only after it.

Connection headers as TCPROS has them (rospy's impl/tcpros_pubsub.py): a Publisher's `headers`
go with its advertise (the lab's extension, docs/reference/rosbridge.md), and every message a
Subscriber hands its callback has `_connection_header`, the publisher's header: `topic`, `type`,
`latching`, `message_definition`, `md5sum` (genmsg's, interfaces/md5sum.py), `callerid` (the
publishing node, as the lab relays it) and the publisher's own fields, which may replace those. A
message the program builds has none, as in rospy.
"""

from __future__ import annotations

import threading
import time
import traceback
from collections import deque
from collections.abc import Callable
from typing import Any

from interfaces.md5sum import md5sum
from interfaces.messages import Message
from interfaces.packages import full_text
from rosclient import process
from rospy import core, names
from rospy.exceptions import ROSException, ROSSerializationException


def _check_class(data_class: Any, what: str) -> None:
    if not (isinstance(data_class, type) and issubclass(data_class, Message)):
        raise ValueError(f"{what}: data_class must be a message class (e.g. std_msgs.msg.String), got {data_class!r}")


def _has_header(data_class: type[Message]) -> bool:
    """genpy's _has_header: the message's first field is a std_msgs/Header named header."""
    fields = data_class._fields
    return bool(fields) and fields[0].name == "header" and fields[0].base == "std_msgs/Header"


class SubscribeListener:
    """rospy's hook for a publisher's peers: `peer_subscribe` when a node subscribes to the topic,
    `peer_unsubscribe` when one leaves (with how many are left). The lab cannot address one
    subscriber, so `peer_publish` publishes to all of them, as `topic_publish` does."""

    def peer_subscribe(
        self, topic_name: str, topic_publish: Callable[..., Any], peer_publish: Callable[..., Any]
    ) -> None:
        pass

    def peer_unsubscribe(self, topic_name: str, num_peers: int) -> None:
        pass


class Topic:
    """What Publisher and Subscriber share: the resolved name and the message class."""

    def __init__(self, name: str, data_class: Any, what: str) -> None:
        _check_class(data_class, what)
        self.name = names.resolve_name(name)
        self.resolved_name = self.name
        self.data_class, self.type = data_class, data_class._type

    def get_num_connections(self) -> int:
        """How many nodes subscribe to the topic now (the lab's rosapi)."""
        return len(_subscribers(self.name))


def _subscribers(topic: str) -> list[str]:
    answer = process.connection().call_service("/rosapi/subscribers", {"topic": topic}, timeout=10)
    return list(answer.get("subscribers", []))


class Publisher(Topic):
    def __init__(
        self,
        name: str,
        data_class: Any,
        subscriber_listener: SubscribeListener | None = None,
        tcp_nodelay: bool = False,
        latch: bool = False,
        headers: Any = None,
        queue_size: int | None = None,
    ) -> None:
        super().__init__(name, data_class, "rospy.Publisher")
        self.seq = 0
        self._lock = threading.Lock()
        self._has_header = _has_header(data_class)
        self._registered = True
        # TCPROSPub's header fields the subscribers cannot know: latching, and the program's own
        # (headers' keys and values written as text, as rospy's handshake writes `key=value`)
        extra = {"latching": "1"} if latch else {}
        extra.update({str(k): str(v) for k, v in (headers or {}).items()})
        process.add_publisher(self.name, self.type, self.data_class, extra, latch=1 if latch else 0)
        if subscriber_listener is not None:
            threading.Thread(
                target=self._watch_peers, args=(subscriber_listener,), daemon=True, name=f"rospy-peers{self.name}"
            ).start()

    def _watch_peers(self, listener: SubscribeListener) -> None:
        """The listener's calls as subscribers come and go (the lab's subscriber list, looked at every POLL s)."""
        peers = 0
        while not process.shutdown_event.wait(process.POLL):
            try:
                now = len(_subscribers(self.name))
            except Exception:  # noqa: BLE001 - the lab is going away: the program ends anyway
                return
            for _ in range(now - peers):
                listener.peer_subscribe(self.name, self.publish, self.publish)
            if now < peers:
                listener.peer_unsubscribe(self.name, now)
            peers = now

    def publish(self, *args: Any, **kwds: Any) -> None:
        if not core.is_initialized():
            raise ROSException("ROS node has not been initialized yet. Please call init_node() first")
        if core.topics_closed() or not process.connected():
            raise ROSException("publish() to a closed topic")
        if len(args) == 1 and not kwds and isinstance(args[0], Message):
            msg = args[0]
            if not isinstance(msg, self.data_class):
                raise ROSSerializationException(f"expected [{self.type}] but got [{msg._type}]")
        else:
            try:
                msg = self.data_class(*args, **kwds)
            except TypeError as exc:
                raise ROSSerializationException(str(exc)) from None
        with self._lock:
            self.seq += 1
            if self._has_header:
                msg.header.seq = self.seq
            try:
                data = msg.to_json()
            except (TypeError, ValueError, AttributeError) as exc:
                raise ROSSerializationException(str(exc)) from None
            process.publish(self.name, self.type, data)

    def unregister(self) -> None:
        """This publisher is done: the topic is unadvertised when no other publisher of it is left
        in the program (rospy shares one connection per topic between its publishers)."""
        with self._lock:
            registered, self._registered = self._registered, False
        if registered:
            process.remove_publisher(self.name)


# s the connection's reader waits, at most, for the callback thread to take the queued message before
# it puts the next in its place (queue full): rospy reads and calls back on one thread, so nothing
# arrives while a callback runs; here the reader and the callback are two threads sharing the
# interpreter, and on this 2-core machine the callback thread's turn can take tens of milliseconds
# (its CPU slows down for 0.1-0.3 s every 1.5 s or so: docs/ros-programs-client.md#measured)
HANDOFF_S = 0.05
# A callback that keeps up (busy less than KEEPUP_SHARE of the last KEEPUP_WINDOW_S s) is handed a
# burst in order: the lab's messages come in bursts where a ROS publisher's are paced (the lab's
# server and this program's reader catching up after this machine's pauses,
# docs/ros-programs-client.md#measured). One busy longer
# does not keep up and is not waited for: its queue drops the oldest, as rospy's does, and the reader
# reads on, so it gets the newest, never a growing backlog of stale ones. The window is long enough
# that a burst does not decide (it makes up for the pause before it).
KEEPUP_WINDOW_S = 1.0
KEEPUP_SHARE = 0.9


class Subscriber(Topic):
    """Messages into a queue of `queue_size` (None: unbounded; full: the oldest dropped), handed to
    the callback on this subscriber's own thread."""

    def __init__(
        self,
        name: str,
        data_class: Any,
        callback: Callable[..., Any] | None = None,
        callback_args: Any = None,
        queue_size: int | None = None,
        buff_size: int = 65536,
        tcp_nodelay: bool = False,
    ) -> None:
        super().__init__(name, data_class, "rospy.Subscriber")
        self.callback, self.callback_args = callback, callback_args
        # (a message, its publisher's connection header as the lab relays it)
        self.queue: deque[tuple[dict[str, Any], dict[str, Any]]] = deque(
            maxlen=queue_size if queue_size and queue_size > 0 else None
        )
        self._header_base: dict[str, str] | None = None  # the fields every publisher's header shares
        self.received = 0
        self._ready = threading.Condition()
        self._closed = False
        self._taker_idle = False  # the callback thread is waiting for a message (or woken, not yet run)
        self._taker_late = False  # it did not take one within HANDOFF_S: not waited for again until it does
        # the callback thread's time at work: (end, s) of each callback of the last KEEPUP_WINDOW_S and
        # their sum, the start of the one running, the start of the first
        self._callbacks: deque[tuple[float, float]] = deque()
        self._busy_s = 0.0
        self._running_since: float | None = None
        self._first_started: float | None = None
        threading.Thread(target=self._deliver, daemon=True, name=f"rospy-sub{self.name}").start()
        # the lab holds at most queue_size messages for this subscriber while it or the program is
        # behind, as a ROS publisher's queue drops for a subscriber that cannot keep up: a program
        # behind on a 1 kHz topic gets the newest message, not a backlog of stale ones (with every
        # message sent, the rospy lifting node's carry failed: in a fresh clone's suite, and in 4 of
        # 5 runs beside two busy loops; 3 of 3 passed with this)
        self._sid = process.connection().subscribe(
            self.name,
            data_class._type,
            self._offer,
            queue_length=queue_size if queue_size and queue_size > 0 else 0,
            connection_header=True,
        )

    def _offer(self, data: dict[str, Any], header: dict[str, Any]) -> None:
        """A message from the connection's reader thread, with what the lab relayed of its publisher."""
        with self._ready:
            self.received += 1
            full = self.queue.maxlen is not None and len(self.queue) >= self.queue.maxlen
            if full and not self._taker_late and self._keeps_up():
                # the callback thread takes the one before first (it is waiting for its turn, or
                # running a callback and will be done soon): bounded. A callback that does not keep
                # up is not waited for: its queue drops the oldest, as rospy's does.
                if not self._ready.wait_for(lambda: len(self.queue) < (self.queue.maxlen or 0), HANDOFF_S):
                    self._taker_late = True  # not waited for again until it takes one
            self.queue.append((data, header))
            self._ready.notify_all()

    def _keeps_up(self) -> bool:
        """The callback thread is waiting for a message, or was at work less than KEEPUP_SHARE of
        the last KEEPUP_WINDOW_S (of the time since its first callback, before that)."""
        if self._taker_idle:
            return True
        if self._first_started is None:
            return False
        now = time.monotonic()
        self._forget_before(now - KEEPUP_WINDOW_S)
        busy = self._busy_s + (now - self._running_since if self._running_since is not None else 0.0)
        return busy < KEEPUP_SHARE * min(KEEPUP_WINDOW_S, now - self._first_started)

    def _forget_before(self, moment: float) -> None:
        """Forget the callbacks that ended before `moment` (with the lock held)."""
        while self._callbacks and self._callbacks[0][0] < moment:
            self._busy_s -= self._callbacks.popleft()[1]

    def _connection_header(self, relayed: dict[str, Any]) -> dict[str, str]:
        """The publisher's header as TCPROSPub writes it: what the type gives, then what the lab
        relayed of the publisher (its `callerid`, `latching` and own fields)."""
        if self._header_base is None:
            self._header_base = {
                "topic": self.name,
                "type": self.type,
                "latching": "0",
                "message_definition": full_text(self.data_class),
                "md5sum": md5sum(self.data_class),
            }
        return {**self._header_base, **{str(k): str(v) for k, v in relayed.items()}}

    def _deliver(self) -> None:
        while True:
            with self._ready:
                self._taker_idle = True
                while not self.queue and not self._closed:
                    self._ready.wait()
                if self._closed:
                    return
                data, header = self.queue.popleft()
                self._taker_idle = self._taker_late = False
                self._ready.notify_all()  # a reader waiting for this take goes on
                started = time.monotonic()
                if self.callback is not None:  # at work from now (_keeps_up)
                    self._running_since = started
                    if self._first_started is None:
                        self._first_started = started
            if self.callback is None:
                continue
            if process.shutdown_event.is_set():  # the program is ending: no new callback
                return
            try:
                with process.running_callback():
                    msg = self.data_class.from_json(data)
                    msg._connection_header = self._connection_header(header)
                    if self.callback_args is None:
                        self.callback(msg)
                    else:
                        self.callback(msg, self.callback_args)
            except Exception:  # noqa: BLE001 - rospy logs a failing callback, the subscriber goes on
                core.logerr("bad callback: %s\n%s", self.callback, traceback.format_exc())
            with self._ready:
                ended = time.monotonic()
                self._callbacks.append((ended, ended - started))
                self._busy_s += ended - started
                self._running_since = None
                self._forget_before(ended - KEEPUP_WINDOW_S)

    def unregister(self) -> None:
        with self._ready:
            self._closed = True
            self._ready.notify()
        process.connection().unsubscribe(self.name, self._sid, self._offer)
