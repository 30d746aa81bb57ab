"""rclpy.event_handler: a publisher's or a subscription's events, as rclpy's
`PublisherEventCallbacks` / `SubscriptionEventCallbacks` take them, with rmw's payloads.

- **matched**: the count of subscriptions matched to a publisher (or of publishers to a subscription)
  changed: the compatible ones, this program's and the other programs' (rclpy/_endpoints.py
  `matched`). A watcher thread looks at the counts of every publisher and subscription that has a
  matched callback at once when this program makes or destroys one or the lab tells of another
  program's, and every POLL_S otherwise (clients that tell no QoS come and go through rosapi).
- **deadline**: a publisher that published nothing for its QoS deadline (QoSOfferedDeadlineMissedInfo),
  a subscription that received nothing for it (QoSRequestedDeadlineMissedInfo): one miss a period,
  counted from the first message.
- **liveliness**: a MANUAL_BY_TOPIC publisher that neither published nor called `assert_liveliness`
  for its lease (QoSLivelinessLostInfo); a subscription's count of alive and not alive compatible
  publishers changed (QoSLivelinessChangedInfo): a publisher of this program is alive from when it
  is made, an AUTOMATIC one until its lease after it was destroyed, a MANUAL_BY_TOPIC one its lease
  after its last assertion; another program's is alive while the lab lists it (its assertions are
  not relayed: a MANUAL_BY_TOPIC one of another program is never seen not alive, only gone).
- **incompatible QoS**: a publisher and a subscription of a topic whose QoS rmw does not match
  (rclpy/qos.py `incompatible_policies`), of this program or another one the lab told of: each side
  of this program gets a QoS*IncompatibleQoSInfo with the last policy found, once per peer
  discovered; without a callback of its own, rclpy's default one warns.

The deadline and liveliness events are the executor's to time (`_due`). Lost messages and
incompatible types are never told: those callbacks are taken and never called.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from enum import IntEnum
from typing import Any

from rosclient import process
from rclpy import _endpoints, _graph
from rclpy import context as _context
from rclpy._entity import Call
from rclpy.callback_groups import CallbackGroup
from rclpy.logging import get_logger
from rclpy.qos import LivelinessPolicy, qos_policy_name_from_kind
from rclpy.waitable import Waitable

class UnsupportedEventTypeError(Exception):
    """An event type the middleware does not support (rclpy raises it when a callback is set)."""


POLL_S = 0.25  # s between two looks at the graph's counts when nothing in this program changed


class rmw_qos_policy_kind_t(IntEnum):  # noqa: N801 - rclpy's name for it
    """The kind of policy an incompatible-QoS event names, as rclpy's binding prints it."""

    RMW_QOS_POLICY_INVALID = 1 << 0
    RMW_QOS_POLICY_DURABILITY = 1 << 1
    RMW_QOS_POLICY_DEADLINE = 1 << 2
    RMW_QOS_POLICY_LIVELINESS = 1 << 3
    RMW_QOS_POLICY_RELIABILITY = 1 << 4
    RMW_QOS_POLICY_HISTORY = 1 << 5
    RMW_QOS_POLICY_LIFESPAN = 1 << 6
    RMW_QOS_POLICY_DEPTH = 1 << 7
    RMW_QOS_POLICY_LIVELINESS_LEASE_DURATION = 1 << 8
    RMW_QOS_POLICY_AVOID_ROS_NAMESPACE_CONVENTIONS = 1 << 9

    def __str__(self) -> str:
        return f"{type(self).__name__}.{self.name}"

    def __format__(self, format_spec: str) -> str:
        return format(str(self), format_spec)


@dataclass
class _MatchedInfo:
    """rmw's matched status: the peers matched in all (ever) and now, and each one's change since
    the last event."""

    total_count: int = 0
    total_count_change: int = 0
    current_count: int = 0
    current_count_change: int = 0


class QoSPublisherMatchedInfo(_MatchedInfo):
    """A publisher's matched status: its subscriptions."""


class QoSSubscriptionMatchedInfo(_MatchedInfo):
    """A subscription's matched status: its publishers."""


@dataclass
class _CountInfo:
    """rmw's count of an event: in all, and since the last event."""

    total_count: int = 0
    total_count_change: int = 0


class QoSRequestedDeadlineMissedInfo(_CountInfo):
    """A subscription's deadlines missed."""


class QoSOfferedDeadlineMissedInfo(_CountInfo):
    """A publisher's deadlines missed."""


class QoSLivelinessLostInfo(_CountInfo):
    """A publisher's losses of liveliness."""


class QoSMessageLostInfo(_CountInfo):
    """A subscription's lost messages (never told over rosbridge)."""


@dataclass
class QoSRequestedIncompatibleQoSInfo:
    """A subscription's (or, as QoSOfferedIncompatibleQoSInfo, a publisher's) incompatible peers."""

    total_count: int = 0
    total_count_change: int = 0
    last_policy_kind: rmw_qos_policy_kind_t = rmw_qos_policy_kind_t.RMW_QOS_POLICY_INVALID


QoSOfferedIncompatibleQoSInfo = QoSRequestedIncompatibleQoSInfo


@dataclass
class QoSLivelinessChangedInfo:
    """A subscription's publishers alive and not alive, and each count's change since the last event."""

    alive_count: int = 0
    not_alive_count: int = 0
    alive_count_change: int = 0
    not_alive_count_change: int = 0


@dataclass
class IncompatibleTypeInfo(_CountInfo):
    """Peers of another type (never told over rosbridge)."""


class PublisherEventCallbacks:
    def __init__(self, *, deadline: Callable[[QoSOfferedDeadlineMissedInfo], Any] | None = None,
                 liveliness: Callable[[QoSLivelinessLostInfo], Any] | None = None,
                 incompatible_qos: Callable[[QoSRequestedIncompatibleQoSInfo], Any] | None = None,
                 matched: Callable[[QoSPublisherMatchedInfo], Any] | None = None, incompatible_type: Any = None,
                 use_default_callbacks: bool = True) -> None:
        self.deadline, self.liveliness, self.incompatible_qos = deadline, liveliness, incompatible_qos
        self.matched, self.incompatible_type = matched, incompatible_type
        self.use_default_callbacks = use_default_callbacks


class SubscriptionEventCallbacks:
    def __init__(self, *, deadline: Callable[[QoSRequestedDeadlineMissedInfo], Any] | None = None,
                 incompatible_qos: Callable[[QoSRequestedIncompatibleQoSInfo], Any] | None = None,
                 liveliness: Callable[[QoSLivelinessChangedInfo], Any] | None = None,
                 message_lost: Any = None, matched: Callable[[QoSSubscriptionMatchedInfo], Any] | None = None,
                 incompatible_type: Any = None, use_default_callbacks: bool = True) -> None:
        self.deadline, self.incompatible_qos, self.liveliness = deadline, incompatible_qos, liveliness
        self.message_lost, self.matched, self.incompatible_type = message_lost, matched, incompatible_type
        self.use_default_callbacks = use_default_callbacks


class EventHandler(Waitable):
    """One event's handler: ready when it holds an event's payload; `_update` (with the context's
    condition held) adds the payloads the time brought, `_due` says when the next may come."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any]) -> None:
        super().__init__(callback_group)
        self.callback = callback
        self._pending: deque[Any] = deque()

    def push(self, info: Any) -> None:
        with _context.CONDITION:
            self._pending.append(info)
        _context.wake()

    def _update(self, now: float) -> None:
        """The events that are due by `now` (timed handlers)."""

    def _is_ready(self) -> bool:
        self._update(time.monotonic())
        return bool(self._pending)

    def _take(self) -> Call | None:
        with _context.CONDITION:
            if not self._pending:
                return None
            info = self._pending.popleft()
        callback = self.callback
        return lambda: callback(info)

    def destroy(self) -> None:
        pass


class MatchedHandler(EventHandler):
    """A matched event's handler: the watcher thread looks at the count it watches."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any], count: Callable[[], int],
                 info: type[_MatchedInfo]) -> None:
        super().__init__(callback_group, callback)
        self._count, self._info = count, info
        self._current = self._total = 0  # as of the last event
        _watch(self)

    def _look(self) -> None:
        """The count now; an event when it changed (the watcher's thread)."""
        current = self._count()
        change = current - self._current
        if change == 0:
            return
        added = max(change, 0)
        self._current, self._total = current, self._total + added
        self.push(self._info(self._total, added, current, change))

    def destroy(self) -> None:
        with _LOCK:
            if self in _HANDLERS:
                _HANDLERS.remove(self)


class DeadlineHandler(EventHandler):
    """Deadlines missed: one a period with no message, from the endpoint's last message."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any], endpoint: _endpoints.Endpoint,
                 info: type[_CountInfo]) -> None:
        super().__init__(callback_group, callback)
        self._endpoint, self._info = endpoint, info
        self._period_s = endpoint.qos.deadline.nanoseconds / 1e9
        self._missed_at = 0.0  # the end of the last period counted as missed
        self._total = 0

    def _due(self) -> float | None:
        last = self._endpoint.last_message
        if last is None or self._endpoint.destroyed is not None:
            return None
        return max(last, self._missed_at) + self._period_s

    def _update(self, now: float) -> None:
        due, missed = self._due(), 0
        while due is not None and due <= now:
            missed += 1
            self._missed_at = due
            due = self._due()
        if missed:
            self._total += missed
            self._pending.append(self._info(self._total, missed))


class LivelinessLostHandler(EventHandler):
    """A MANUAL_BY_TOPIC publisher's losses of liveliness: its lease passed with no assertion."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any],
                 endpoint: _endpoints.Endpoint) -> None:
        super().__init__(callback_group, callback)
        self._endpoint = endpoint
        self._lost_since: float | None = None  # the assertion whose lease ran out
        self._total = 0

    def _due(self) -> float | None:
        endpoint = self._endpoint
        if endpoint.destroyed is not None or endpoint.last_assertion == self._lost_since:
            return None
        return endpoint.alive_until()

    def _update(self, now: float) -> None:
        due = self._due()
        if due is not None and due <= now:
            self._lost_since = self._endpoint.last_assertion
            self._total += 1
            self._pending.append(QoSLivelinessLostInfo(self._total, 1))


class LivelinessChangedHandler(EventHandler):
    """A subscription's compatible publishers alive and not alive (this program's and the others'
    the lab told of, rclpy/_endpoints.py). As rmw_fastrtps reports DDS's liveliness changes: every
    change since the last event is in the next one, the counts as they are and the changes summed;
    a publisher that lapsed and asserted itself again between two looks made two changes (a lapse
    and a revival: `Endpoint.revivals`), summed to none but still an event."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any],
                 endpoint: _endpoints.Endpoint) -> None:
        super().__init__(callback_group, callback)
        self._endpoint = endpoint
        self._alive = self._not_alive = 0
        self._revivals: dict[int, int] = {}  # id(publisher): its revivals at the last look

    def _publishers(self) -> list[_endpoints.Endpoint]:
        topic = self._endpoint.topic
        every = _endpoints.publishers(topic) + _endpoints.remotes(True, topic)
        return [p for p in every if _endpoints.compatible(p, self._endpoint)]

    def _due(self) -> float | None:
        if self._endpoint.destroyed is not None:
            return None
        now = time.monotonic()
        ends = [end for end in (p.alive_until() for p in self._publishers()) if end > now]
        return min(ends, default=None)

    def _update(self, now: float) -> None:
        if self._endpoint.destroyed is not None:
            return
        alive = not_alive = 0
        revived = False  # a lapse and a revival since the last look (no count moved for it)
        revivals: dict[int, int] = {}
        for publisher in self._publishers():
            if publisher.alive_until() > now:
                alive += 1
            elif publisher.destroyed is None:  # a MANUAL_BY_TOPIC one past its lease
                not_alive += 1
            else:
                continue
            revivals[id(publisher)] = publisher.revivals
            revived = revived or self._revivals.get(id(publisher), publisher.revivals) != publisher.revivals
        self._revivals = revivals
        if revived or (alive, not_alive) != (self._alive, self._not_alive):
            self._pending.append(QoSLivelinessChangedInfo(alive, not_alive, alive - self._alive,
                                                          not_alive - self._not_alive))
            self._alive, self._not_alive = alive, not_alive


class IncompatibleQoSHandler(EventHandler):
    """Incompatible peers found: told by `found` (rclpy/_endpoints.py's pairs)."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any]) -> None:
        super().__init__(callback_group, callback)
        self._total = 0

    def found(self, kind: int) -> None:
        self._total += 1
        self.push(QoSRequestedIncompatibleQoSInfo(self._total, 1, rmw_qos_policy_kind_t(kind)))


def _default_incompatible(logger_name: str, topic: str, publisher: bool) -> Callable[[Any], None]:
    """rclpy's default incompatible-QoS callback: a warning in the entity's logger."""
    logger = get_logger(logger_name)
    if publisher:
        text = (f"New subscription discovered on topic '{topic}', requesting incompatible QoS. "
                f"No messages will be sent to it. Last incompatible policy: ")
    else:
        text = (f"New publisher discovered on topic '{topic}', offering incompatible QoS. "
                f"No messages will be received from it. Last incompatible policy: ")
    def warn(event: Any) -> None:
        logger.warn(text + qos_policy_name_from_kind(event.last_policy_kind))

    return warn


def publisher_handlers(callbacks: Any, group: CallbackGroup, topic: str, endpoint: _endpoints.Endpoint,
                       logger_name: str) -> list[EventHandler]:
    """The event handlers a publisher's PublisherEventCallbacks ask for."""
    handlers: list[EventHandler] = []
    if callbacks.deadline and endpoint.qos.deadline.nanoseconds > 0:
        handlers.append(DeadlineHandler(group, callbacks.deadline, endpoint, QoSOfferedDeadlineMissedInfo))
    if callbacks.liveliness and endpoint.qos.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC and endpoint.lease_s() > 0:
        handlers.append(LivelinessLostHandler(group, callbacks.liveliness, endpoint))
    handlers += _incompatible(callbacks, group, topic, logger_name, True)
    if callbacks.matched is not None:
        handlers.append(MatchedHandler(group, callbacks.matched, lambda: _endpoints.matched(endpoint),
                                       QoSPublisherMatchedInfo))
    return handlers


def subscription_handlers(callbacks: Any, group: CallbackGroup, topic: str, endpoint: _endpoints.Endpoint,
                          logger_name: str) -> list[EventHandler]:
    """The event handlers a subscription's SubscriptionEventCallbacks ask for."""
    handlers: list[EventHandler] = []
    if callbacks.deadline and endpoint.qos.deadline.nanoseconds > 0:
        handlers.append(DeadlineHandler(group, callbacks.deadline, endpoint, QoSRequestedDeadlineMissedInfo))
    handlers += _incompatible(callbacks, group, topic, logger_name, False)
    if callbacks.liveliness:
        handlers.append(LivelinessChangedHandler(group, callbacks.liveliness, endpoint))
    if callbacks.matched is not None:
        handlers.append(MatchedHandler(group, callbacks.matched, lambda: _endpoints.matched(endpoint),
                                       QoSSubscriptionMatchedInfo))
    return handlers


def _incompatible(callbacks: Any, group: CallbackGroup, topic: str, logger_name: str,
                  publisher: bool) -> list[EventHandler]:
    callback = callbacks.incompatible_qos
    if callback is None and callbacks.use_default_callbacks:
        callback = _default_incompatible(logger_name, topic, publisher)
    return [] if callback is None else [IncompatibleQoSHandler(group, callback)]


def tell_incompatible(pairs: _endpoints.Pairs) -> None:
    """A new endpoint's incompatible pairs (rclpy/_endpoints.py `add`, `told`): an event for each side
    of this program (another program's side has no handlers here: its program tells its own)."""
    for publisher, subscription, kind in pairs:
        for endpoint in (publisher, subscription):
            for handler in endpoint.handlers:
                if isinstance(handler, IncompatibleQoSHandler):
                    handler.found(kind)


def _discovered(pairs: _endpoints.Pairs) -> None:
    """The lab told of other programs' endpoints: their incompatible pairs, and every wait looks again
    (a subscription's liveliness counts them)."""
    tell_incompatible(pairs)
    _context.wake()


_endpoints.discovered[:] = [_discovered]


# --- the watcher ---------------------------------------------------------------------------------
_LOCK = threading.Lock()
_HANDLERS: list[MatchedHandler] = []
_THREAD: list[threading.Thread] = []


def _watch(handler: MatchedHandler) -> None:
    with _LOCK:
        _HANDLERS.append(handler)
        if not _THREAD:
            _THREAD.append(threading.Thread(target=_watcher, name="rclpy-matched-events", daemon=True))
            _THREAD[0].start()
    _graph.CHANGED.set()


def _watcher() -> None:
    while not process.shutdown_event.is_set():
        _graph.CHANGED.wait(POLL_S)
        _graph.CHANGED.clear()
        with _LOCK:
            handlers = list(_HANDLERS)
        for handler in handlers:
            try:
                handler._look()
            except Exception:  # noqa: BLE001 - the lab is going away: the program ends anyway
                return
