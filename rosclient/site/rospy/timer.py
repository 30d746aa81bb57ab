"""rospy.timer: sleep, Rate and Timer on the wall clock; each ends with ROSInterruptException when
the node shuts down meanwhile."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

from rosclient import process
from rospy.exceptions import ROSInterruptException
from rospy.rostime import Duration, Time


def sleep(duration: float | Duration) -> None:
    seconds = duration.to_sec() if isinstance(duration, Duration) else float(duration)
    if process.shutdown_event.wait(max(seconds, 0.0)):
        raise ROSInterruptException("ROS shutdown request")


class Rate:
    """Sleeps to keep a loop at `hz` (a late loop starts the next period now, as rospy does)."""

    def __init__(self, hz: float, reset: bool = False) -> None:
        self.period = 1.0 / hz
        self.last = time.monotonic()

    def remaining(self) -> Duration:
        return Duration(max(self.last + self.period - time.monotonic(), 0.0))

    def sleep(self) -> None:
        now = time.monotonic()
        wait = self.last + self.period - now
        self.last = self.last + self.period if wait > 0 or now - self.last < 2 * self.period else now
        if wait > 0 and process.shutdown_event.wait(wait):
            raise ROSInterruptException("ROS shutdown request")
        if process.shutdown_event.is_set():
            raise ROSInterruptException("ROS shutdown request")


class TimerEvent:
    def __init__(
        self, last_expected: Any, last_real: Any, current_expected: Any, current_real: Any, last_duration: Any
    ) -> None:
        self.last_expected, self.last_real = last_expected, last_real
        self.current_expected, self.current_real = current_expected, current_real
        self.last_duration = last_duration


class Timer(threading.Thread):
    """rospy.Timer(period, callback): callback(TimerEvent) every period on a thread of its own."""

    def __init__(
        self, period: Duration, callback: Callable[[TimerEvent], Any], oneshot: bool = False, reset: bool = False
    ) -> None:
        super().__init__(daemon=True, name="rospy-timer")
        self._period, self._callback, self._oneshot = period, callback, oneshot
        self._stop_event = threading.Event()
        self.start()

    def run(self) -> None:
        last: Time | None = None
        expected = Time.now() + self._period
        while not self._stop_event.wait(max(expected.to_sec() - time.time(), 0.0)):
            if process.shutdown_event.is_set():
                return
            now = Time.now()
            duration = None if last is None else now - last
            with process.callbacks:
                self._callback(TimerEvent(last, last, expected, now, duration))
            last, expected = now, expected + self._period
            if self._oneshot:
                return

    def shutdown(self) -> None:
        self._stop_event.set()
