"""rospy.topics: Publisher and Subscriber over the lab's rosbridge endpoint.

A publisher fills a message's `header.seq` (its count of messages, from 1) as rospy does. A
subscriber's `queue_size` is its own queue, in this process (and the most the lab holds for it
while the lab or the program is behind): the callback, on the subscriber's own thread, takes the
messages in order; a full queue drops its oldest, so a message is lost in the program only to a
callback that does not keep up, as in rospy (the rules: rosclient/delivery.py). Both may be made
before init_node, as rospy allows; a message is published only after it.

Connection headers as TCPROS has them (rospy's impl/tcpros_pubsub.py): a Publisher's `headers`
go with its advertise (the lab's extension, docs/reference/rosbridge.md), and every message a
Subscriber hands its callback has `_connection_header`, the publisher's header: `topic`, `type`,
`latching`, `message_definition`, `md5sum` (genmsg's, interfaces/md5sum.py), `callerid` (the
publishing node, as the lab relays it) and the publisher's own fields, which may replace those. A
message the program builds has none, as in rospy.
"""

from __future__ import annotations

import threading
import traceback
from collections.abc import Callable
from typing import Any

from interfaces.md5sum import md5sum
from interfaces.messages import Message
from interfaces.packages import full_text
from rosclient import delivery, process
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


class Subscriber(Topic):
    """Messages into a queue of `queue_size` (None: unbounded; full: the oldest dropped), handed to
    the callback on this subscriber's own thread (the rules: rosclient/delivery.py's Mailbox)."""

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
        self.mailbox: delivery.Mailbox[tuple[dict[str, Any], dict[str, Any]]] = delivery.Mailbox(queue_size)
        self.queue = self.mailbox.queue
        self._header_base: dict[str, str] | None = None  # the fields every publisher's header shares
        threading.Thread(target=self._deliver, daemon=True, name=f"rospy-sub{self.name}").start()
        self._sid = process.connection().subscribe(
            self.name,
            data_class._type,
            self._offer,
            queue_length=delivery.lab_queue_length(queue_size),
            connection_header=True,
        )

    @property
    def received(self) -> int:
        """Messages that reached the subscriber (its queue may have dropped some since)."""
        return self.mailbox.received

    def _offer(self, data: dict[str, Any], header: dict[str, Any]) -> None:
        """A message from the connection's reader thread, with what the lab relayed of its publisher."""
        self.mailbox.offer((data, header))

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
            taken = self.mailbox.take(at_work=self.callback is not None)
            if taken is None:
                return
            (data, header), started = taken
            if self.callback is None:
                continue
            if process.shutdown_event.is_set():  # the program is ending: no new callback
                return
            try:
                with process.callbacks:
                    msg = self.data_class.from_json(data)
                    msg._connection_header = self._connection_header(header)
                    if self.callback_args is None:
                        self.callback(msg)
                    else:
                        self.callback(msg, self.callback_args)
            except Exception:  # noqa: BLE001 - rospy logs a failing callback, the subscriber goes on
                core.logerr("bad callback: %s\n%s", self.callback, traceback.format_exc())
            self.mailbox.done(started)

    def unregister(self) -> None:
        self.mailbox.close()
        process.connection().unsubscribe(self.name, self._sid, self._offer)
