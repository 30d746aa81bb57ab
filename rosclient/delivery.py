"""The client's message-delivery policy: which message a subscriber's callback gets, and when.

The mechanisms call these rules: the connection (rosclient/connection.py: what a subscription asks
the lab to hold, the interpreter's switch interval), rospy's Subscriber (site/rospy/topics.py: its
reader hands messages to a `Mailbox`, its callback thread takes them), rclpy's Subscription
(site/rclpy/subscription.py: a `bounded_queue` of the QoS depth) and the program's end
(rosclient/process.py: `Callbacks`). The rules, each pinned by tests/rosclient/test_delivery.py:

- a queue of `queue_size` (None, 0 or less: unbounded) in the program; full, its oldest is dropped
  (rospy's queue, rclpy's KEEP_LAST);
- the lab holds at most `queue_size` messages for a rospy subscriber while it or the program is
  behind (`lab_queue_length`); an rclpy subscription asks for every message (LAB_QUEUE);
- rospy's reader waits, at most HANDOFF_S, for the callback thread to take the queued message
  before it puts the next in its place (queue full), if the callback keeps up (`Workload`); one
  that did not take it in time is not waited for again until it takes one; one that does not keep
  up is never waited for: it gets the newest message;
- the interpreter passes between threads every READER_SWITCH_S (`reader_turns`);
- once the program ends no new callback starts, and one running gets CALLBACK_GRACE_S to finish.

docs/ros-programs-client.md#how-callbacks-run tells it to students.
"""

from __future__ import annotations

import sys
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Generic, TypeVar

T = TypeVar("T")

# rosbridge's queue_length a program's subscription asks of the lab unless it says: 0, every message
# sent on (the lab bounds what it holds for a reader that is behind; /image_raw at a few images). An
# rclpy subscription's QoS depth is its own queue, on the program's side, as a DDS reader's history
# is; a rospy subscriber asks for its queue_size (`lab_queue_length`)
LAB_QUEUE = 0
READER_SWITCH_S = 0.0005  # s, the program's interpreter switch interval (`reader_turns`)
# s the connection's reader waits, at most, for the callback thread to take the queued message before
# it puts the next in its place (queue full): rospy reads and calls back on one thread, so nothing
# arrives while a callback runs; here the reader and the callback are two threads sharing the
# interpreter, and on this 2-core machine the callback thread's turn can take tens of milliseconds
# (its CPU slows down for 0.1-0.3 s every 1.5 s or so: docs/ros-programs-client.md#measured)
HANDOFF_S = 0.05
# A callback that keeps up (busy less than KEEPUP_SHARE of the last KEEPUP_WINDOW_S s) is handed a
# burst in order: the lab's messages come in bursts where a ROS publisher's are paced (the lab's
# server and this program's reader catching up after this machine's pauses,
# docs/ros-programs-client.md#measured). One busy longer does not keep up and is not waited for:
# its queue drops the oldest, as rospy's does, and the reader reads on, so it gets the newest, never
# a growing backlog of stale ones. The window is long enough that a burst does not decide (it makes
# up for the pause before it).
KEEPUP_WINDOW_S = 1.0
KEEPUP_SHARE = 0.9
CALLBACK_GRACE_S = 2.0  # s a callback in progress gets to finish when the program ends


def queue_bound(size: int | None) -> int | None:
    """A queue's bound from a queue_size or QoS depth: None, 0 or less is unbounded (None)."""
    return size if size is not None and size > 0 else None


def bounded_queue(size: int | None) -> deque:
    """A queue of `size` messages (`queue_bound`): full, an append drops the oldest."""
    return deque(maxlen=queue_bound(size))


def lab_queue_length(queue_size: int | None) -> int:
    """What a rospy subscriber asks the lab to hold for it while the lab or the program is behind: its
    queue_size, as a ROS publisher's queue drops for a subscriber that cannot keep up (a program
    behind on a 1 kHz topic gets the newest message, not a backlog of stale ones: with every message
    sent, the rospy lifting node's carry failed in a fresh clone's suite, and in 4 of 5 runs beside
    two busy loops; 3 of 3 passed with this); no queue_size: every message (LAB_QUEUE)."""
    return queue_bound(queue_size) or LAB_QUEUE


def reader_turns() -> None:
    """The interpreter passes between threads every READER_SWITCH_S (or less, if it already did)
    while one wants it: the connection's readers (websockets' and ours) then get their turn while a
    callback computes, and read the lab's messages as they come; at Python's 5 ms, a callback that
    computes 2 ms per message of a 1 kHz topic left them behind, seconds of stale messages in the
    socket."""
    sys.setswitchinterval(min(sys.getswitchinterval(), READER_SWITCH_S))


class Workload:
    """A callback thread's time at work, by `clock` (s): whether it keeps up. Not thread-safe: its
    owner holds a lock around it."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self.clock = clock
        self._callbacks: deque[tuple[float, float]] = deque()  # (end, s) of each of the last KEEPUP_WINDOW_S
        self._busy_s = 0.0  # their sum
        self._running_since: float | None = None  # the start of the one running
        self._first_started: float | None = None

    def started(self) -> float:
        """A callback starts now (its start returned, for `ended`)."""
        now = self.clock()
        self._running_since = now
        if self._first_started is None:
            self._first_started = now
        return now

    def ended(self, started: float) -> None:
        """The callback that started at `started` ended now."""
        now = self.clock()
        self._callbacks.append((now, now - started))
        self._busy_s += now - started
        self._running_since = None
        self._forget_before(now - KEEPUP_WINDOW_S)

    def keeps_up(self) -> bool:
        """At work less than KEEPUP_SHARE of the last KEEPUP_WINDOW_S (of the time since its first
        callback, before that); never, before its first callback."""
        if self._first_started is None:
            return False
        now = self.clock()
        self._forget_before(now - KEEPUP_WINDOW_S)
        busy = self._busy_s + (now - self._running_since if self._running_since is not None else 0.0)
        return busy < KEEPUP_SHARE * min(KEEPUP_WINDOW_S, now - self._first_started)

    def _forget_before(self, moment: float) -> None:
        while self._callbacks and self._callbacks[0][0] < moment:
            self._busy_s -= self._callbacks.popleft()[1]


class Mailbox(Generic[T]):
    """A rospy subscriber's queue between the connection's reader (`offer`) and its callback thread
    (`take`, then `done` when the callback ended): `queue_size` messages (`queue_bound`), full: the
    oldest dropped, after the hand-off wait when the callback keeps up (the module's rules)."""

    def __init__(
        self, queue_size: int | None, clock: Callable[[], float] = time.monotonic, handoff_s: float | None = None
    ) -> None:
        self.queue: deque[T] = bounded_queue(queue_size)
        self.handoff_s = HANDOFF_S if handoff_s is None else handoff_s
        self.workload = Workload(clock)
        self.received = 0  # messages offered (the queue may have dropped some since)
        self.handing_off = False  # the reader is waiting for the taker to take the queued message
        self._ready = threading.Condition()
        self._closed = False
        self._taker_idle = False  # the callback thread is waiting for a message (or woken, not yet run)
        self._taker_late = False  # it did not take one within handoff_s: not waited for again until it does

    def _full(self) -> bool:
        return self.queue.maxlen is not None and len(self.queue) >= self.queue.maxlen

    def offer(self, item: T) -> None:
        """A message from the reader: queued, the oldest dropped when the queue is full and the taker
        does not take one first (it is waited for, at most handoff_s, only when it keeps up: it is
        waiting for its turn, or running a callback and will be done soon)."""
        with self._ready:
            self.received += 1
            if self._full() and not self._taker_late and (self._taker_idle or self.workload.keeps_up()):
                self.handing_off = True
                if not self._ready.wait_for(lambda: not self._full(), self.handoff_s):
                    self._taker_late = True  # not waited for again until it takes one
                self.handing_off = False
            self.queue.append(item)
            self._ready.notify_all()

    def take(self, at_work: bool = True) -> tuple[T, float] | None:
        """The oldest message and the callback's start (for `done`), once there is one; None once
        closed. `at_work`: a callback runs on it (it counts for keeping up)."""
        with self._ready:
            self._taker_idle = True
            while not self.queue and not self._closed:
                self._ready.wait()
            if self._closed:
                return None
            item = self.queue.popleft()
            self._taker_idle = self._taker_late = False
            self._ready.notify_all()  # a reader waiting for this take goes on
            return item, self.workload.started() if at_work else self.workload.clock()

    def done(self, started: float) -> None:
        """The callback on the message taken at `started` ended."""
        with self._ready:
            self.workload.ended(started)

    def close(self) -> None:
        """No more takes: a taker waiting gets None."""
        with self._ready:
            self._closed = True
            self._ready.notify_all()


class Callbacks:
    """The callbacks running now on the program's threads (rospy's subscribers, timers, services):
    the program's end waits for them, CALLBACK_GRACE_S at most (a thread left inside native code,
    e.g. OpenCV, when the interpreter exits aborts the process)."""

    def __init__(self) -> None:
        self._running = 0
        self._done = threading.Condition()

    def __enter__(self) -> None:
        with self._done:
            self._running += 1

    def __exit__(self, *exc: object) -> None:
        with self._done:
            self._running -= 1
            self._done.notify_all()

    def running(self) -> int:
        with self._done:
            return self._running

    def wait(self, timeout: float = CALLBACK_GRACE_S) -> bool:
        """Until none runs (True) or `timeout` s passed (False)."""
        with self._done:
            return self._done.wait_for(lambda: self._running == 0, timeout)
