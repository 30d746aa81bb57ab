"""rclpy.subscription.Subscription: the messages of a topic wait in the subscription's queue of the
QoS depth (full: the oldest goes, as KEEP_LAST drops it); each take is one message, so an executor's
wait round runs the callback once per subscription (rclpy/executors.py)."""

from __future__ import annotations

import json
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from rosclient import delivery, process
from rosclient.connection import framed, message_of, sender_of
from interfaces.messages import Message
from rclpy import _endpoints, _graph, context
from rclpy._entity import Call, Entity
from rclpy.callback_groups import CallbackGroup
from rclpy.publisher import type_name
from rclpy.qos import DurabilityPolicy, QoSProfile, profile

if TYPE_CHECKING:
    from rclpy.node import Node


class Subscription(Entity):
    def __init__(self, node: Node, msg_type: type, topic: str, callback: Callable[..., Any], qos: QoSProfile | int,
                 callback_group: CallbackGroup, raw: bool = False) -> None:
        if not (isinstance(msg_type, type) and issubclass(msg_type, Message)):
            raise TypeError(f"create_subscription: msg_type must be a message class, got {msg_type!r}")
        self.node, self.msg_type, self.callback, self.raw = node, msg_type, callback, raw
        self.callback_group = callback_group
        callback_group.add_entity(self)
        self.qos_profile = profile(qos)
        self.topic_name = node.resolve_topic_name(topic)
        self._endpoint = _endpoints.Endpoint(self.topic_name, self.qos_profile, False, node.get_fully_qualified_name())
        self._incompatible = _endpoints.add(self._endpoint)  # told once its handlers are made (node.py)
        self._muted: tuple[int, set[str]] = (-1, set())  # (the endpoints' generation, the programs it does not hear)
        depth = self.qos_profile.queue_length
        self._queue: deque[bytes | dict[str, Any]] = delivery.bounded_queue(depth)  # frames, decoded when taken
        self.received = 0  # messages that reached the program (the queue may have dropped some since)
        self._sid = process.connection().subscribe(
            self.topic_name,
            type_name(msg_type),
            self._offer,
            connection_header=True,
            undecoded=True,
            volatile=self.qos_profile.durability != DurabilityPolicy.TRANSIENT_LOCAL,
        )  # every message (delivery.LAB_QUEUE): the QoS depth is this subscription's own queue; a
        # TRANSIENT_LOCAL one gets first what the latched publishers kept (as many as its depth keeps);
        # each with its publisher's connection header (its program: `_offer`)
        self._destroyed = False
        self.event_handlers: list[Any] = []  # rclpy/event_handler.py
        _graph.add_subscription(self.topic_name)

    def _offer(self, data: bytes | dict[str, Any]) -> None:
        """A message from the lab (the connection's reader thread): its frame, decoded only if taken.
        Not one of a program every publisher of the topic of which offers an incompatible QoS (its
        connection header's `callerid`, read only while some program is: rclpy/_endpoints.py `muted`)."""
        if self._muted[0] != _endpoints.generation[0]:
            self._muted = (_endpoints.generation[0], _endpoints.muted(self._endpoint))
        if self._muted[1]:
            data = framed(data)  # decoded once: its header now, its message when taken
            if sender_of(data) in self._muted[1]:
                return
        self._endpoint.message()
        with context.CONDITION:
            self.received += 1
            self._queue.append(data)
        context.wake()

    def _is_ready(self) -> bool:
        return bool(self._queue)

    def _take(self) -> Call | None:
        with context.CONDITION:
            if not self._queue:
                return None
            frame = self._queue.popleft()
        data = message_of(frame)
        if data is None:  # not JSON: nothing a callback could take (the lab sends none)
            return None
        # raw: the message as it travelled (rosbridge's JSON, UTF-8), where rclpy gives its CDR bytes
        msg = json.dumps(data).encode() if self.raw else self.msg_type.from_json(data)
        callback = self.callback
        return lambda: callback(msg)

    @property
    def topic(self) -> str:
        return self.topic_name

    def get_publisher_count(self) -> int:
        """rmw's count of the publishers matched to it: its topic's compatible ones (rclpy/_endpoints.py)."""
        return _endpoints.matched(self._endpoint)

    def destroy(self) -> None:
        if not self._destroyed:
            self._destroyed = True
            # as it was made, in reverse: the lab's subscription goes before the endpoint told of it,
            # so no other program ever sees this client subscribed and its QoS untold (counted matched)
            process.connection().unsubscribe(self.topic_name, self._sid, self._offer)
            _graph.remove_subscription(self.topic_name)
            _endpoints.remove(self._endpoint)
