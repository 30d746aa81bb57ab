"""rclpy.event_handler: a publisher's or a subscription's events, as rclpy's
`PublisherEventCallbacks` / `SubscriptionEventCallbacks` take them.

Over rosbridge one event can be told: **matched** — the count of subscriptions matched to a
publisher (or of publishers to a subscription) changed (rclpy/_graph.py counts them). A watcher
thread looks at the counts of every publisher and subscription that has a matched callback at once
when this program makes or destroys one and every POLL_S otherwise (other clients come and go
through the lab's rosapi); a change makes the handler ready, and the executor runs its callback with
a QoSPublisherMatchedInfo / QoSSubscriptionMatchedInfo, once per change seen. The lab's graph has no
deadlines, liveliness, lost messages or incompatible QoS: those callbacks are taken and never called.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rosclient import process
from rclpy import _graph
from rclpy import context as _context
from rclpy._entity import Call
from rclpy.callback_groups import CallbackGroup
from rclpy.waitable import Waitable

class UnsupportedEventTypeError(Exception):
    """An event type the middleware does not support (rclpy raises it when a callback is set)."""


POLL_S = 0.25  # s between two looks at the graph's counts when nothing in this program changed


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


class PublisherEventCallbacks:
    def __init__(self, *, deadline: Any = None, liveliness: Any = None, incompatible_qos: Any = None,
                 matched: Callable[[QoSPublisherMatchedInfo], Any] | None = None, incompatible_type: Any = None,
                 use_default_callbacks: bool = True) -> None:
        self.deadline, self.liveliness, self.incompatible_qos = deadline, liveliness, incompatible_qos
        self.matched, self.incompatible_type = matched, incompatible_type
        self.use_default_callbacks = use_default_callbacks


class SubscriptionEventCallbacks:
    def __init__(self, *, deadline: Any = None, incompatible_qos: Any = None, liveliness: Any = None,
                 message_lost: Any = None, matched: Callable[[QoSSubscriptionMatchedInfo], Any] | None = None,
                 incompatible_type: Any = None, use_default_callbacks: bool = True) -> None:
        self.deadline, self.incompatible_qos, self.liveliness = deadline, incompatible_qos, liveliness
        self.message_lost, self.matched, self.incompatible_type = message_lost, matched, incompatible_type
        self.use_default_callbacks = use_default_callbacks


class EventHandler(Waitable):
    """A matched event's handler: ready when the count it watches changed."""

    def __init__(self, callback_group: CallbackGroup, callback: Callable[[Any], Any], count: Callable[[], int],
                 info: type[_MatchedInfo]) -> None:
        super().__init__(callback_group)
        self.callback, self._count, self._info = callback, count, info
        self._current = self._total = 0  # as of the last event
        self._pending: deque[Any] = deque()
        _watch(self)

    def _look(self) -> None:
        """The count now; an event when it changed (the watcher's thread)."""
        current = self._count()
        change = current - self._current
        if change == 0:
            return
        added = max(change, 0)
        info = self._info(self._total + added, added, current, change)
        with _context.CONDITION:
            self._current, self._total = current, self._total + added
            self._pending.append(info)
        _context.wake()

    def _is_ready(self) -> bool:
        return bool(self._pending)

    def _take(self) -> Call | None:
        with _context.CONDITION:
            if not self._pending:
                return None
            info = self._pending.popleft()
        callback = self.callback
        return lambda: callback(info)

    def destroy(self) -> None:
        with _LOCK:
            if self in _HANDLERS:
                _HANDLERS.remove(self)


def publisher_handlers(callbacks: Any, group: CallbackGroup, topic: str) -> list[EventHandler]:
    """The event handlers a publisher's PublisherEventCallbacks ask for (matched: the one the lab can tell)."""
    return _matched(callbacks, group, lambda: _graph.count_subscriptions(topic), QoSPublisherMatchedInfo)


def subscription_handlers(callbacks: Any, group: CallbackGroup, topic: str) -> list[EventHandler]:
    """The event handlers a subscription's SubscriptionEventCallbacks ask for."""
    return _matched(callbacks, group, lambda: _graph.count_publishers(topic), QoSSubscriptionMatchedInfo)


def _matched(callbacks: Any, group: CallbackGroup, count: Callable[[], int], info: type[_MatchedInfo]) -> list[EventHandler]:
    matched = getattr(callbacks, "matched", None)
    return [] if matched is None else [EventHandler(group, matched, count, info)]


# --- the watcher ---------------------------------------------------------------------------------
_LOCK = threading.Lock()
_HANDLERS: list[EventHandler] = []
_THREAD: list[threading.Thread] = []


def _watch(handler: EventHandler) -> None:
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
